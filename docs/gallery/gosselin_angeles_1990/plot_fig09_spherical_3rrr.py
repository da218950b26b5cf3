"""
Fig. 9: the spherical 3-RRR parallel wrist
==========================================

Gosselin & Angeles 1990, Section VI, eqs. (66)-(70): a spherical parallel
manipulator (Fig. 9), three motors on fixed axes uᵢ, intermediate axes wᵢ,
gripper axes vᵢ, all through one point; A = [(wᵢ × vᵢ)ᵀ] (eq. 68),
B = diag((wᵢ × uᵢ)·vᵢ) (eq. 69).

* First kind (eq. 70): uᵢ, vᵢ, wᵢ coplanar — leg i extended or folded.
* Second kind: the three vectors wᵢ × vᵢ coplanar (eq. 68 singular).
* Designs with a third kind: α₁ = α₂, where uᵢ = vᵢ for all legs is reachable
  (rank B = 0; the first and second kinds meet where moreover
  θ₁ = θ₂ = θ₃ = 0 or π/2); and α₁ = α₂ = π/2, where every configuration with
  v₁, v₂, v₃ coplanar to u₁, u₂, u₃ lets the gripper turn with the motors
  locked (A singular).

The catalogue's ``spherical-3rrr`` at its default (Fig. 9),
``eq70_leg1_extended``, ``eq68_distal_links_orthogonal``,
``section6_equal_alphas_folded`` (θ = 0.7 and θ = 0) and ``section6_right_alphas_coplanar``, drawn
on the unit sphere (a joint is where its axis meets it); A and B are the
paper's (:func:`classify.gosselin_angeles_examples.spherical_3rrr.spherical_3rrr_relation`).
"""

# %%
from matplotlib.figure import Figure

from classify.comparison import compare
from classify.figures.drawing import draw_mechanism
from classify.gosselin_angeles_examples.spherical_3rrr import spherical_3rrr_relation
from mechanisms import catalogue, configuration

entry = catalogue.entry("spherical-3rrr")
# (configuration, parameters overriding it, where in the paper, what it states)
stated = [(None, {}, "Fig. 9", "regular"),
          ("eq70_leg1_extended", {}, "eq. 70", "I"),
          ("eq68_distal_links_orthogonal", {}, "eq. 68", "II"),
          ("section6_equal_alphas_folded", {}, "α1 = α2, θ = 0.7", "I (rank B = 0)"),
          ("section6_equal_alphas_folded", {"theta_folded": 0.0}, "α1 = α2, θ = 0", "I, II, III"),
          ("section6_right_alphas_coplanar", {}, "α1 = α2 = π/2", "II (turns with motors locked)")]
figure = Figure(figsize=(13, 8.5), layout="constrained")
for index, (name, overrides, where, paper) in enumerate(stated):
    mechanism = entry.mechanism(name, **overrides)
    point = configuration(mechanism).point
    relation, coordinates = spherical_3rrr_relation(mechanism)
    row = compare(mechanism, point[None], labels=[name or "default"], relation=relation,
                  coordinates=coordinates).rows[0]
    found = row.gosselin_angeles.label
    draw_mechanism(mechanism, point, report=row.park_kim,
                   axes=figure.add_subplot(2, 3, index + 1, projection="3d"), title=f"{where}: G-A {found}")
    print(f"{where} ({name or 'default'}{overrides or ''}): paper: {paper};  found: G-A {found} "
          f"(rank A {row.gosselin_angeles.rank_A}, rank B {row.gosselin_angeles.rank_B}), "
          f"Park & Kim {', '.join(row.park_kim.kinds) or 'regular'}")
