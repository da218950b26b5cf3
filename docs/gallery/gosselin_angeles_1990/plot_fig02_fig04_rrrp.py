"""
Figs. 2-4: the planar RRRP (slider-crank) and its three kinds of singularity
============================================================================

Gosselin & Angeles 1990, Section III, eqs. (6)-(17): the crank angle θ is the
input, the slide x the output; A = √(1 − r² sin² θ), B = R sin θ (√(1 − r²
sin² θ) ± r cos θ) (eq. 12), r = R/l.

* Fig. 2: the mechanism (R = 2, l = 1, θ = 0.3): regular.
* First kind, B = 0 at θ = 0 or π (eq. 13): crank and coupler aligned, the
  limit of the workspace (not in a figure of the paper).
* Fig. 3, second kind, A = 0 at sin θ = l/R (eq. 14): the two branches of the
  direct problem meet, the output moves with the input locked.
* Fig. 4, third kind, R = l (eq. 15): the branch x = 0 is constant (eq. 17);
  where it crosses the branch x = 2R cos θ (θ = π/2) both A and B vanish.

The catalogue's ``slider-crank`` (default, ``fig3c_dead_centre``,
``fig3b_actuator``, ``fig3a_self_intersection``, ``eq17_constant_branch``);
A and B are the paper's own eq. (12)
(:func:`classify.gosselin_angeles_examples.slider_crank.eq12_relation`),
compared with the Park & Kim kinds by :func:`classify.comparison.compare`.
"""

# %%
from matplotlib.figure import Figure

from classify.comparison import compare
from classify.figures.drawing import draw_mechanism
from classify.gosselin_angeles_examples.slider_crank import eq12_relation, slider_crank_branch
from mechanisms import catalogue, configuration

entry = catalogue.entry("slider-crank")
stated = {None: ("Fig. 2", "regular"),
          "fig3c_dead_centre": ("eq. 13", "I"),
          "fig3b_actuator": ("Fig. 3", "II"),
          "fig3a_self_intersection": ("Fig. 4", "I, II, III"),
          "eq17_constant_branch": ("eq. 17", "I (x = 0 stays at rest)")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    relation, coordinates = eq12_relation(mechanism, slider_crank_branch(mechanism, point))
    row = compare(mechanism, point[None], labels=[name or "default"], relation=relation,
                  coordinates=coordinates).rows[0]
    found = row.gosselin_angeles.label
    if index < 4:
        draw_mechanism(mechanism, point, report=row.park_kim, axes=figure.add_subplot(2, 2, index + 1),
                       title=f"{where}: G-A kinds {found}")
    values = entry.values(name)
    print(f"{where} ({name or 'default'}: R = {values['crank']:g}, l = {values['coupler']:g}, "
          f"θ = {values['theta']:.6f}): paper: {paper};  found: G-A {found}, "
          f"Park & Kim {', '.join(row.park_kim.kinds) or 'regular'}")
