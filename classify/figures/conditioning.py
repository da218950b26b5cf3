"""Isoconditioning figures: 1/κ maps with their isoconditioning curves and the singularity curves overlaid.

Chablat, Caro, Wenger & Angeles 2002 Figs. 6-8 (the 3-PRR, positions (x, y)
in mm); Chablat, Wenger & Angeles 1998 Figs. 3-5 (the five-bar, (x, y) or
(θ1, θ2)). Axes are labelled in the papers' symbols; the contours are levels
of 1/κ, the singularity curve is the level 1/κ = 0 (drawn at a small level,
:data:`SINGULAR_LEVEL`) and the boundary of the reachable region.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MATRIX_LABELS", "SINGULAR_LEVEL", "isoconditioning_figure"]

#: the papers' names of the matrices
MATRIX_LABELS = {"A": "Ā", "B": "B", "A-1B": "J̄ = Ā⁻¹B", "B-1A": "K̄ = B⁻¹Ā", "lambda": "λ₁/λₙ (Park & Kim)"}
#: 1/κ level drawn as the singularity curve
SINGULAR_LEVEL = 1e-3


def isoconditioning_figure(maps, matrix, levels=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9), units=""):
    """One panel per working mode: filled 1/κ, isoconditioning curves, singularity curves.

    Parameters
    ----------
    maps : sequence of classify.isoconditioning.ConditioningMap
        Two-dimensional maps.
    matrix : str
        A key of :data:`MATRIX_LABELS`.
    levels : sequence of float
        Levels of 1/κ drawn as curves.
    units : str
        Appended to the axis labels (``"mm"``).

    Returns
    -------
    matplotlib.figure.Figure
        Each axes has the title ``"mode M: 1/κ(X), index G"``, x and y labels in the papers' symbols, the
        contour sets of `levels` (gid ``"isoconditioning"``) and of the singularity (gid ``"singularity"``).
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(4.2 * len(maps), 4.0), layout="constrained")
    axes_list = figure.subplots(1, len(maps), squeeze=False)[0]
    suffix = f" ({units})" if units else ""
    for axes, conditioning_map in zip(axes_list, maps):
        first, second = conditioning_map.axes
        grid_first, grid_second = np.meshgrid(first, second, indexing="ij")
        values = np.ma.masked_invalid(conditioning_map.inverse[matrix])
        image = axes.pcolormesh(grid_first, grid_second, values, vmin=0.0, vmax=1.0, cmap="viridis",
                                shading="auto")
        curves = axes.contour(grid_first, grid_second, values, levels=sorted(levels), colors="white",
                              linewidths=0.7)
        curves.set_gid("isoconditioning")
        axes.clabel(curves, fontsize=6, fmt="%.1f")
        singular = axes.contour(grid_first, grid_second, values, levels=[SINGULAR_LEVEL], colors="red",
                                linewidths=1.2)
        singular.set_gid("singularity")
        axes.set_xlabel(f"{conditioning_map.axis_names[0]}{suffix}")
        axes.set_ylabel(f"{conditioning_map.axis_names[1]}{suffix}")
        axes.set_aspect("equal")
        axes.set_title(f"mode {conditioning_map.mode}: 1/κ({MATRIX_LABELS[matrix]}), "
                       f"index {conditioning_map.global_index(matrix):.3f}", fontsize=8)
    figure.colorbar(image, ax=list(axes_list), label=f"1/κ({MATRIX_LABELS[matrix]})")
    return figure
