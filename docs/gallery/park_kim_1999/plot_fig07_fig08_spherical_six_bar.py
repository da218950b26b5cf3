"""
Figs. 7 and 8: the spherical six-bar — an actuator singularity removed by moving or adding an actuator
======================================================================================================

Park & Kim 1999, Figs. 7, 8a, 8b (Section 3, Case 2): a spherical 6R loop
(equal twists) with three actuated joints, at an actuator singularity
(Fig. 7). Moving one actuator to another joint, the same configuration is
regular (Fig. 8a); adding a fourth actuator (redundant actuation) removes the
singularity too (Fig. 8b). The linkage is drawn on the unit sphere: each
joint is the point where its axis meets it.

The catalogue's ``spherical-six-bar`` at ``fig7_actuator`` (actuated joints
1, 3, 5), ``fig8a_moved_actuator`` (1, 3, 4) and ``fig8b_added_actuator``
(1, 2, 3, 5): one configuration, three choices of actuators. The paper says
the condition is that "the axes corresponding to the three actuated joints
are coplanar"; at the catalogue's configuration the three *passive* axes are
coplanar (the reading of :mod:`mechanisms.catalogue.spherical_six_bar`; with
the actuated axes coplanar, ``fig7_actuated_axes_coplanar``, the
configuration is regular — printed below).
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("spherical-six-bar")
stated = {"fig7_actuator": ("7", "actuator (nondegenerate)"),
          "fig8a_moved_actuator": ("8a", "regular"),
          "fig8b_added_actuator": ("8b", "regular")}
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
    print(f"Fig. {number} ({name}, actuated {entry.configurations[name]['actuated']}): paper: {paper};  "
          f"found: {found}; rank G {report.actuator.rank}/{report.actuator.expected_rank}")

literal = entry.mechanism("fig7_actuated_axes_coplanar")
report = classify(literal, configuration(literal).point)
print(f"literal reading (actuated joints 2, 4, 6): {', '.join(report.kinds) or 'regular'}")
