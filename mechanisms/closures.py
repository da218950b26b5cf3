"""The loop-closure file that goes beside a URDF (the convention of the Gepetto ``example-parallel-robots`` collection).

A URDF describes a tree; the loops cut open to make it one are given in a
small YAML file::

    closed_loop: [[closedloop1_A, closedloop1_B]]   # frame pairs that must coincide
    type: [6d]                                      # per pair: 6d (rigidly) or 3d (origins only: a ball joint)
    name_mot: [mot1, mot2]                          # the actuated joints (names; see below)
    joint_name: [spherical_foot]                    # optional: URDF joints re-typed ...
    joint_type: [SPHERICAL]                         # ... as SPHERICAL, FIXED, UJOINT_AB or CARDAN
    end_effector: {frame: effector, output: pose}   # optional (closedchain's own key): the end-effector

``type`` is optional (every pair ``6d``, as that collection's loader assumes)
and is read case-insensitively (``3D`` = ``3d``); ``name_mot`` is optional
(no actuated joint); ``joint_name`` and ``joint_type`` go together, one type
per name. ``UJOINT_AB`` (``A``, ``B`` ∈ {X, Y, Z}, different) is a universal
joint: a revolute about the joint frame's axis A, then one about its (moved)
axis B; ``CARDAN`` is ``UJOINT_XY``. ``end_effector`` is closedchain's
addition to the convention (Pinocchio's loaders read only their own keys): a
frame name, resolved as the loop frames are, whose origin and link are the
end-effector's, and ``output`` (``position``, the default; ``orientation``,
``pose``, or ``tool`` with ``axis: [x, y, z]``, the tool's direction in that
frame's coordinates), so that end-effector singularities can be classified
and an exported mechanism comes back with its end-effector.

The file is read as the collection's own loader reads it. ``name_mot``
entries: its ``ActuationModel`` takes every joint whose name *contains* an
entry; here an entry that is the exact name of a joint names that joint
alone, and an entry that names no joint selects every movable joint whose name
contains it, which the import says (:func:`mechanisms.urdf.import_tree`). The
collection's older files write ``name_mot`` as one such pattern
(``name_mot: mot``, read as a one-entry list) and give ``rotule_name:
PATTERN``, with which their loader re-typed every joint whose name contains it
as ``SPHERICAL`` (:attr:`Closures.spherical_pattern`). Any other key (the
older files' ``Lidmot``/``Lidvmot`` joint indices, say) is not read: the
collection's loaders ignore keys they do not use, and so does this reader,
but never silently: :attr:`Closures.notes` names them. A file with such keys
and none of the convention's is another kind of file, and refused.

The file is read as :mod:`mechanisms.io` reads a mechanism file (YAML 1.2
core schema, no anchors or tags, 1 MiB at most); nothing is evaluated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

from .errors import MechanismError
from .joints import check_name

__all__ = ["Closures", "CLOSURE_TYPES", "JOINT_RETYPES", "END_EFFECTOR_OUTPUTS", "read_closures", "closures_from_dict",
           "closures_to_dict", "universal_axes"]

#: the two kinds of closure: the frames coincide rigidly, or only their origins do
CLOSURE_TYPES = ("6d", "3d")
#: re-typings of a URDF joint besides ``UJOINT_AB``
JOINT_RETYPES = ("SPHERICAL", "FIXED", "CARDAN")
_KEYS = ("closed_loop", "type", "name_mot", "joint_name", "joint_type", "end_effector", "rotule_name")
#: the convention's own keys: a file with keys not read and none of these is another kind of file, refused
_CONVENTION_KEYS = tuple(key for key in _KEYS if key != "end_effector")
_END_EFFECTOR_KEYS = ("frame", "output", "axis")
#: what an end-effector may output (as :class:`mechanisms.joints.EndEffector`)
END_EFFECTOR_OUTPUTS = ("position", "orientation", "pose", "tool")
_AXES = "XYZ"


@dataclass(frozen=True)
class Closures:
    """The contents of a closures file.

    Parameters
    ----------
    loops : tuple of (str, str)
        Frame pairs that coincide on the closed robot.
    types : tuple of str
        ``"6d"`` or ``"3d"``, one per loop.
    actuated : tuple of str
        Names of the actuated joints.
    retyped : dict
        Joint name → ``"SPHERICAL"``, ``"FIXED"`` or ``"UJOINT_AB"`` (``CARDAN`` read as ``UJOINT_XY``).
    end_effector : tuple of (str, str), optional
        (frame name, output) of the end-effector; None: none.
    end_effector_axis : tuple of float, optional
        A ``tool`` output's axis in the frame's coordinates (None for the other outputs).
    spherical_pattern : str, optional
        The older files' ``rotule_name``: every movable joint whose name contains it is re-typed ``SPHERICAL``
        (unless ``joint_name`` re-types it otherwise). None: none.
    notes : tuple of str
        What reading the file decided that changes nothing by itself but must be said: keys not read, ``name_mot``
        given as one pattern.
    """

    loops: tuple = ()
    types: tuple = ()
    actuated: tuple = ()
    retyped: dict = field(default_factory=dict)
    end_effector: Optional[tuple] = None
    end_effector_axis: Optional[tuple] = None
    spherical_pattern: Optional[str] = None
    notes: tuple = ()


def universal_axes(joint_type):
    """The axis indices (0, 1, 2 for X, Y, Z) of a ``UJOINT_AB`` re-typing, or None for another type."""
    if len(joint_type) == 9 and joint_type.startswith("UJOINT_"):
        first, second = joint_type[7], joint_type[8]
        if first in _AXES and second in _AXES and first != second:
            return _AXES.index(first), _AXES.index(second)
    return None


def _names(value, where):
    if not isinstance(value, list):
        raise MechanismError(f"{where}: expected a list of names, got {type(value).__name__}")
    return tuple(check_name(item, f"{where}: item {index}") for index, item in enumerate(value))


def closures_from_dict(data, source="closures file"):
    """Validate the parsed contents of a closures file.

    Parameters
    ----------
    data : object
        What the YAML file holds (a mapping).
    source : str
        Starts every error message.

    Returns
    -------
    Closures

    Raises
    ------
    MechanismError
        One line naming the field and item: a pair that is not two frame
        names, a type other than 6d/3d, as many types as pairs not given, a
        joint type not known, unequal ``joint_name`` and ``joint_type``
        lists, a name listed twice, a key that is not text, keys not read
        and none of the convention's (another kind of file). Other keys that
        are not read are named in :attr:`Closures.notes`, not refused (the
        collection's loaders ignore them too).
    """
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise MechanismError(f"{source}: expected a mapping with keys {', '.join(_KEYS[:5])}, "
                             f"got {type(data).__name__}")
    notes = []
    ignored = []
    for key in data:
        if not isinstance(key, str):
            raise MechanismError(f"{source}: key {key!r}: expected a text key"[:300])
        if key not in _KEYS:
            ignored.append(key)
    if ignored:
        shown = ", ".join(repr(key) for key in ignored[:8]) + (", ..." if len(ignored) > 8 else "")
        if not any(key in data for key in _CONVENTION_KEYS):  # another kind of file (a mechanism file, say)
            raise MechanismError(f"{source}: not a closures file: it has keys {shown} and none of "
                                 f"{', '.join(_CONVENTION_KEYS)}")
        notes.append(f"closures file: key(s) {shown} not read (only {', '.join(_KEYS)} are), ignored as the "
                     f"collection's loaders ignore them")
    loops = data.get("closed_loop") or []
    if not isinstance(loops, list):
        raise MechanismError(f"{source}: field 'closed_loop': expected a list of frame pairs, "
                             f"got {type(loops).__name__}")
    pairs = []
    for index, pair in enumerate(loops):
        where = f"{source}: field 'closed_loop': item {index}"
        if not isinstance(pair, list) or len(pair) != 2:
            raise MechanismError(f"{where}: expected a pair of frame names [A, B], got {pair!r}"[:300])
        first, second = _names(pair, where)
        if first == second:
            raise MechanismError(f"{where}: the two frames are the same ({first!r})")
        pairs.append((first, second))
    types = data.get("type")
    if types is None:
        types = ["6d"] * len(pairs)
    if not isinstance(types, list):
        raise MechanismError(f"{source}: field 'type': expected a list of 6d/3d, got {type(types).__name__}")
    if len(types) != len(pairs):
        raise MechanismError(f"{source}: field 'type': expected {len(pairs)} types, one per closed_loop pair, "
                             f"got {len(types)}")
    checked = []
    for index, kind in enumerate(types):
        if not isinstance(kind, str) or kind.lower() not in CLOSURE_TYPES:
            raise MechanismError(f"{source}: field 'type': item {index}: expected 6d or 3d, got {kind!r}"[:300])
        checked.append(kind.lower())
    motors = data.get("name_mot") or []
    if isinstance(motors, str):  # the older files: one name pattern, ``name_mot: mot``
        notes.append(f"closures file: name_mot {motors!r} is one name, read as a list of one (the older files' "
                     f"pattern)")
        motors = [motors]
    actuated = _names(motors, f"{source}: field 'name_mot'")
    _no_duplicates(actuated, f"{source}: field 'name_mot'")
    spherical = data.get("rotule_name")
    if spherical is not None:
        spherical = check_name(spherical, f"{source}: field 'rotule_name'")
    names = _names(data.get("joint_name") or [], f"{source}: field 'joint_name'")
    joint_types = data.get("joint_type") or []
    if not isinstance(joint_types, list):
        raise MechanismError(f"{source}: field 'joint_type': expected a list, got {type(joint_types).__name__}")
    if len(joint_types) != len(names):
        raise MechanismError(f"{source}: field 'joint_type': expected {len(names)} types, one per joint_name, "
                             f"got {len(joint_types)}")
    _no_duplicates(names, f"{source}: field 'joint_name'")
    retyped = {}
    for index, (name, joint_type) in enumerate(zip(names, joint_types)):
        if joint_type == "CARDAN":
            joint_type = "UJOINT_XY"
        if not isinstance(joint_type, str) or (joint_type not in JOINT_RETYPES and universal_axes(joint_type) is None):
            raise MechanismError(f"{source}: field 'joint_type': item {index}: expected SPHERICAL, FIXED, CARDAN "
                                 f"or UJOINT_AB (A, B two different axes of X, Y, Z), got {joint_type!r}"[:300])
        retyped[name] = joint_type
    end_effector, axis = _end_effector(data.get("end_effector"), source)
    return Closures(tuple(pairs), tuple(checked), actuated, retyped, end_effector, axis, spherical, tuple(notes))


def _end_effector(value, source):
    """((frame, output), axis) of the ``end_effector`` key: (None, None) without one; the axis a ``tool``'s."""
    where = f"{source}: field 'end_effector'"
    if value is None:
        return None, None
    if not isinstance(value, dict):
        raise MechanismError(f"{where}: expected a mapping {{frame: NAME, output: position|orientation|pose|tool}}, "
                             f"got {type(value).__name__}")
    for key in value:
        if key not in _END_EFFECTOR_KEYS:
            raise MechanismError(f"{where}: unknown key {key!r} (expected frame, output, axis)")
    if "frame" not in value:
        raise MechanismError(f"{where}: field 'frame': missing")
    frame = check_name(value["frame"], f"{where}: field 'frame'")
    output = value.get("output", "position")
    if output not in END_EFFECTOR_OUTPUTS:
        raise MechanismError(f"{where}: field 'output': expected position, orientation, pose or tool, "
                             f"got {output!r}"[:300])
    return (frame, output), _tool_axis(value.get("axis"), output, f"{where}: field 'axis'")


def _tool_axis(axis, output, where):
    """A ``tool`` output's axis: three finite numbers, not all zero (given for a tool and only for it)."""
    if output != "tool":
        if axis is not None:
            raise MechanismError(f"{where}: only a 'tool' output has an axis")
        return None
    if axis is None:
        raise MechanismError(f"{where}: missing (a 'tool' output needs its axis, [x, y, z] in the frame)")
    if (not isinstance(axis, list) or len(axis) != 3
            or not all(isinstance(value, (int, float)) and not isinstance(value, bool) for value in axis)):
        raise MechanismError(f"{where}: expected three numbers [x, y, z], got {axis!r}"[:300])
    if not all(math.isfinite(value) for value in axis) or not any(axis):
        raise MechanismError(f"{where}: expected finite numbers, not all zero, got {axis!r}"[:300])
    return tuple(float(value) for value in axis)


def _no_duplicates(names, where):
    seen = set()
    for index, name in enumerate(names):
        if name in seen:
            raise MechanismError(f"{where}: item {index}: {name!r} is listed twice")
        seen.add(name)


def read_closures(path):
    """Read and validate a closures file (YAML; see the module's note).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    Closures

    Raises
    ------
    MechanismError
        Starting with the path.
    """
    from ._text import _parse_yaml, _path, read_text_file

    path = _path(path)
    return closures_from_dict(_parse_yaml(read_text_file(path), str(path)), str(path))


def closures_to_dict(closures):
    """The plain data of a closures file (what :func:`closures_from_dict` reads back)."""
    data = {"closed_loop": [list(pair) for pair in closures.loops], "type": list(closures.types),
            "name_mot": list(closures.actuated)}
    if closures.retyped:
        data["joint_name"] = list(closures.retyped)
        data["joint_type"] = list(closures.retyped.values())
    if closures.spherical_pattern is not None:
        data["rotule_name"] = closures.spherical_pattern
    if closures.end_effector is not None:
        data["end_effector"] = {"frame": closures.end_effector[0], "output": closures.end_effector[1]}
        if closures.end_effector_axis is not None:
            data["end_effector"]["axis"] = list(closures.end_effector_axis)
    return data
