"""Coordinate names of the command line: joint names and coordinate names to columns, and names in messages.

A batch or a grid holds joint displacements as a matrix, shape=[n, k], one
column per tangent coordinate in the order of ``mechanism.coordinate_names``
(``A``, ``S1[x]``, ``S1[y]``, ``S1[z]``, ``U1[1]``, …; an S joint's three
columns are its rotation vector; an R or P joint's name is also its
coordinate's). Names that come from a file or an option are shown quoted,
escaped and cut (:func:`shown`), so that a refusal stays one line.
"""

from __future__ import annotations

import math

from mechanisms.joints import COORDINATE_LIMIT, joint_coordinate_names

from ..displacements import coordinate_columns
from ..text import printable
from ._common import InputError

__all__ = ["coordinate_columns", "coordinate_column", "coordinate_number", "shown", "known"]


def _coordinate_index(mechanism):
    """Coordinate name → column, and joint name → column for joints of one coordinate (R, P)."""
    index = {name: column for column, name in enumerate(mechanism.coordinate_names)}
    for joint, indices in coordinate_columns(mechanism).items():
        if len(indices) == 1:
            index.setdefault(joint, indices[0])
    return index


def coordinate_column(mechanism, name, where):
    """The column of a coordinate named in a file or an option.

    Raises
    ------
    InputError
        ``WHERE: unknown coordinate 'NAME' (known: ...)``, or the coordinates
        to name instead of a joint of several.
    """
    index = _coordinate_index(mechanism)
    if name in index:
        return index[name]
    joints = {joint.name: joint for joint in mechanism.joints}
    if name in joints:
        names = joint_coordinate_names(joints[name])
        raise InputError(f"{where}: joint {shown(name)} ({joints[name].type}) has {len(names)} coordinates: name "
                         f"one of {known(names)}")
    raise InputError(f"{where}: unknown coordinate {shown(name)} (known: {known(mechanism.coordinate_names)})")


def shown(text, limit=40):
    """A name or a cell from a file, quoted, escaped and cut for a one-line message."""
    text = str(text)
    return printable(repr(text if len(text) <= limit else text[:limit - 3] + "..."))


def known(names, limit=20):
    """Names for a message: the first `limit`, then how many in all."""
    names = list(names)
    listed = ", ".join(names[:limit]) + (f", … ({len(names)} in all)" if len(names) > limit else "")
    return printable(listed)


def coordinate_number(text, where, empty="nothing"):
    """A finite number of at most :data:`~mechanisms.joints.COORDINATE_LIMIT` in absolute value, from text.

    Parameters
    ----------
    text : str
        A CSV cell or a bound of ``--grid``.
    where : str
        What the text is, first in every message.
    empty : str
        How an empty text is named in the message.

    Raises
    ------
    InputError
        One line: not a number, not finite, or out of range.
    """
    from mechanisms._numerals import Underflow, decimal_number

    try:
        value = decimal_number(text)
    except ValueError as error:
        if isinstance(error, Underflow):
            raise InputError(f"{where}: {shown(text.strip())} is below the smallest float (it would read as 0)") \
                from None
        raise InputError(f"{where}: expected a number, got {shown(text) if text.strip() else empty}") from None
    if not math.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {shown(text.strip())}")
    if abs(value) > COORDINATE_LIMIT:
        raise InputError(f"{where}: {value:g} is out of range (at most {COORDINATE_LIMIT:g} in absolute value)")
    return value
