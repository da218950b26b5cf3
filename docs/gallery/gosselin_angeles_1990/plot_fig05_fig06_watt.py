"""
Figs. 5-6: Watt's linkage and its singularities
===============================================

Gosselin & Angeles 1990, Section IV, eqs. (18)-(41): Watt's six-bar linkage
(Fig. 5), input the crank angle θ, output the angle φ of link l₃, with
A = D₁D₂ and B = N₁N₂ (eq. 32). First kind (eq. 37): N₁ = 0 (links l₁, l₂
aligned) or N₂ = 0 (l₄ aligned with the line of joints 4, 5). Second kind
(eqs. 38-40): D₁ = 0 — link l₂ aligned with the line of joints 3, 4, the
configuration of Fig. 6 — or D₂ = 0. Third kind (eq. 41): l₁ = l₂ or
l₃ = l₄.

The catalogue's ``watt-six-bar`` at its default (Fig. 5) and at
``eq37_n1_crank_and_coupler_aligned``, ``eq39_d1_coupler_aligned_with_rocker``
(Fig. 6) and ``eq41_joints_4_6_branch_crossing`` (l₃ = l₄, where the
constant branch crosses another). A = D₁D₂ and B = N₁N₂ are the
paper's (:func:`classify.gosselin_angeles_examples.watt.watt_relation`),
compared with the Park & Kim kinds by :func:`classify.comparison.compare`.
"""

# %%
from matplotlib.figure import Figure

from classify.comparison import compare
from classify.figures.drawing import draw_mechanism
from classify.gosselin_angeles_examples.watt import watt_relation
from mechanisms import catalogue, configuration

entry = catalogue.entry("watt-six-bar")
stated = {None: ("Fig. 5", "regular"),
          "eq37_n1_crank_and_coupler_aligned": ("eq. 37, N1 = 0", "I"),
          "eq39_d1_coupler_aligned_with_rocker": ("Fig. 6, eq. 39", "II"),
          "eq41_joints_4_6_branch_crossing": ("eq. 41, l3 = l4", "I, II, III")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    relation, coordinates = watt_relation(mechanism)
    row = compare(mechanism, point[None], labels=[name or "default"], relation=relation,
                  coordinates=coordinates).rows[0]
    report = row.park_kim
    found = row.gosselin_angeles.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 2, index + 1),
                   title=f"{where}: G-A {found}")
    print(f"{where} ({name or 'default'}): paper: {paper};  found: G-A {found}, "
          f"Park & Kim {', '.join(report.kinds) or 'regular'}")
