"""The grid of a 2- or 3-dof locus: its coordinates, ranges and counts, its assembly on M, and its sections.

The grid is over two coordinates (3 dof: then a third, the section
coordinate, whose values give the sections), assembled by continuation from
a starting configuration (:func:`classify.grid_continuation.assemble_branches`);
a section adds the row h(p) = x_c(p) − c to a traced curve (see
:mod:`classify.loci`).

References
----------
Park & Kim 1999, Section 3 (the loci the grid seeds).
"""

from __future__ import annotations

import numpy as np

from .loci_coordinates import _is_angle, default_columns

__all__ = ["SECTION_COUNT", "SLIDE_RANGE"]

#: sections of a 3-dof locus when the caller gives no count
SECTION_COUNT = 4

#: a slide's default grid range: this many characteristic lengths either side of the start (a span of one: a
#: slide's travel is of the order of a link, shorter than the whole mechanism; ±2 put most of a 3-RPR's grid out
#: of its legs' reach)
SLIDE_RANGE = 0.5


def _section_function(mechanism, column, value):
    """h(p) = x_c(p) − c, the section coordinate's displacement from home minus the section's value (an angle's
    difference wrapped to [−π, π)), shape=[n]."""
    from .displacements import displacements_of

    angle = _is_angle(mechanism, column)

    def section(points):
        difference = displacements_of(mechanism, points)[:, column] - value
        return (difference + np.pi) % (2 * np.pi) - np.pi if angle else difference

    return section


def _default_sections(value, half, count, angle):
    """The default range of `count` sections around the start's `value`: evenly spaced by 2·half / count (an
    angle: half = π, a turn without its end, the start again) or half / ⌊count / 2⌋ (a slide, within ±half), the
    start's value the ⌊count / 2⌋-th of them (0-based): 4 sections at −half, −half / 2, 0 and half / 2 from it,
    5 symmetric about it, 1 at it."""
    below = count // 2
    if below == 0:
        return (value, value)
    spacing = 2 * half / count if angle else half / below
    return (value - below * spacing, value + (count - 1 - below) * spacing)


def _whole(value):
    """Whether `value` is an integer (not a bool, a float or text)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _grid_arguments(mechanism, start, columns, ranges, counts, dof=2):
    """The grid's columns, ranges and counts with their defaults (see :func:`trace_loci`): 2 dof two axes; 3 dof
    three, the last the section coordinate."""
    from mechanisms.kinematics import kinematics_of

    from .displacements import displacements_of

    size = len(mechanism.coordinate_names)
    if columns is not None and not all(_whole(column) and 0 <= column < size for column in columns):
        raise ValueError(f"a locus grid's columns are coordinate numbers from 0 to {size - 1}, got {list(columns)}")
    columns = default_columns(mechanism, dof, start) if columns is None else [int(column) for column in columns]
    if len(columns) != dof:
        axes = "two grid axes and a section" if dof == 3 else "two grid axes"
        raise ValueError(f"a {dof}-dof locus grid has {dof} coordinates ({axes}), got {len(columns)}")
    if len(set(columns)) != len(columns):
        raise ValueError(f"a locus grid names a coordinate twice: {columns}")
    if isinstance(counts, (str, bytes)) or not all(_whole(count) for count in counts):
        raise ValueError(f"a locus grid's counts are whole numbers, got {counts!r}")
    counts = [int(count) for count in counts]
    if dof == 3 and len(counts) == 2:
        counts.append(SECTION_COUNT)
    if len(counts) != dof or min(counts[:2]) < 2 or min(counts) < 1:
        raise ValueError(f"a {dof}-dof locus grid needs {dof} counts (the grid's ≥ 2), got {counts}")
    if ranges is None:
        ranges = [None] * dof
    if len(ranges) > dof or not all(pair is None or (len(pair) == 2 and all(np.isfinite(value) for value in pair))
                                    for pair in ranges):
        raise ValueError(f"a {dof}-dof locus grid has at most {dof} ranges, each None or two finite numbers (low, "
                         f"high), got {ranges!r}")
    ranges = list(ranges) + [None] * (dof - len(ranges))
    values = displacements_of(mechanism, start[None])[0]
    scales = kinematics_of(mechanism).ambient.tangent_scales
    for axis, column in enumerate(columns):
        if ranges[axis] is None:
            half = np.pi if _is_angle(mechanism, column) else SLIDE_RANGE * scales[column]
            ranges[axis] = (_default_sections(values[column], half, counts[axis], _is_angle(mechanism, column))
                            if axis == 2 else (values[column] - half, values[column] + half))
    ranges = [tuple(map(float, pair)) for pair in ranges]
    if dof == 3 and counts[2] == 1 and ranges[2][0] != ranges[2][1]:
        raise ValueError(f"one section has one value: its range must be a single value, got {ranges[2]}")
    return columns, ranges, counts


def _assembled_grid(mechanism, start, columns, ranges, counts, assembly_branches=1, rng=None, constraint_rank=None):
    """The grid assembled by continuation from `start` (:func:`classify.grid_continuation.assemble_branches`; a
    singular start reaching nothing: from its regular neighbour); (points [b, n, point_size], reached [b, n],
    StartingPoint, distinct solutions the probes found); `constraint_rank` the survey's rank of DΦ·s on M (a start
    at a C-space singularity is left for a regular neighbour)."""
    from .grid_continuation import Grid, assemble_branches, grid_targets, held_columns

    grid = Grid(tuple(mechanism.coordinate_names[column] for column in columns), tuple(columns),
                tuple(low for low, _ in ranges), tuple(high for _, high in ranges), tuple(counts))
    targets = grid_targets(mechanism, grid, start)
    rng = np.random.default_rng(0) if rng is None else rng
    points, reached, starting, solutions = assemble_branches(mechanism, start, targets, grid.shape,
                                                             held_columns(mechanism, grid, False),
                                                             assembly_branches, rng,
                                                             constraint_rank=constraint_rank)
    return points, np.asarray(reached, dtype=bool), starting, solutions
