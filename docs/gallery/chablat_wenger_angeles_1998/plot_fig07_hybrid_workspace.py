"""
Fig. 7 and §5: the hybrid's workspace and isoconditioning surfaces of revolution
================================================================================

Chablat, Wenger & Angeles 1998, §5.1 and Fig. 7: the isoconditioning loci of
the hybrid are surfaces of revolution, the five-bar's curves turned about the
axis of the first revolute (AB); Fig. 7 shows the boundary of the workspace.

:func:`classify.isoconditioning.hybrid_plane_map` maps 1/κ(Ā) and 1/κ(B) over
the five-bar's plane (distance d₁ from AB, eq. 27, and the position along
AB), per working mode (first figure). The second figure turns the boundary
of the reachable region of the plane about AB — the workspace boundary of
Fig. 7 — with :mod:`matplotlib` (the package has no surface drawing). The
workspace is the union over the four working modes; the plane map is coarse
(60 × 60).
"""

# %%
import numpy as np
from matplotlib.figure import Figure

from classify.figures.conditioning import isoconditioning_figure
from classify.isoconditioning import hybrid_plane_map

distances, alongs = np.linspace(0.0, 14.0, 60), np.linspace(-10.0, 16.0, 60)
maps = [hybrid_plane_map(distances, alongs, signs, mode=label)
        for label, signs in (("++", (1, 1)), ("-+", (-1, 1)))]
sections = isoconditioning_figure(maps, "B")
for conditioning_map in maps:
    values = conditioning_map.inverse["B"][conditioning_map.reachable]
    print(f"mode {conditioning_map.mode}: 1/κ(B) from {values.min():.3f} to {values.max():.3f} in the plane; "
          f"reachable {conditioning_map.reachable.mean():.0%} of the (d1, y) grid")

# %%
# The workspace boundary, turned about AB (the y axis of the plane map), Fig. 7.
every = [hybrid_plane_map(distances, alongs, signs).reachable
         for signs in ((1, 1), (1, -1), (-1, 1), (-1, -1))]
reachable = np.logical_or.reduce(every)
outline = Figure(figsize=(4, 4))
generator = outline.add_subplot().contour(*np.meshgrid(distances, alongs, indexing="ij"),
                                          reachable.astype(float), levels=[0.5])
boundary = max(generator.allsegs[0], key=len)  # the outer curve (d1, y)
turn = np.linspace(0.0, 1.5 * np.pi, 40)  # three quarters, to see inside
surface = Figure(figsize=(6, 6), layout="constrained")
axes = surface.add_subplot(projection="3d")
axes.plot_surface(np.outer(boundary[:, 0], np.cos(turn)), np.outer(boundary[:, 1], np.ones_like(turn)),
                  np.outer(boundary[:, 0], np.sin(turn)), color="tab:blue", alpha=0.5, linewidth=0)
axes.set_xlabel("x")
axes.set_ylabel("y (along AB)")
axes.set_zlabel("z")
axes.set_title("Fig. 7: the boundary of the workspace")
print(f"workspace section (grid boundary): d1 up to {boundary[:, 0].max():.3f} "
      f"(exact: √(13² − 3²) = {np.sqrt(13.0 ** 2 - 3.0 ** 2):.3f}, P above the mid-point of AB), "
      f"along AB from {boundary[:, 1].min():.3f} to {boundary[:, 1].max():.3f} (exact: 6 − 13 = −7 and 13)")
del outline, generator  # only used to find the boundary curve, not a picture of the gallery
