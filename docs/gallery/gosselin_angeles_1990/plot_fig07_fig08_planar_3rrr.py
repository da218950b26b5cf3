"""
Figs. 7-8: the planar 3-RRR parallel manipulator
================================================

Gosselin & Angeles 1990, Section V, eqs. (42)-(65): a planar parallel
manipulator with three fixed revolute motors (Fig. 7), gripper pose
s = (x, y, φ), B = diag(dᵢ), A = [aᵢ bᵢ cᵢ] (eqs. 44-56).

* First kind (eqs. 57-59): a leg stretched or folded, sin ψᵢ = 0.
* Second kind (eq. 61, Fig. 8): the lines of the three distal links meet at
  one point; (eq. 63): they are parallel.
* Third kind (eq. 64): for l₁ = √3/3, l₂ = l₃ the elbows can all reach the
  centroid.

The catalogue's ``planar-3rrr`` at its default (Fig. 7),
``eq58_leg_stretched``, ``eq61_distal_links_concurrent`` (Fig. 8),
``eq63_distal_links_parallel`` and ``eq64_elbows_at_centroid``; A and B are
the paper's (:func:`classify.gosselin_angeles_examples.planar_3rrr.planar_3rrr_relation`).
"""

# %%
from matplotlib.figure import Figure

from classify.comparison import compare
from classify.figures.drawing import draw_mechanism
from classify.gosselin_angeles_examples.planar_3rrr import planar_3rrr_relation
from mechanisms import catalogue, configuration

entry = catalogue.entry("planar-3rrr")
stated = {None: ("Fig. 7", "regular"),
          "eq58_leg_stretched": ("eq. 58", "I"),
          "eq61_distal_links_concurrent": ("Fig. 8, eq. 61", "II"),
          "eq63_distal_links_parallel": ("eq. 63", "II"),
          "eq64_elbows_at_centroid": ("eq. 64", "I, II, III")}
figure = Figure(figsize=(13, 8.5), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    relation, coordinates = planar_3rrr_relation(mechanism)
    row = compare(mechanism, point[None], labels=[name or "default"], relation=relation,
                  coordinates=coordinates).rows[0]
    found = row.gosselin_angeles.label
    draw_mechanism(mechanism, point, report=row.park_kim, axes=figure.add_subplot(2, 3, index + 1),
                   title=f"{where}: G-A {found}")
    print(f"{where} ({name or 'default'}): paper: {paper};  found: G-A {found} "
          f"(rank A {row.gosselin_angeles.rank_A}, rank B {row.gosselin_angeles.rank_B}), "
          f"Park & Kim {', '.join(row.park_kim.kinds) or 'regular'}")
