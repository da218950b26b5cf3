"""
Figs. 6 and 13: the five-bar's actuator singularities, nondegenerate and degenerate
===================================================================================

Park & Kim 1999, Fig. 6 (Section 3, Case 2; eqs. 9-10): the 5R linkage of
Fig. 1 (base 2, links 1) with its base joints actuated, at two actuator
singularities. (a) The two distal links aligned: locked, the linkage is a
structure — a *nondegenerate* actuator singularity. (b) The two elbows on one
point: locked, the middle links turn about it (a self-motion) — a
*degenerate* one. Fig. 13: a five-bar (base √13, links 1, 1, 1, 2) at a
combined actuator and end-effector singularity.

The catalogue's ``five-bar`` at ``fig6a_distal_aligned``,
``fig6b_elbows_coincide`` and ``fig13_combined``, classified by
:func:`classify.classify`, whose second-order test separates the two actuator
cases (:doc:`/second_order`: the Hessian of eq. 10 as printed is G itself and
cannot separate them); red arrows: lost actuator directions, blue: end-effector.
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("five-bar")
stated = {"fig6a_distal_aligned": ("6a", "actuator, nondegenerate"),
          "fig6b_elbows_coincide": ("6b", "actuator, degenerate"),
          "fig13_combined": ("13", "actuator and end-effector")}
figure = Figure(figsize=(13, 4.8), layout="constrained")
for index, (name, (number, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    if report.actuator.singular:
        found += f" ({report.degeneracy})"
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 3, index + 1),
                   title=f"Fig. {number}: {found}")
    print(f"Fig. {number} ({name}): paper: {paper};  found: {found}; "
          f"rank G {report.actuator.rank}/{report.actuator.expected_rank}, "
          f"rank J {report.end_effector.rank}/{report.end_effector.expected_rank}")
