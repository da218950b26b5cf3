"""Grids of joint coordinates for ``closedchain map --grid NAME=a:b:n ...``.

NAME is a coordinate name (:mod:`classify.cli._names`), a and b finite
numbers, n an integer ≥ 1 (``numpy.linspace(a, b, n)``; n = 1 needs a = b);
at most :data:`GRID_POINT_LIMIT` points in all. Every refusal is one line
naming the option's text and the field.
"""

from __future__ import annotations

# the dataclass lives in the core (:mod:`classify.grid_continuation`); its name stays importable from here
from ..grid_continuation import Grid
from ._common import InputError
from ._names import coordinate_column, coordinate_number, shown

__all__ = ["GRID_POINT_LIMIT", "Grid", "parse_axis", "parse_grid"]

#: most points of a --grid (the product of the counts)
GRID_POINT_LIMIT = 1_000_000


def parse_axis(text, option="--grid"):
    """``(name, a, b, n)`` of one axis text ``NAME=a:b:n`` (the name as written, stripped).

    Raises
    ------
    InputError
        ``OPTION 'TEXT': ...`` (one line): no ``=`` or no name, not three fields, a non-finite or out-of-range
        bound, a count that is not an integer ≥ 1 (or 1 with a ≠ b).
    """
    where = f"{option} {shown(text, 60)}"
    name, equals, spec = text.rpartition("=")
    if not equals or not name.strip():
        raise InputError(f"{where}: expected NAME=a:b:n (a coordinate name, the first and last values and "
                         f"the number of points)")
    fields = spec.split(":")
    if len(fields) != 3:
        raise InputError(f"{where}: expected NAME=a:b:n with three fields after '=', got {len(fields)}")
    start = coordinate_number(fields[0], f"{where}: a")
    stop = coordinate_number(fields[1], f"{where}: b")
    count_text = fields[2].strip()
    if not (count_text.isascii() and count_text.isdecimal()) or len(count_text) > 12 or int(count_text) < 1:
        raise InputError(f"{where}: n: expected an integer ≥ 1, got "
                         f"{shown(fields[2]) if count_text else 'nothing'}")
    count = int(count_text)
    if count == 1 and start != stop:
        raise InputError(f"{where}: n = 1 gives one point: a and b must be equal (got {start:g} and {stop:g})")
    return name.strip(), start, stop, count


def parse_grid(texts, mechanism, option="--grid"):
    """The :class:`Grid` of ``--grid`` texts ``NAME=a:b:n`` (`option`: the option named in messages).

    Raises
    ------
    InputError
        ``--grid 'TEXT': ...`` (one line): no ``=``, not three fields, a
        non-finite bound, a count that is not an integer ≥ 1 (or 1 with
        a ≠ b), an unknown or repeated coordinate, or more than
        :data:`GRID_POINT_LIMIT` points in all.
    """
    names, columns, starts, stops, counts = [], [], [], [], []
    size = 1
    for text in texts:
        where = f"{option} {shown(text, 60)}"
        name, start, stop, count = parse_axis(text, option)
        column = coordinate_column(mechanism, name, where)
        if column in columns:
            raise InputError(f"{where}: coordinate {shown(mechanism.coordinate_names[column])} is on the grid twice")
        size *= count
        if size > GRID_POINT_LIMIT:
            raise InputError(f"{where}: the grid has more than {GRID_POINT_LIMIT} points (the product of the counts)")
        names.append(mechanism.coordinate_names[column])
        columns.append(column)
        starts.append(start)
        stops.append(stop)
        counts.append(count)
    if not names:
        raise InputError(f"{option}: expected at least one NAME=a:b:n")
    return Grid(tuple(names), tuple(columns), tuple(starts), tuple(stops), tuple(counts))
