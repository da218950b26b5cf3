"""
Figs. 3-5: the five-bar's isoconditioning curves
================================================

Chablat, Wenger & Angeles 1998, §3.4, Figs. 3-5: the isoconditioning curves
of the direct-kinematics matrix A (κ(A) = 1/``|tan((θ₃ − θ₄)/2)|``, eq. 9) of the
five-bar with L₀ = 6, L₁ = 8, L₂ = 5 — in the Cartesian space (Fig. 3), in
the joint space (Fig. 4), and per working mode in the Cartesian space
(Fig. 5), where they are the coupler curves of the four-bar obtained by
locking the joint at P (θ₃ − θ₄ fixed).

Maps from :mod:`classify.isoconditioning` (:func:`~classify.isoconditioning.five_bar_cartesian_map`,
:func:`~classify.isoconditioning.five_bar_joint_map`), drawn by
:func:`classify.figures.conditioning.isoconditioning_figure`: 1/κ(Ā) filled,
its level curves white, the singularity (1/κ = 0) red. Grids are coarse
(60 × 60) to keep the build fast; ``closedchain conditioning five-bar`` draws
finer ones. Fig. 3 overlays the curves of the four modes in one plane
(:func:`classify.isoconditioning.contours`).
"""

# %%
# Fig. 5: one panel per working mode, Cartesian space.
import numpy as np
from matplotlib.figure import Figure

from classify.figures.conditioning import isoconditioning_figure
from classify.isoconditioning import contours, five_bar_cartesian_map, five_bar_joint_map

xs, ys = np.linspace(-8.0, 14.0, 60), np.linspace(-12.0, 12.0, 60)
maps = [five_bar_cartesian_map(xs, ys, signs, mode=label)
        for label, signs in (("++", (1, 1)), ("+-", (1, -1)), ("-+", (-1, 1)), ("--", (-1, -1)))]
fig5 = isoconditioning_figure(maps, "A", units="")
for conditioning_map in maps:
    reachable = conditioning_map.reachable
    inverse = conditioning_map.inverse["A"][reachable]
    print(f"mode {conditioning_map.mode}: {reachable.mean():.0%} of the grid reachable, "
          f"1/κ(Ā) from {inverse.min():.3f} to {inverse.max():.3f}, mean {inverse.mean():.3f}")

# %%
# eq. 9 at the grid points: κ(Ā) against 1/``|tan((θ3 − θ4)/2)|`` (θ3 − θ4 reduced modulo π, see
# the conditioning page), largest relative difference.
angles = maps[0].extra["angles"][maps[0].reachable]
difference = np.angle(np.exp(2j * (angles[:, 2] - angles[:, 3]))) / 2
closed_form = np.abs(np.tan(difference / 2))
print(f"mode ++: max |1/κ(Ā) − |tan((θ3 − θ4)/2)|| = "
      f"{np.max(np.abs(maps[0].inverse['A'][maps[0].reachable] - closed_form)):.2e}")

# %%
# Fig. 3: the four modes' curves overlaid in the Cartesian plane.
fig3 = Figure(figsize=(5.5, 5.5), layout="constrained")
axes = fig3.add_subplot()
colours = ("tab:blue", "tab:orange", "tab:green", "tab:purple")
for conditioning_map, colour in zip(maps, colours):
    for level, lines in contours(conditioning_map, "A", (0.2, 0.4, 0.6, 0.8)).items():
        for line in lines:
            axes.plot(line[:, 0], line[:, 1], color=colour, linewidth=0.8)
    axes.plot([], [], color=colour, label=f"mode {conditioning_map.mode}")
axes.set_aspect("equal")
axes.set_xlabel("x")
axes.set_ylabel("y")
axes.legend(fontsize=7)
axes.set_title("Fig. 3: 1/κ(Ā) = 0.2, 0.4, 0.6, 0.8, Cartesian space")

# %%
# Fig. 4: joint space (θ1, θ2), one panel per assembly mode.
thetas = np.linspace(-np.pi, np.pi, 60)
joint_maps = [five_bar_joint_map(thetas, thetas, assembly) for assembly in (1, -1)]
fig4 = isoconditioning_figure(joint_maps, "A")
for conditioning_map in joint_maps:
    print(f"{conditioning_map.mode}: {conditioning_map.reachable.mean():.0%} of the (θ1, θ2) grid assembles")
