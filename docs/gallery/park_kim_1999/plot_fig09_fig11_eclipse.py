"""
Figs. 9-11: the Eclipse (SNU mechanism) — actuator and end-effector singularities
=================================================================================

Park & Kim 1999, Figs. 9, 10 and 11c (Section 3, Cases 2-3): the Eclipse, a
6-dof parallel manipulator whose three RPS legs ride on a circular track.
Fig. 9: the mechanism. Fig. 10: a nondegenerate actuator singularity (four
lines of the static Jacobian meet at a point). Fig. 11c: an end-effector
singularity — the platform parallel to the base with one spherical joint
exactly above the centre of the base.

The catalogue's ``eclipse`` at its default pose (Fig. 9), ``fig10_actuator``
and ``fig11c_end_effector``, classified by :func:`classify.classify` and
drawn on 3-D axes.
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("eclipse")
stated = {None: ("9", "the mechanism (regular)"),
          "fig10_actuator": ("10", "actuator (nondegenerate)"),
          "fig11c_end_effector": ("11c", "end-effector")}
figure = Figure(figsize=(13, 4.8), layout="constrained")
for index, (name, (number, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    if report.actuator.singular:
        found += f" ({report.degeneracy})"
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(1, 3, index + 1, projection="3d"),
                   title=f"Fig. {number}: {found}")
    print(f"Fig. {number} ({name or 'default pose'}): paper: {paper};  found: {found}; "
          f"rank G {report.actuator.rank}/{report.actuator.expected_rank}, "
          f"rank J {report.end_effector.rank}/{report.end_effector.expected_rank}")
