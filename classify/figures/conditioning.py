"""Isoconditioning figures: 1/κ maps with their isoconditioning curves and the singularity curves overlaid.

Chablat, Caro, Wenger & Angeles 2002 Figs. 6-8 (the 3-PRR, positions (x, y)
in mm); Chablat, Wenger & Angeles 1998 Figs. 3-5 (the five-bar, (x, y) or
(θ1, θ2)). Axes are labelled in the papers' symbols; the contours are levels
of 1/κ. The singularity curve 1/κ = 0 is the zero level of a signed field,
det of the matrix mapped (:func:`singularity_field`: the five-bar's and the
hybrid's maps, from their angles), where the map carries one: 1/κ ≥ 0 has a
V-shaped zero between grid nodes that no level of it finds (1/κ(Ā) =
‖tan((θ3 − θ4)/2)‖ of the five-bar, 1998 eq. 9). The small level
:data:`SINGULAR_LEVEL` of 1/κ is drawn too, for the zeros 1/κ touches
without a change of sign (towards the boundary of the reachable region) and
for the maps without a signed field (the 3-PRR's best orientation, a general
mechanism's map).
"""

from __future__ import annotations

import numpy as np

from ..text import drawn

__all__ = ["MATRIX_LABELS", "SINGULAR_LEVEL", "singularity_field", "isoconditioning_figure",
           "isoconditioning_surface_figure"]

#: the papers' names of the matrices
MATRIX_LABELS = {"A": "Ā", "B": "B", "A-1B": "J̄ = Ā⁻¹B", "B-1A": "K̄ = B⁻¹Ā", "lambda": "λ₁/λₙ (Park & Kim)"}
#: 1/κ level drawn with the singularity curve (where 1/κ touches 0 without a signed field changing sign)
SINGULAR_LEVEL = 1e-3


def singularity_field(conditioning_map, matrix):
    """A signed field whose zero level is the singularity curve of `matrix` (1/κ = 0), or None.

    det A for Ā, det B for B, det A · det B for J̄, K̄ and λ (singular where either is), from the angles a
    five-bar or hybrid map carries (``extra["angles"]``, :mod:`classify.conditioning_matrices`). Its sign
    changes across the parallel-singularity locus θ3 − θ4 = kπ of the five-bar (1998 eq. 9), where 1/κ ≥ 0
    only touches 0, between grid nodes.

    Parameters
    ----------
    conditioning_map : classify.isoconditioning.ConditioningMap
    matrix : str
        A key of :data:`MATRIX_LABELS`.

    Returns
    -------
    ndarray, shape=grid shape, or None
        NaN where not reachable; None for a map without angles (the 3-PRR's, a general mechanism's).
    """
    from ..conditioning_matrices import five_bar_matrices, hybrid_matrices

    extra = conditioning_map.extra
    if "angles" not in extra or "design" not in extra:
        return None
    design, reachable = extra["design"], conditioning_map.reachable
    angles = np.where(reachable[..., None], extra["angles"], 0.0)
    if tuple(conditioning_map.axis_names[:1]) == ("d1",) or "distance" in extra:   # the hybrid's (θ2..θ5)
        direct, inverse = hybrid_matrices(angles, design["L1"], design["L2"])
    else:
        direct, inverse = five_bar_matrices(angles, design["L1"], design["L2"], design.get("L3"), design.get("L4"))
    determinants = {"A": np.linalg.det(direct), "B": np.linalg.det(inverse)}
    field = determinants.get(matrix, determinants["A"] * determinants["B"])
    return np.where(reachable, field, np.nan)


def isoconditioning_figure(maps, matrix, levels=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9), units="",
                           equal_aspect=True):
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
    equal_aspect : bool
        One unit the same length on both axes (Cartesian maps; not for a grid of mixed joint coordinates).

    Returns
    -------
    matplotlib.figure.Figure
        Each axes has the title ``"mode M: 1/κ(X), index G"``, x and y labels in the papers' symbols, the
        contour sets of `levels` (gid ``"isoconditioning"``) and of the singularity (gid ``"singularity"``);
        a general mechanism's map (:func:`classify.isoconditioning.mechanism_map`) also marks the grid
        points the batched classification finds singular (gid ``"singular_points"``, red crosses) and the
        unreachable ones (gid ``"unreachable_points"``, grey dots).
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
        signed = singularity_field(conditioning_map, matrix)
        finite = signed[np.isfinite(signed)] if signed is not None else np.zeros(0)
        if np.any(finite > 0) and np.any(finite < 0):   # a change of sign to draw
            crossing = axes.contour(grid_first, grid_second, np.ma.masked_invalid(signed), levels=[0.0],
                                    colors="red", linewidths=1.2)
            crossing.set_gid("singularity")
        singular = axes.contour(grid_first, grid_second, values, levels=[SINGULAR_LEVEL], colors="red",
                                linewidths=1.2)
        singular.set_gid("singularity")
        if "singular" in conditioning_map.extra:
            singular = conditioning_map.extra["singular"] & conditioning_map.reachable
            marks = axes.scatter(grid_first[singular], grid_second[singular], marker="x", color="red", s=14,
                                 label="singular (classification)")
            marks.set_gid("singular_points")
            unreachable = ~conditioning_map.reachable
            dots = axes.scatter(grid_first[unreachable], grid_second[unreachable], marker=".", color="0.6", s=6,
                                label="not reached on the branch")
            dots.set_gid("unreachable_points")
        axes.set_xlabel(f"{drawn(conditioning_map.axis_names[0])}{suffix}")
        axes.set_ylabel(f"{drawn(conditioning_map.axis_names[1])}{suffix}")
        if equal_aspect:
            axes.set_aspect("equal")
        axes.set_title(f"mode {conditioning_map.mode}: 1/κ({MATRIX_LABELS[matrix]}), "
                       f"index {conditioning_map.global_index(matrix):.3f}", fontsize=8)
    figure.colorbar(image, ax=list(axes_list), label=f"1/κ({MATRIX_LABELS[matrix]})")
    return figure


def isoconditioning_surface_figure(plane_maps, matrix, levels=(0.2, 0.4, 0.6), turns=40, sweep=1.5 * np.pi):
    """The hybrid's isoconditioning surfaces: its in-plane curves turned about AB (Chablat, Wenger & Angeles
    1998 §5.1), one 3-D panel (mplot3d) per working mode.

    Parameters
    ----------
    plane_maps : sequence of classify.isoconditioning.ConditioningMap
        Maps of :func:`classify.isoconditioning.hybrid_plane_map` over (d₁, y).
    matrix : str
    levels : sequence of float
        Levels of 1/κ; each curve (d₁(s), y(s)) becomes the surface (d₁ cos t, y, −d₁ sin t), t ∈ [0, sweep]
        (the catalogue's frame: AB is the y axis; a part is left open to show the inside).
    turns : int
        Samples of t.

    Returns
    -------
    matplotlib.figure.Figure
        Each 3-D axes holds one surface (gid ``"isoconditioning_surface"``, label ``"1/κ = level"``) per curve
        piece of each level, axes labelled x, y, z.
    """
    from matplotlib import colormaps
    from matplotlib.figure import Figure

    from ..isoconditioning import contours

    figure = Figure(figsize=(4.2 * len(plane_maps), 4.2), layout="constrained")
    colours = colormaps["viridis"]
    angles = np.linspace(0.0, sweep, turns)
    for index, plane_map in enumerate(plane_maps):
        axes = figure.add_subplot(1, len(plane_maps), index + 1, projection="3d")
        for level, lines in contours(plane_map, matrix, levels).items():
            for line in lines:
                if len(line) < 2:
                    continue
                distance, along = line[:, 0], line[:, 1]
                surface = axes.plot_surface(distance[:, None] * np.cos(angles)[None], along[:, None]
                                            * np.ones_like(angles)[None], -distance[:, None] * np.sin(angles)[None],
                                            color=colours(level), alpha=0.55, linewidth=0, shade=True,
                                            label=f"1/κ = {level:g}")
                surface.set_gid("isoconditioning_surface")
        axes.set_xlabel("x")
        axes.set_ylabel("y (along AB)")
        axes.set_zlabel("z")
        axes.set_title(f"mode {plane_map.mode}: 1/κ({MATRIX_LABELS[matrix]}) = {', '.join(map(str, levels))}",
                       fontsize=8)
    return figure
