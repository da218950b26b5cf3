"""Figures of line-plane 5-SPU designs: the B-lines over the base, and a rearrangement before/after.

* :func:`draw_b_lines` draws, on the base plane Π, the base attachments,
  the B-line B_{zᵢ} through each (14), the point B (16), the line B∞ (15)
  and Λ⁺ (23) with the platform attachments copied onto it (Borràs, Thomas &
  Torras 2011 Figs. 4, 8).
* :func:`draw_rearrangement` draws a design before and after a rearrangement
  side by side, and a third panel with a slice of the singularity locus of
  both: for a fixed direction i and height p_z, (17) is linear in (pₓ, p_y),
  so the slice is a line; an allowed rearrangement leaves it in place.

Artists carry labels (``"B-line 1"``, ``"B"``, ``"B_inf"``, ``"Lambda+"``,
``"base"``, ``"locus before"``, ``"locus after"``) so the tests read them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["draw_b_lines", "draw_rearrangement", "locus_slice"]


def _figure(width, height):
    from matplotlib.figure import Figure

    return Figure(figsize=(width, height))


def _limits(design, extra=()):
    points = [design.base] + [np.atleast_2d(point) for point in extra if point is not None]
    points = np.concatenate(points)
    centre = points.mean(axis=0)
    half = max(float(np.max(np.abs(points - centre))) * 1.4, 1e-9)
    return centre[0] - half, centre[0] + half, centre[1] - half, centre[1] + half


def _segment(line, limits):
    """Two points of the line ax + by + c = 0 spanning the box `limits`, shape=[2, 2]; None if at infinity."""
    a, b, c = line
    x0, x1, y0, y1 = limits
    norm = np.hypot(a, b)
    if norm <= 1e-12 * np.linalg.norm(line):
        return None
    normal = np.array([a, b]) / norm
    foot = -c / norm * normal
    direction = np.array([-normal[1], normal[0]])
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    reach = np.hypot(x1 - x0, y1 - y0)
    middle = foot + ((centre - foot) @ direction) * direction
    return np.array([middle - reach * direction, middle + reach * direction])


def draw_b_lines(design, axes=None, title=None):
    """The B-lines of a design over its base plane.

    Parameters
    ----------
    design : LinePlaneDesign
    axes : matplotlib.axes.Axes, optional
        Draw here; default a new figure's single axes.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        For an architecturally singular design (all Cⱼ vanish) there are no
        B-lines, B, B∞ or Λ⁺: only the base attachments are drawn, and the
        title says so.
    """
    from ..line_plane import b_infinity, b_line, b_point, family, lambda_plus

    if axes is None:
        figure = _figure(5, 5)
        axes = figure.add_subplot(1, 1, 1)
    point = b_point(design)
    plus = lambda_plus(design)
    copies = None if plus is None else plus[1]
    limits = _limits(design, [point, copies])
    singular = family(design).name == "architecturally singular"
    if singular:
        title = "architecturally singular: no B-lines" if title is None else f"{title} (architecturally singular)"
    for index, line in enumerate(() if singular else b_line(design, design.platform)):
        segment = _segment(line, limits)
        if segment is not None:
            axes.plot(segment[:, 0], segment[:, 1], "-", lw=0.8, color=f"C{index}", label=f"B-line {index + 1}")
    axes.plot(design.base[:, 0], design.base[:, 1], "ko", label="base")
    for index, (x, y) in enumerate(design.base):
        axes.annotate(f"a{index + 1} (z={design.platform[index]:.3g})", (x, y), textcoords="offset points",
                      xytext=(4, 4), fontsize=7)
    if point is not None:
        axes.plot([point[0]], [point[1]], "r*", markersize=12, label="B")
    infinity = b_infinity(design)
    if infinity is not None:
        segment = _segment(infinity, limits)
        axes.plot(segment[:, 0], segment[:, 1], "k--", lw=1.0, label="B_inf")
    if plus is not None:
        segment = _segment(plus[0], limits)
        axes.plot(segment[:, 0], segment[:, 1], "k:", lw=1.0, label="Lambda+")
        if copies is not None:
            axes.plot(copies[:, 0], copies[:, 1], "ks", markerfacecolor="none", label="b+")
    axes.set_xlim(limits[0], limits[1])
    axes.set_ylim(limits[2], limits[3])
    axes.set_aspect("equal")
    axes.set_xlabel("x")
    axes.set_ylabel("y")
    if title is not None:
        axes.set_title(title)
    return axes.figure


def locus_slice(design, direction, height):
    """The slice of the singularity locus at fixed i and p_z: the line a pₓ + b p_y + c = 0, shape=[3].

    From (17): ℓ·(pₓw − p_zu, p_yw − p_zv, w) with ℓ = w(C₂, C₃, C₆) − p_z(C₄, C₅, C₁),
    so a = ℓ₁w, b = ℓ₂w, c = −p_z(ℓ₁u + ℓ₂v) + ℓ₃w; normalised to a² + b² = 1
    (for w ≠ 0 and a finite slice).
    """
    from ..line_plane import cofactors

    c1, c2, c3, c4, c5, c6 = cofactors(design)
    u, v, w = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    line = w * np.array([c2, c3, c6]) - height * np.array([c4, c5, c1])
    result = np.array([line[0] * w, line[1] * w, -height * (line[0] * u + line[1] * v) + line[2] * w])
    return result / np.hypot(result[0], result[1])


def draw_rearrangement(before, after, direction=(0.2, -0.3, 1.0), height=2.0, title=None):
    """A design before and after a rearrangement, and their locus slices at (i, p_z).

    Parameters
    ----------
    before, after : LinePlaneDesign
    direction : array_like, shape=[3]
        The fixed i of the slice.
    height : float
        The fixed p_z of the slice.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Three axes: the B-lines before, after, and the two locus slices.
    """
    figure = _figure(13, 4.5)
    draw_b_lines(before, figure.add_subplot(1, 3, 1), "before")
    draw_b_lines(after, figure.add_subplot(1, 3, 2), "after")
    axes = figure.add_subplot(1, 3, 3)
    limits = _limits(before)
    for design, style, label in ((before, "b-", "locus before"), (after, "r--", "locus after")):
        segment = _segment(locus_slice(design, direction, height), limits)
        if segment is not None:
            axes.plot(segment[:, 0], segment[:, 1], style, label=label)
    axes.set_xlim(limits[0], limits[1])
    axes.set_ylim(limits[2], limits[3])
    axes.set_xlabel("p_x")
    axes.set_ylabel("p_y")
    axes.set_title(f"singular p (i fixed, p_z = {height:g})")
    axes.legend(fontsize=7)
    if title is not None:
        figure.suptitle(title)
    return figure
