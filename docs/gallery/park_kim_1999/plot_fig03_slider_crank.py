"""
Fig. 3: the slider-crank's four singularities
=============================================

Park & Kim 1999, Fig. 3 (Section 3, Cases 1-3): a slider-crank (RRRP)
(a) at a configuration-space singularity — crank and coupler of equal length,
folded onto each other at θ = π/2 (the two branches of M cross there, Fig. 4);
(b) at an actuator singularity — crank R = 2, coupler l = 1 at sin θ = l/R,
the coupler square to the slide (also Gosselin & Angeles 1990, eq. 14, Fig. 3);
(c) at an end-effector singularity — the dead centre θ = 0, where the slide
cannot move to first order; (d) the dead centre with the slider driven:
combined actuator and end-effector singularity.

Each configuration is the catalogue's ``slider-crank`` at the named
configuration (``fig3a_self_intersection`` ...), classified by
:func:`classify.classify`; the arrows are the lost directions.
"""

# %%
# Build, classify and draw the four configurations.
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("slider-crank")
# what the paper states for each panel
stated = {"fig3a_self_intersection": ("(a)", "cspace"),
          "fig3b_actuator": ("(b)", "actuator"),
          "fig3c_dead_centre": ("(c)", "end_effector"),
          "fig3d_dead_centre": ("(d)", "actuator, end_effector")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (panel, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    axes = figure.add_subplot(2, 2, index + 1)
    draw_mechanism(mechanism, point, report=report, axes=axes, title=f"Fig. 3{panel}: {found}")
    ranks = ", ".join(f"{kind} rank {result.rank}/{result.expected_rank}" for kind, result in
                      (("C-space", report.cspace), ("actuator", report.actuator),
                       ("end-effector", report.end_effector)) if result is not None)
    print(f"Fig. 3{panel} {name} {entry.configurations[name]}")
    print(f"    paper: {paper} singular;  found: {found} ({ranks})")
    if report.actuator.singular:
        print(f"    actuator singularity: {report.degeneracy}")
