"""
Fig. 5: the eight working modes of the 3-PRR
============================================

Chablat, Caro, Wenger & Angeles 2002, §3.5, Fig. 5: B (eq. 4b) is diagonal,
so a working mode is a sign pattern of its diagonal — 2³ = 8 inverse-kinematics
solutions for one pose of the platform. Modes with opposite signs (1-5, 2-6,
3-7, 4-8) are mirror images with the same conditioning.

:func:`classify.working_modes.three_prr_working_modes` lists the modes at
the pose x = y = 0, φ = π/3 (Fig. 4a); each is drawn from the catalogue's
``3-prr`` with ``working_mode`` = 1 … 8 at that pose.
"""

# %%
import math

from matplotlib.figure import Figure

from classify import classify
from classify.figures.drawing import draw_mechanism
from classify.working_modes import three_prr_mode_pairs, three_prr_working_modes
from mechanisms import catalogue, configuration

entry = catalogue.entry("3-prr")
pose = (0.0, 0.0, math.pi / 3)
modes = three_prr_working_modes(pose)
figure = Figure(figsize=(14, 7.5), layout="constrained")
for index, mode in enumerate(modes):
    mechanism = entry.mechanism(working_mode=int(mode.label), x=pose[0], y=pose[1], phi=pose[2])
    point = configuration(mechanism).point
    report = classify(mechanism, point)
    draw_mechanism(mechanism, point, report=report, axes=figure.add_subplot(2, 4, index + 1),
                   title=f"mode {mode.label} {''.join('+' if sign > 0 else '-' for sign in mode.signs)}")
    print(f"mode {mode.label}: signs {mode.signs}, reachable {mode.reachable}, B diagonal "
          f"({', '.join(f'{value:+.2f}' for value in mode.diagonal)}), "
          f"classified {', '.join(report.kinds) or 'regular'}")
print(f"pairs of opposite modes: {three_prr_mode_pairs()} (paper: 1-5, 2-6, 3-7, 4-8)")
