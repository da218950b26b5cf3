"""
Fig. 6: the three-dof hybrid manipulator and its singularities
==============================================================

Chablat, Wenger & Angeles 1998, §4, Fig. 6, eqs. (14)-(30): the five-bar of
Fig. 1 turned about its base line AB by a third actuated revolute (θ₁); A and
B become 3 × 3 (eqs. 22a-b). B is singular (eq. 30) where P lies on the axis
AB (d₁ = 0, eq. 27) or a leg is stretched or folded; A is singular where the
distal links are aligned (eq. 25, as for the five-bar).

The catalogue's ``hybrid`` at ``regular`` (Fig. 6), ``eq30_on_the_axis``,
``eq30_left_leg_stretched`` and ``eq25_distal_aligned``, classified by
:func:`classify.classify` and drawn on 3-D axes.
"""

# %%
from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from mechanisms import catalogue, configuration

entry = catalogue.entry("hybrid")
stated = {"regular": ("Fig. 6", "regular"),
          "eq30_on_the_axis": ("eq. 30, d1 = 0", "B singular (end-effector)"),
          "eq30_left_leg_stretched": ("eq. 30, leg stretched", "B singular (end-effector)"),
          "eq25_distal_aligned": ("eq. 25", "A singular (actuator)")}
figure = Figure(figsize=(10, 9), layout="constrained")
for index, (name, (where, paper)) in enumerate(stated.items()):
    mechanism = entry.mechanism(name)
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    found = report.label
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 2, index + 1, projection="3d"),
                   title=f"{where}: {found}")
    print(f"{where} ({name}): paper: {paper};  found: {found}; rank G {report.actuator.rank}/"
          f"{report.actuator.expected_rank}, rank J {report.end_effector.rank}/{report.end_effector.expected_rank}")
