"""Joints and end-effectors: the frozen nouns a mechanism is built from.

Geometry is that of the assembled reference configuration ("home"), in the
ground frame; a joint value is the displacement of the second listed link
relative to the first (docs/design.rst, "Mechanism file").

=====  ===============================  ==============================  ===========
type   fields                           value                           factors
=====  ===============================  ==============================  ===========
``R``  ``point`` (planar/spatial),      rotation angle (rad),           S¹
       ``axis`` (spherical/spatial)     right-handed about the axis
``P``  ``axis``                         translation along the axis      ℝ
``S``  ``point`` (spatial)              rotation vector, in ground      SO(3)
                                        frame components
``U``  ``point``, ``axes``              pair of angles, the first       S¹ × S¹
                                        axis fixed in the first link
``C``  ``point``, ``axis``              (angle, translation)            S¹ × ℝ
=====  ===============================  ==============================  ===========
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Optional

import numpy as np

from .errors import MechanismError

__all__ = [
    "SPACES", "JOINT_TYPES", "OUTPUTS", "Joint", "EndEffector",
    "COORDINATE_LIMIT", "NAME_LENGTH_LIMIT", "WEIGHT_RANGE",
    "joint_factors", "joint_coordinate_names", "check_joint", "check_end_effector", "check_name",
    "check_text",
]

SPACES = ("planar", "spherical", "spatial")
OUTPUTS = ("position", "orientation", "pose", "tool")
#: joint type -> (space -> required geometric fields)
JOINT_TYPES = {
    "R": {"planar": ("point",), "spherical": ("axis",), "spatial": ("point", "axis")},
    "P": {"planar": ("axis",), "spatial": ("axis",)},
    "S": {"spatial": ("point",)},
    "U": {"spatial": ("point", "axes")},
    "C": {"spatial": ("point", "axis")},
}
_FACTORS = {"R": ("S1",), "P": ("R",), "S": ("SO3",), "U": ("S1", "S1"), "C": ("S1", "R")}
_SUFFIXES = {"R": ("",), "P": ("",), "S": ("[x]", "[y]", "[z]"), "U": ("[1]", "[2]"),
             "C": ("[angle]", "[slide]")}
#: largest ``|coordinate|`` of a point or an axis: beyond it squares of distances lose all precision
#: (and overflow near 1e154); a mechanism drawn in micrometres or in kilometres stays far inside
COORDINATE_LIMIT = 1e12
#: longest name (of the mechanism, a joint, a link, a space, a type) in characters
NAME_LENGTH_LIMIT = 256
#: smallest and largest actuator weight
WEIGHT_RANGE = (1e-12, 1e12)


def is_number(value):
    """True for a real number that is not a boolean (``True`` is an int in Python)."""
    return isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))


def check_text(value, where):
    """Refuse a string that is not valid Unicode text (a lone surrogate cannot be written as UTF-8).

    Parameters
    ----------
    value : str
    where : str
        The field, for the message.

    Raises
    ------
    MechanismError
        Naming the field and the position of the first lone surrogate.
    """
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as error:
        code = ord(value[error.start])
        raise MechanismError(f"{where}: not valid text: lone surrogate U+{code:04X} at position "
                             f"{error.start}") from None


def check_name(value, where):
    """A name: a non-empty string of valid text, at most :data:`NAME_LENGTH_LIMIT` characters.

    Parameters
    ----------
    value : object
    where : str
        The field, for the message.

    Returns
    -------
    str
        `value`, unchanged.

    Raises
    ------
    MechanismError
        Naming the field.
    """
    if not isinstance(value, str) or not value:
        shown = repr(value) if len(repr(value)) <= 40 else type(value).__name__
        raise MechanismError(f"{where}: expected a non-empty string, got {shown}")
    if len(value) > NAME_LENGTH_LIMIT:
        raise MechanismError(f"{where}: expected a name of at most {NAME_LENGTH_LIMIT} characters, "
                             f"got {len(value)} ({value[:20]!r}...)")
    check_text(value, where)
    return value


def _vector(values, where):
    """A tuple of floats from a sequence of numbers; MechanismError naming the field otherwise."""
    if values is None:
        return None
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise MechanismError(f"{where}: expected a list of numbers, got {values!r}")
    if not all(is_number(value) for value in values):
        raise MechanismError(f"{where}: expected numbers, got {list(values)!r}")
    return tuple(float(value) for value in values)


@dataclass(frozen=True)
class Joint:
    """A joint between two links.

    Parameters
    ----------
    name : str
    type : {"R", "P", "S", "U", "C"}
    links : tuple of two str
        ``(first, second)``; the value moves `second` relative to `first`.
    point : tuple of float, optional
        A point of the joint axis / the joint centre at home (2 numbers planar, 3 spatial).
    axis : tuple of float, optional
        Direction (2 numbers for a planar P, 3 otherwise). Need not be unit.
    axes : tuple of two tuples, optional
        For ``U``: the first axis (fixed in the first link) and the second.
    actuated : bool
    weight : float
        Weight of the actuated coordinates in the actuator metric E (default 1).
    """

    name: str
    type: str
    links: tuple
    point: Optional[tuple] = None
    axis: Optional[tuple] = None
    axes: Optional[tuple] = None
    actuated: bool = False
    weight: float = 1.0

    def __post_init__(self):
        where = f"joint {self.name!r}"
        if isinstance(self.links, (str, bytes)) or not hasattr(self.links, "__len__"):
            raise MechanismError(f"{where}: field 'links': expected two link names, got {self.links!r}")
        object.__setattr__(self, "links", tuple(self.links))
        object.__setattr__(self, "point", _vector(self.point, f"{where}: field 'point'"))
        object.__setattr__(self, "axis", _vector(self.axis, f"{where}: field 'axis'"))
        if self.axes is not None:
            if isinstance(self.axes, (str, bytes)) or not hasattr(self.axes, "__len__"):
                raise MechanismError(f"{where}: field 'axes': expected two axes, got {self.axes!r}")
            object.__setattr__(self, "axes", tuple(_vector(axis, f"{where}: field 'axes'") for axis in self.axes))
        if not is_number(self.weight):
            raise MechanismError(f"{where}: field 'weight': expected a number, got {self.weight!r}")
        object.__setattr__(self, "weight", float(self.weight))


@dataclass(frozen=True)
class EndEffector:
    """The end-effector: a frame on a link, or an axisymmetric tool on it.

    Parameters
    ----------
    link : str
    point : tuple of float, optional
        Origin of the frame at home (planar/spatial; not for spherical); for
        ``tool``, a point of the tool's axis (the tool point).
    output : {"position", "orientation", "pose", "tool"}
        What the end-effector map f returns: the point (ℝ² / ℝ³), the link's
        orientation (SO(2) / SO(3)), both (SE(2) / SE(3)), or, for a spatial
        mechanism, the tool point and the unit direction of `axis`
        (ℝ³ × S², dimension 5: an axisymmetric tool, whose spin about its own
        axis is not an end-effector motion).
    axis : tuple of float, optional
        For ``tool`` only (and required by it): the direction of the tool's
        axis at home, 3 numbers in the ground frame, fixed in the link. Need
        not be unit; its sign does not matter to any verdict.
    """

    link: str
    point: Optional[tuple] = None
    output: str = "position"
    axis: Optional[tuple] = None

    def __post_init__(self):
        object.__setattr__(self, "point", _vector(self.point, "end_effector: field 'point'"))
        object.__setattr__(self, "axis", _vector(self.axis, "end_effector: field 'axis'"))


def joint_factors(joint):
    """Ambient factors of a joint, e.g. ``("S1", "R")`` for ``C``."""
    return _FACTORS[joint.type]


def joint_coordinate_names(joint):
    """Names of a joint's tangent coordinates, e.g. ``("S1[x]", "S1[y]", "S1[z]")``."""
    return tuple(joint.name + suffix for suffix in _SUFFIXES[joint.type])


def _point_dimension(space):
    return 2 if space == "planar" else 3


def _axis_dimension(space, joint_type):
    return 2 if (space == "planar" and joint_type == "P") else 3


def _check_vector(values, size, where):
    if values is None:
        raise MechanismError(f"{where}: missing")
    if len(values) != size:
        raise MechanismError(f"{where}: expected {size} numbers, got {len(values)}")
    if not all(math.isfinite(value) for value in values):
        raise MechanismError(f"{where}: expected finite numbers, got {list(values)}")
    for index, value in enumerate(values):
        if abs(value) > COORDINATE_LIMIT:
            raise MechanismError(f"{where}: item {index}: {value:g} is out of range "
                                 f"(coordinates are at most {COORDINATE_LIMIT:g} in absolute value)")


def _check_direction(values, size, where):
    _check_vector(values, size, where)
    if np.linalg.norm(values) < 1e-12:
        raise MechanismError(f"{where}: the axis must not be zero")


def check_joint(joint, space):
    """Validate one joint for a space; raise :class:`MechanismError` naming the joint and field."""
    if not isinstance(joint.name, str) or not joint.name:
        raise MechanismError(f"joint name: expected a non-empty string, got {joint.name!r}")
    check_name(joint.name, "joint name")
    where = f"joint {joint.name!r}"
    if joint.type not in JOINT_TYPES:
        raise MechanismError(f"{where}: field 'type': unknown joint type {joint.type!r} "
                             f"(expected one of {', '.join(JOINT_TYPES)})")
    if space not in JOINT_TYPES[joint.type]:
        allowed = ", ".join(JOINT_TYPES[joint.type])
        article = "an" if joint.type in "SUR" else "a"
        raise MechanismError(f"{where}: field 'type': {article} {joint.type} joint is not allowed in a "
                             f"{space} mechanism (only {allowed})")
    if len(joint.links) != 2 or not all(isinstance(link, str) and link for link in joint.links):
        raise MechanismError(f"{where}: field 'links': expected two link names, got {list(joint.links)}")
    for index, link in enumerate(joint.links):
        check_name(link, f"{where}: field 'links': item {index}")
    if joint.links[0] == joint.links[1]:
        raise MechanismError(f"{where}: field 'links': a joint cannot join link "
                             f"{joint.links[0]!r} to itself")
    if not isinstance(joint.actuated, bool):
        raise MechanismError(f"{where}: field 'actuated': expected true or false, got {joint.actuated!r}")
    if not math.isfinite(joint.weight) or joint.weight <= 0:
        raise MechanismError(f"{where}: field 'weight': expected a positive finite number, got {joint.weight!r}")
    if not WEIGHT_RANGE[0] <= joint.weight <= WEIGHT_RANGE[1]:
        raise MechanismError(f"{where}: field 'weight': expected a weight between {WEIGHT_RANGE[0]:g} and "
                             f"{WEIGHT_RANGE[1]:g}, got {joint.weight:g}")
    if not joint.actuated and joint.weight != 1.0:
        raise MechanismError(f"{where}: field 'weight': a weight is only used on an actuated joint")
    if joint.actuated and joint.type == "S":
        raise MechanismError(f"{where}: field 'actuated': an S joint cannot be actuated")
    required = JOINT_TYPES[joint.type][space]
    for name in ("point", "axis", "axes"):
        if name not in required and getattr(joint, name) is not None:
            raise MechanismError(f"{where}: field {name!r}: not used by a {space} {joint.type} joint")
    if "point" in required:
        _check_vector(joint.point, _point_dimension(space), f"{where}: field 'point'")
    if "axis" in required:
        _check_direction(joint.axis, _axis_dimension(space, joint.type), f"{where}: field 'axis'")
    if "axes" in required:
        if joint.axes is None or len(joint.axes) != 2:
            raise MechanismError(f"{where}: field 'axes': expected two axes [first, second]")
        for index, axis in enumerate(joint.axes):
            _check_direction(axis, 3, f"{where}: field 'axes[{index}]'")
        first, second = (np.asarray(axis) / np.linalg.norm(axis) for axis in joint.axes)
        if np.linalg.norm(np.cross(first, second)) < 1e-9:
            raise MechanismError(f"{where}: field 'axes': the two axes of a U joint must not be parallel")


def check_end_effector(end_effector, space, links):
    """Validate an end-effector; raise :class:`MechanismError` naming the field."""
    where = "end_effector"
    check_name(end_effector.link, f"{where}: field 'link'")
    if end_effector.link not in links:
        raise MechanismError(f"{where}: field 'link': unknown link {end_effector.link!r}")
    if end_effector.output not in OUTPUTS:
        raise MechanismError(f"{where}: field 'output': expected one of {', '.join(OUTPUTS)}, "
                             f"got {end_effector.output!r}")
    if end_effector.output != "tool" and end_effector.axis is not None:
        raise MechanismError(f"{where}: field 'axis': only used by a 'tool' output, not by "
                             f"{end_effector.output!r}")
    if end_effector.output == "tool":
        if space != "spatial":
            raise MechanismError(f"{where}: field 'output': a 'tool' output needs a spatial mechanism, "
                                 f"not a {space} one")
        _check_vector(end_effector.point, 3, f"{where}: field 'point'")
        _check_direction(end_effector.axis, 3, f"{where}: field 'axis'")
        return
    if space == "spherical":
        if end_effector.point is not None:
            raise MechanismError(f"{where}: field 'point': not used by a spherical mechanism")
        if end_effector.output != "orientation":
            raise MechanismError(f"{where}: field 'output': a spherical mechanism's end-effector "
                                 f"output must be 'orientation'")
        return
    if end_effector.output == "orientation":
        if end_effector.point is not None:
            raise MechanismError(f"{where}: field 'point': not used by an 'orientation' output")
        return
    _check_vector(end_effector.point, _point_dimension(space), f"{where}: field 'point'")
