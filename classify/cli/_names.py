"""Coordinate names of the command line: joint names and coordinate names to columns, and names in messages.

A batch or a grid holds joint displacements as a matrix, shape=[n, k], one
column per tangent coordinate in the order of ``mechanism.coordinate_names``
(``A``, ``S1[x]``, ``S1[y]``, ``S1[z]``, ``U1[1]``, …; an S joint's three
columns are its rotation vector; an R or P joint's name is also its
coordinate's). Names that come from a file or an option are shown quoted,
escaped and cut (:func:`shown`), so that a refusal stays one line.
"""

from __future__ import annotations

from mechanisms.joints import joint_coordinate_names

from ..text import printable
from ._common import InputError

__all__ = ["coordinate_columns", "coordinate_column", "shown", "known"]


def coordinate_columns(mechanism):
    """Joint name → the indices of its tangent coordinates (columns of a displacement matrix), in order.

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    dict of str to tuple of int
    """
    columns, start = {}, 0
    for joint in mechanism.joints:
        count = len(joint_coordinate_names(joint))
        columns[joint.name] = tuple(range(start, start + count))
        start += count
    return columns


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
