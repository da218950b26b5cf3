"""Pictures of singularity loci and C-space maps (:mod:`classify.loci`), in the coordinates the user chooses.

* :func:`draw_loci`: each locus piece as a line (actuator red, end-effector
  blue; gid ``locus:KIND:INDEX``), C-space singularities (branch points) as
  black crosses (gid ``branch-point:INDEX``). A piece that is a whole branch
  of M singular everywhere (``LocusPiece.whole_branch``) is drawn dashed
  along the branch (gid ``locus:KIND:INDEX:whole-branch``).
* :func:`draw_cspace_map`: M itself under the loci. 1 dof: each traced
  branch of M as a line of its own colour (gid ``branch:INDEX``), its
  crossings the branch points (Park & Kim 1999 Fig. 3a, Fig. 4: the two
  branches of the slider-crank meeting at its C-space singularity).
  2 dof: the points of M the search started from, coloured by the signs of
  the actuator and end-effector functions (gid ``mode:SA,SE``): the
  assembly modes (sign of det A) and working modes (sign of det B) of
  Chablat, Wenger & Angeles 1998 (Figs. 2–5), with the loci as their
  boundaries. When the grid was assembled on several assembly branches
  (``trace_loci(..., assembly_branches=n)``), its points are coloured by
  branch instead (gid ``grid-branch:INDEX``; nested squares where branches
  share a grid point).

* :func:`draw_sections`: a 3-dof mechanism's loci as a grid of panels, one
  per section (titled with the section coordinate's value), each the C-space
  map of that section in two coordinates, every panel's axes labelled; one
  legend for the figure (``figure.legends[0]``, below the panels) names
  every kind drawn in any panel (a panel may draw nothing).

A 3-dof mechanism's loci drawn by :func:`draw_cspace_map` in three joint
coordinates are the sections stacked in 3-D axes.

Axes are labelled with the coordinates' names; with ``units=True`` (the HTML report's pictures and
``closedchain loci --out``) with what
they show and in which unit (:func:`axis_labels`): a joint coordinate as its displacement from home, in rad
for an angle and in the mechanism's unit of length for a slide (``"A − A₀ (rad)"``); an end-effector's
coordinates in the unit of length (``"x (length unit)"``, :func:`classify.figures.drawing.length_unit`).

Angles are wrapped to [−π, π); a line is broken where a wrapped angle jumps by more than π (never where
a length coordinate does).
"""

from __future__ import annotations

import numpy as np

from .drawing import KIND_COLOURS, length_unit

__all__ = ["draw_loci", "draw_cspace_map", "draw_sections", "axis_labels", "BRANCH_COLOURS"]

#: colours of the branches of a 1-dof C-space map
BRANCH_COLOURS = ("tab:green", "tab:orange", "tab:cyan", "tab:olive", "tab:pink", "tab:brown")
#: sign patterns (actuator, end-effector) → colour
_MODE_COLOURS = {(1, 1): "#c6dbef", (1, -1): "#fdd0a2", (-1, 1): "#c7e9c0", (-1, -1): "#dadaeb"}


def _broken(values, angle_columns):
    """The line with NaN rows inserted where a wrapped angle jumps by more than π.

    Parameters
    ----------
    values : ndarray, shape=[p, d]
        The drawn points.
    angle_columns : ndarray of bool, shape=[d]
        The columns that are angles wrapped to [−π, π) (revolute joint coordinates); only they can wrap. A
        length (a prismatic coordinate, an end-effector position) is never broken, whatever its jumps.

    Returns
    -------
    ndarray, shape=[p + breaks, d]
    """
    angle_columns = np.asarray(angle_columns, dtype=bool)
    if len(values) < 2 or not np.any(angle_columns):
        return values
    steps = np.abs(np.diff(values[:, angle_columns], axis=0))
    jumps = np.flatnonzero(np.any(steps > np.pi, axis=1))
    return np.insert(values, jumps + 1, np.nan, axis=0) if jumps.size else values


def _angle_columns(mechanism, coordinates):
    """Which shown columns are wrapped angles: the revolute joint coordinates among `coordinates`; none for
    the end-effector's coordinates (``coordinates`` a string), which are not wrapped."""
    from ..loci_coordinates import _is_angle

    if isinstance(coordinates, str):
        return np.zeros(0, dtype=bool)
    return np.array([_is_angle(mechanism, column) for column in coordinates], dtype=bool)


def axis_labels(mechanism, coordinates, units=False):
    """The axis labels of loci shown in `coordinates`, known without a point (an empty panel is labelled too).

    Parameters
    ----------
    mechanism : Mechanism
    coordinates : sequence of int or "end-effector"
        Tangent coordinate columns, or the end-effector point (x, y; z for a spatial mechanism).
    units : bool
        Say what each axis shows and in which unit: ``"NAME − NAME₀ (rad)"`` for an angle, ``"NAME − NAME₀
        (UNIT)"`` for a slide (a displacement from home), ``"x (UNIT)"`` for the end-effector, UNIT the
        mechanism's unit of length (:func:`classify.figures.drawing.length_unit`). Default: the bare names.

    Returns
    -------
    tuple of str
        Matplotlib text (:func:`classify.text.drawn`: escaped, no mathtext).
    """
    from ..text import drawn

    length = length_unit(mechanism)
    if isinstance(coordinates, str):
        names = ("x", "y", "z")[: 3 if mechanism.space == "spatial" else 2]
        return tuple(f"{name} ({length})" if units else name for name in names)
    labels = []
    for column, angle in zip(coordinates, _angle_columns(mechanism, coordinates)):
        name = drawn(mechanism.coordinate_names[column])
        labels.append(f"{name} − {name}₀ ({'rad' if angle else length})" if units else name)
    return tuple(labels)


def _axes(mechanism, coordinates):
    """New axes for loci shown in `coordinates`: 3-D for three joint coordinates or a spatial end-effector."""
    from matplotlib.figure import Figure

    joints = not isinstance(coordinates, str)
    three = (joints and len(coordinates) == 3) or (not joints and mechanism.space == "spatial")
    return Figure(figsize=(6, 5.5)).add_subplot(projection="3d" if three else None)


def _line(axes, values, **style):
    if values.shape[1] == 3:
        return axes.plot(values[:, 0], values[:, 1], values[:, 2], **style)[0]
    if values.shape[1] == 1:
        return axes.plot(values[:, 0], np.zeros(len(values)), **style)[0]
    return axes.plot(values[:, 0], values[:, 1], **style)[0]


def draw_sections(mechanism, loci, coordinates, title=None, columns=3, units=False):
    """Draw a 3-dof mechanism's loci section by section, one panel each (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    loci : Loci
        Traced in sections (``loci.coverage["sections"]``).
    coordinates : sequence of int or "end-effector"
        What each panel shows (two joint coordinates, or a planar end-effector point).
    title : str, optional
    columns : int
        Panels per row.
    units : bool
        Label the axes with what they show and their unit (:func:`axis_labels`).

    Returns
    -------
    matplotlib.figure.Figure
        One axes per section (gid ``section:INDEX``), each with its axis labels; one figure legend
        (``figure.legends``) of every label drawn in any panel, each once.
    """
    from dataclasses import replace

    from matplotlib.figure import Figure

    from ..displacements import displacements_of
    from ..text import drawn

    if "sections" not in loci.coverage:
        raise ValueError("draw_sections: the loci were not traced in sections (a 3-dof mechanism)")
    (name, _), = loci.coverage["section"].items()
    column = mechanism.coordinate_names.index(name)
    values = [entry["value"] for entry in loci.coverage["sections"]]
    rows = -(-len(values) // columns)
    across = min(columns, len(values))
    figure = Figure(figsize=(4.2 * across, 4.0 * rows))
    offsets = (displacements_of(mechanism, loci.samples)[:, column][:, None] - np.array(values)[None]
               if len(loci.samples) else np.zeros((0, len(values))))
    offsets = (offsets + np.pi) % (2 * np.pi) - np.pi
    for index, value in enumerate(values):
        axes = figure.add_subplot(rows, across, index + 1)
        axes.set_gid(f"section:{index}")
        chosen = np.abs(offsets[:, index]) < 1e-9
        part = replace(loci, pieces=tuple(piece for piece in loci.pieces if piece.section == value), branches=(),
                       samples=loci.samples[chosen], sample_signs=loci.sample_signs[chosen],
                       sample_branches=None if loci.sample_branches is None else loci.sample_branches[chosen])
        draw_cspace_map(mechanism, part, coordinates, axes=axes, title=f"{drawn(name)} = {value:.4g}", units=units)
    handles = {}  # label → the first artist drawn with it, over every panel
    for axes in figure.axes:
        if axes.get_legend() is not None:
            axes.get_legend().remove()
        for handle, label in zip(*axes.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    if handles:
        across_legend = min(3, len(handles))
        height = 0.22 * -(-len(handles) // across_legend) + 0.75  # inches: the legend's rows and the x labels
        figure.legend(list(handles.values()), list(handles), loc="lower center", ncol=across_legend,
                      fontsize="small", frameon=False)
        figure.subplots_adjust(bottom=min(height / figure.get_figheight(), 0.4))
    figure.subplots_adjust(wspace=0.4 if units else 0.3)  # room for a panel's y label beside its neighbour
    if title is not None:
        figure.suptitle(title)
        figure.subplots_adjust(top=0.84 if rows == 1 else 0.9, hspace=0.35)
    return figure


def draw_loci(mechanism, loci, coordinates, axes=None, title=None, units=False):
    """Draw the loci (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    loci : Loci
    coordinates : sequence of int or "end-effector"
        As :func:`classify.loci_coordinates.locus_coordinates`.
    axes : matplotlib Axes, optional
    title : str, optional
    units : bool
        Label the axes with what they show and their unit (:func:`axis_labels`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..loci import locus_coordinates

    angles = _angle_columns(mechanism, coordinates)
    axes = _axes(mechanism, coordinates) if axes is None else axes
    labelled = set()
    for index, piece in enumerate(loci.pieces):
        values, _ = locus_coordinates(mechanism, piece.points, coordinates)
        if piece.kind == "cspace":
            _line(axes, values, linestyle="none", marker="X", markersize=11, color="k", zorder=6,
                  gid=f"branch-point:{index}", label=None if "cspace" in labelled else "C-space singularity")
        else:
            style = dict(color=KIND_COLOURS[piece.kind], linewidth=2, gid=f"locus:{piece.kind}:{index}",
                         label=None if piece.kind in labelled else f"{piece.kind.replace('_', '-')} locus")
            if piece.whole_branch:  # a branch of M singular at every point: drawn along it, dashed
                style.update(linestyle="--", linewidth=3, gid=f"locus:{piece.kind}:{index}:whole-branch",
                             label=None if f"{piece.kind}:whole-branch" in labelled
                             else f"{piece.kind.replace('_', '-')} locus: a whole branch")
                if piece.closed:
                    values = np.concatenate([values, values[:1]])
            if len(values) == 1:
                style.update(linestyle="none", marker="o", markersize=8)

            _line(axes, _broken(values, angles), **style)
        labelled.add(piece.kind + (":whole-branch" if piece.whole_branch else ""))
    _finish(axes, axis_labels(mechanism, coordinates, units), title)
    return axes.figure


def draw_cspace_map(mechanism, loci, coordinates, axes=None, title=None, units=False):
    """Draw M in the chosen coordinates with its branches or modes, the loci overlaid (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    loci : Loci
    coordinates : sequence of int or "end-effector"
    axes : matplotlib Axes, optional
    title : str, optional
    units : bool
        Label the axes with what they show and their unit (:func:`axis_labels`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..loci import locus_coordinates

    angles = _angle_columns(mechanism, coordinates)
    axes = _axes(mechanism, coordinates) if axes is None else axes
    for index, branch in enumerate(loci.branches):
        values, _ = locus_coordinates(mechanism, branch.points, coordinates)
        _line(axes, _broken(values, angles), color=BRANCH_COLOURS[index % len(BRANCH_COLOURS)], linewidth=5,
              alpha=0.5, gid=f"branch:{index}", label=f"branch {index + 1}" + (" (closed)" if branch.closed else ""))
    branch_of = loci.sample_branches
    several = branch_of is not None and len(branch_of) and branch_of.max() > 0
    if not loci.branches and several:  # the grid on several assembly branches: coloured by branch, nested squares
        values, _ = locus_coordinates(mechanism, loci.samples, coordinates)
        for branch in range(int(branch_of.max()) + 1):
            chosen = branch_of == branch
            _line(axes, values[chosen], linestyle="none", marker="s", markersize=max(9 - 2.5 * branch, 3),
                  color=BRANCH_COLOURS[branch % len(BRANCH_COLOURS)], alpha=0.6, gid=f"grid-branch:{branch}",
                  label=f"assembly branch {branch + 1}")
    elif not loci.branches and len(loci.samples):
        values, _ = locus_coordinates(mechanism, loci.samples, coordinates)
        signs = loci.sample_signs.astype(int)
        for pattern, colour in _MODE_COLOURS.items():
            chosen = np.all(signs == np.array(pattern), axis=1)
            if chosen.any():
                _line(axes, values[chosen], linestyle="none", marker="s", markersize=6, color=colour,
                      gid=f"mode:{pattern[0]:+d},{pattern[1]:+d}",
                      label=f"det sign: actuator {pattern[0]:+d}, end-effector {pattern[1]:+d}")
    return draw_loci(mechanism, loci, coordinates, axes=axes, title=title, units=units)


def _finish(axes, names, title):
    """Axis labels (`names`, matplotlib text already), the legend, the title."""
    if len(names) >= 1:
        axes.set_xlabel(names[0])
    if len(names) >= 2:
        axes.set_ylabel(names[1])
    if len(names) >= 3:
        axes.set_zlabel(names[2])
    if axes.get_legend_handles_labels()[0]:
        axes.legend(loc="best", fontsize="small")
    if title is not None:
        axes.set_title(title)
