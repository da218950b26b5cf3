"""Reading and writing mechanism files (JSON or YAML, one schema).

The schema is the contract of docs/design.rst, "Mechanism file"::

    name: five-bar
    space: planar            # planar | spherical | spatial
    ground: ground           # optional, default "ground"
    joints:
      - {name: J1, type: R, links: [ground, proximal1], point: [0, 0], actuated: true}
      - {name: S1, type: P, links: [ground, slider], axis: [1, 0]}
    end_effector:            # optional
      link: proximal1
      point: [1.0, 1.0]      # planar/spatial; not for spherical
      output: position       # position | orientation | pose | tool (default position)

Additive extensions (readers that do not know them must reject them, as they
reject every unknown key):

``output: tool`` and ``axis`` (in ``end_effector``, spatial only)
    An axisymmetric tool: ``point`` is the tool point and ``axis`` (3 finite
    numbers, not zero, in the ground frame at home, fixed in the link) the
    direction of its axis; f is the point and the unit direction, in
    ℝ³ × S². ``axis`` is required by a ``tool`` output and refused by every
    other output.

``weight`` (per joint, optional)
    A number in [1e-12, 1e12], default 1: the weight of the joint's
    coordinates in the actuator metric E. Only an actuated joint may have a
    weight other than 1 (refused on a passive joint).
``description`` (top level, optional)
    Free text.
``configurations`` (top level, optional)
    A mapping from a configuration name to a mapping from joint name to a
    displacement from home: a number for ``R`` and ``P``, a list of 3 numbers
    (a rotation vector) for ``S``, a list of 2 numbers for ``U`` (the two
    angles) and ``C`` (angle, translation). Joints left out are at home.

``null`` for ``end_effector``, ``description`` or ``configurations`` means
"none". Every other key a file contains must be known: an unknown key is an
error naming it, never silently ignored. Numbers are ints or floats (never
booleans, never strings such as ``"1.0"``) and must be finite.

YAML is read in the YAML 1.2 core schema, not PyYAML's YAML 1.1 default:
only ``true``/``false`` are booleans (``yes``, ``no``, ``on``, ``off`` are
strings, so ``actuated: yes`` is refused rather than read as true), ``1e-3``
is a number, ``1:30`` is a string and there are no implicit timestamps.
Duplicate keys are an error in both formats. The loader builds plain data
only (the constructors of ``yaml.SafeLoader``) and nothing in a file is ever
evaluated.

Limits (a mechanism file is small, plain data):

* only a regular file is read (not a FIFO, a device or a directory), of at
  most :data:`FILE_SIZE_LIMIT` bytes (1 MiB), in UTF-8;
* YAML anchors, aliases and merge keys (``&a``, ``*a``, ``<<``) are refused,
  and so is every explicit tag but the plain ones (``!!str``, ``!!int``,
  ``!!float``, ``!!bool``, ``!!null``, ``!!seq``, ``!!map``): in
  particular ``!!python/...``;
* documents nest at most :data:`DEPTH_LIMIT` levels, and integers have at
  most :data:`DIGITS_LIMIT` digits;
* names (of the mechanism, joints, links, configurations) are valid text of
  at most 256 characters, coordinates at most 1e12 in absolute value
  (:mod:`mechanisms.joints`); displacements too.

Every problem raises :class:`~mechanisms.errors.MechanismError` with a
one-line message that starts with the file (or source) and names the joint
and field, e.g. ``five_bar.yaml: joint 'J3': field 'point': expected 2
numbers, got 3``.
"""

from __future__ import annotations

__all__ = [
    "MechanismDocument",
    "mechanism_from_dict",
    "mechanism_to_dict",
    "read",
    "load",
    "loads",
    "save",
    "FILE_SIZE_LIMIT",
    "DEPTH_LIMIT",
    "DIGITS_LIMIT",
    "read_text_file",
    "write_text_file",
    "parse_json",
]

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Optional

import yaml

from .errors import MechanismError
from .joints import COORDINATE_LIMIT, EndEffector, Joint, check_name, check_text, is_number
from .mechanism import Mechanism
from ._text import (  # the limits, read_text_file, write_text_file and parse_json are part of this module's API
    DEPTH_LIMIT, DIGITS_LIMIT, FILE_SIZE_LIMIT, _describe, _Dumper, _is_sequence, _json_text, _one_line, _parse_yaml,
    _path, parse_json, read_text_file, write_text_file,
)

_TOP_LEVEL_FIELDS = ("name", "space", "ground", "joints", "end_effector",
                     "description", "configurations")
_JOINT_FIELDS = ("name", "type", "links", "point", "axis", "axes", "actuated", "weight")
_END_EFFECTOR_FIELDS = ("link", "point", "output", "axis")
_FORMATS = {".json": "json", ".yaml": "yaml", ".yml": "yaml"}
#: joint type -> (number of displacement values or None for a single number, what they are)
_DISPLACEMENTS = {
    "R": (None, "an angle"),
    "P": (None, "a translation"),
    "S": (3, "a rotation vector"),
    "U": (2, "the two angles"),
    "C": (2, "angle and translation"),
}


@dataclass(frozen=True, eq=False)
class MechanismDocument:
    """The contents of a mechanism file.

    Parameters
    ----------
    mechanism : Mechanism
    configurations : dict of str to dict of str to (float or list of float)
        Named configurations: joint name -> displacement from home (a float
        for ``R``/``P``, a list of 3 floats for ``S``, of 2 for ``U``/``C``).
    description : str or None

    Notes
    -----
    Two documents are equal when their mechanisms agree field by field
    (name, space, ground, joints, end-effector) and their configurations and
    descriptions are equal; :class:`Mechanism` itself compares by identity.
    """

    mechanism: Mechanism
    configurations: dict = field(default_factory=dict)
    description: Optional[str] = None

    def __eq__(self, other):
        if not isinstance(other, MechanismDocument):
            return NotImplemented
        return (_mechanism_fields(self.mechanism) == _mechanism_fields(other.mechanism)
                and self.configurations == other.configurations
                and self.description == other.description)

    __hash__ = None


def mechanism_from_dict(data, source="mechanism file"):
    """Build a :class:`Mechanism` from the parsed contents of a mechanism file.

    Parameters
    ----------
    data : mapping
        The file's top-level mapping (as from ``yaml.safe_load`` or
        ``json.load``). ``description`` and ``configurations`` are validated
        (against the mechanism) but not returned; use :func:`loads` or
        :func:`read` to get them.
    source : str
        Where `data` came from; it starts every error message.

    Returns
    -------
    Mechanism

    Raises
    ------
    MechanismError
        With a one-line message naming the joint and field.

    Examples
    --------
    >>> slider = mechanism_from_dict({"name": "slider", "space": "planar", "joints": [
    ...     {"name": "S1", "type": "P", "links": ["ground", "block"], "axis": [1, 0]}]})
    >>> slider.joints[0].axis
    (1.0, 0.0)
    """
    return _document_from_dict(data, source).mechanism


def mechanism_to_dict(mechanism):
    """The file representation of a mechanism, ready for JSON or YAML.

    Optional fields at their defaults are left out (``ground: ground``,
    ``actuated: false``, ``weight: 1``, ``output: position``), so that
    ``mechanism_from_dict(mechanism_to_dict(m))`` equals `m` field by field.

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    dict
        Plain dicts, lists, strings, floats and booleans.
    """
    if not isinstance(mechanism, Mechanism):
        raise TypeError(f"expected a Mechanism, got {type(mechanism).__name__}")
    data = {"name": mechanism.name, "space": mechanism.space}
    if mechanism.ground != "ground":
        data["ground"] = mechanism.ground
    data["joints"] = [_joint_to_dict(joint) for joint in mechanism.joints]
    end_effector = mechanism.end_effector
    if end_effector is not None:
        entry = {"link": end_effector.link}
        if end_effector.point is not None:
            entry["point"] = list(end_effector.point)
        if end_effector.output != "position":
            entry["output"] = end_effector.output
        if end_effector.axis is not None:
            entry["axis"] = list(end_effector.axis)
        data["end_effector"] = entry
    return data


def read(path):
    """Read a mechanism file with its configurations and description.

    Parameters
    ----------
    path : str or os.PathLike
        ``.json`` is read as JSON, ``.yaml`` and ``.yml`` as YAML.

    Returns
    -------
    MechanismDocument

    Raises
    ------
    MechanismError
        When the file cannot be read or parsed, or its contents are invalid;
        the one-line message starts with the path.
    """
    path = _path(path)
    file_format = _format(path)
    return loads(read_text_file(path), file_format, source=str(path))


def load(path):
    """Read only the mechanism of a mechanism file: ``read(path).mechanism``.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    Mechanism

    Raises
    ------
    MechanismError
    """
    return read(path).mechanism


def loads(text, format="yaml", source="mechanism text"):
    """Parse the text of a mechanism file.

    Parameters
    ----------
    text : str
    format : {"yaml", "json"}
    source : str
        Where the text came from; it starts every error message.

    Returns
    -------
    MechanismDocument

    Raises
    ------
    MechanismError

    Examples
    --------
    >>> document = loads('''
    ... name: slider
    ... space: planar
    ... joints: [{name: S1, type: P, links: [ground, block], axis: [1, 0], actuated: true}]
    ... configurations: {pushed: {S1: 0.25}}
    ... ''')
    >>> document.mechanism.name, document.configurations
    ('slider', {'pushed': {'S1': 0.25}})
    """
    if format not in ("yaml", "json"):
        raise MechanismError(f"{source}: unknown format {format!r} (expected 'yaml' or 'json')")
    if not isinstance(text, str):
        raise MechanismError(f"{source}: expected text, got {type(text).__name__}")
    data = _parse_yaml(text, source) if format == "yaml" else parse_json(text, source)
    return _document_from_dict(data, source)


def save(mechanism, path, configurations=None, description=None):
    """Write a mechanism file that :func:`read` reads back identically.

    Parameters
    ----------
    mechanism : Mechanism
    path : str or os.PathLike
        ``.json`` writes JSON, ``.yaml`` or ``.yml`` writes YAML.
    configurations : mapping, optional
        Configuration name -> joint name -> displacement, as in
        :attr:`MechanismDocument.configurations`; validated against the
        mechanism before anything is written.
    description : str, optional

    Raises
    ------
    MechanismError
        When the path has an unknown extension, the configurations or the
        description are invalid, or the file cannot be written.
    """
    path = _path(path)
    file_format = _format(path)
    data = mechanism_to_dict(mechanism)
    if description is not None:
        data["description"] = description
    if configurations:
        data["configurations"] = configurations
    document = _document_from_dict(data, str(path))
    if document.configurations:
        data["configurations"] = document.configurations
    if file_format == "json":
        text = _json_text(data)
    else:
        text = yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=None,
                         allow_unicode=True)
    write_text_file(path, text)


# ---------------------------------------------------------------- from dicts

def _document_from_dict(data, source):
    try:
        return _parse_document(data)
    except MechanismError as error:
        raise MechanismError(_one_line(f"{source}: {error}")) from None


def _parse_document(data):
    if data is None:
        raise MechanismError("top level: expected a mapping, got an empty document")
    if not isinstance(data, Mapping):
        raise MechanismError(f"top level: expected a mapping, got {_describe(data)}")
    _check_keys(data, _TOP_LEVEL_FIELDS, "")
    for required in ("name", "space", "joints"):
        if required not in data:
            raise MechanismError(f"field {required!r}: missing")
    name = _string(data["name"], "field 'name'")
    space = _string(data["space"], "field 'space'")
    ground = _string(data["ground"], "field 'ground'") if "ground" in data else "ground"
    joints = data["joints"]
    if not isinstance(joints, (list, tuple)):
        raise MechanismError(f"field 'joints': expected a list of joints, got {_describe(joints)}")
    joints = [_joint_from_dict(entry, index) for index, entry in enumerate(joints)]
    end_effector = data.get("end_effector")
    if end_effector is not None:
        end_effector = _end_effector_from_dict(end_effector)
    mechanism = Mechanism(name, space, joints, ground=ground, end_effector=end_effector)
    description = data.get("description")
    if description is not None and not isinstance(description, str):
        raise MechanismError(f"field 'description': expected a string, got {_describe(description)}")
    if description is not None:
        check_text(description, "field 'description'")
    configurations = _configurations_from_dict(data.get("configurations"), mechanism)
    return MechanismDocument(mechanism, configurations, description)


def _joint_from_dict(data, index):
    if not isinstance(data, Mapping):
        raise MechanismError(f"field 'joints': item {index}: expected a mapping of joint fields, "
                             f"got {_describe(data)}")
    if "name" not in data:
        raise MechanismError(f"field 'joints': item {index}: field 'name': missing")
    name = _string(data["name"], f"field 'joints': item {index}: field 'name'")
    where = f"joint {name!r}"
    _check_keys(data, _JOINT_FIELDS, where)
    for required in ("type", "links"):
        if required not in data:
            raise MechanismError(f"{where}: field {required!r}: missing")
    joint_type = _string(data["type"], f"{where}: field 'type'")
    links = data["links"]
    if (not isinstance(links, (list, tuple)) or len(links) != 2
            or not all(isinstance(link, str) and link for link in links)):
        raise MechanismError(f"{where}: field 'links': expected two link names [first, second], "
                             f"got {_describe(links)}")
    for position, link in enumerate(links):
        check_name(link, f"{where}: field 'links': item {position}")
    fields = {}
    for vector in ("point", "axis"):
        if vector in data:
            fields[vector] = _numbers(data[vector], f"{where}: field '{vector}'")
    if "axes" in data:
        axes = data["axes"]
        if not _is_sequence(axes):
            raise MechanismError(f"{where}: field 'axes': expected a list of two axes "
                                 f"[first, second], got {_describe(axes)}")
        fields["axes"] = tuple(_numbers(axis, f"{where}: field 'axes[{position}]'")
                               for position, axis in enumerate(axes))
    if "actuated" in data:
        actuated = data["actuated"]
        if not isinstance(actuated, bool):
            raise MechanismError(f"{where}: field 'actuated': expected true or false, "
                                 f"got {_describe(actuated)}")
        fields["actuated"] = actuated
    if "weight" in data:
        fields["weight"] = _number(data["weight"], f"{where}: field 'weight'")
    return Joint(name, joint_type, tuple(links), **fields)


def _end_effector_from_dict(data):
    where = "end_effector"
    if not isinstance(data, Mapping):
        raise MechanismError(f"field 'end_effector': expected a mapping with 'link', 'point', "
                             f"'output' (and 'axis' for a tool), got {_describe(data)}")
    _check_keys(data, _END_EFFECTOR_FIELDS, where)
    if "link" not in data:
        raise MechanismError(f"{where}: field 'link': missing")
    link = _string(data["link"], f"{where}: field 'link'")
    point = _numbers(data["point"], f"{where}: field 'point'") if "point" in data else None
    output = _string(data["output"], f"{where}: field 'output'") if "output" in data else "position"
    axis = _numbers(data["axis"], f"{where}: field 'axis'") if "axis" in data else None
    return EndEffector(link, point, output, axis)


def _configurations_from_dict(data, mechanism):
    if data is None:
        return {}
    if not isinstance(data, Mapping):
        raise MechanismError(f"field 'configurations': expected a mapping from configuration "
                             f"names to joint displacements, got {_describe(data)}")
    joints = {joint.name: joint for joint in mechanism.joints}
    configurations = {}
    for name, displacements in data.items():
        if not isinstance(name, str) or not name:
            raise MechanismError(f"field 'configurations': expected configuration names to be "
                                 f"non-empty strings, got {_describe(name)}")
        check_name(name, f"field 'configurations': name {_describe(name)}")
        where = f"configurations[{name!r}]"
        if not isinstance(displacements, Mapping):
            raise MechanismError(f"{where}: expected a mapping from joint names to displacements, "
                                 f"got {_describe(displacements)}")
        configuration = {}
        for joint_name, value in displacements.items():
            joint_where = f"{where}: joint {joint_name!r}"
            if not isinstance(joint_name, str) or joint_name not in joints:
                raise MechanismError(f"{joint_where}: unknown joint")
            configuration[joint_name] = check_displacement(value, joints[joint_name], joint_where)
        configurations[name] = configuration
    return configurations


def check_displacement(value, joint, where):
    """A joint displacement checked against the joint type: a float, or a list of floats."""
    size, meaning = _DISPLACEMENTS[joint.type]
    if size is None:
        if _is_sequence(value):
            raise MechanismError(f"{where}: expected a number ({meaning} of the {joint.type} "
                                 f"joint), got {_describe(value)}")
        return _in_range(_number(value, where), where)
    if not _is_sequence(value):
        raise MechanismError(f"{where}: expected a list of {size} numbers ({meaning} of the "
                             f"{joint.type} joint), got {_describe(value)}")
    if len(value) != size:
        raise MechanismError(f"{where}: expected {size} numbers ({meaning} of the {joint.type} "
                             f"joint), got {len(value)}")
    return [_in_range(number, f"{where}: item {position}")
            for position, number in enumerate(_numbers(value, where))]


def _in_range(number, where):
    if abs(number) > COORDINATE_LIMIT:
        raise MechanismError(f"{where}: {number:g} is out of range (displacements are at most "
                             f"{COORDINATE_LIMIT:g} in absolute value)")
    return number


# ------------------------------------------------------------------ to dicts

def _joint_to_dict(joint):
    entry = {"name": joint.name, "type": joint.type, "links": list(joint.links)}
    if joint.point is not None:
        entry["point"] = list(joint.point)
    if joint.axis is not None:
        entry["axis"] = list(joint.axis)
    if joint.axes is not None:
        entry["axes"] = [list(axis) for axis in joint.axes]
    if joint.actuated:
        entry["actuated"] = True
    if joint.weight != 1.0:
        entry["weight"] = joint.weight
    return entry


def _mechanism_fields(mechanism):
    return (mechanism.name, mechanism.space, mechanism.ground, mechanism.joints,
            mechanism.end_effector)


# ------------------------------------------------------------ value checking

def _check_keys(data, allowed, where):
    for key in data:
        if key not in allowed:
            prefix = f"{where}: " if where else ""
            raise MechanismError(f"{prefix}unknown field {_describe(key)} "
                                 f"(expected one of {', '.join(allowed)})")


def _string(value, where):
    if not isinstance(value, str) or not value:
        raise MechanismError(f"{where}: expected a non-empty string, got {_describe(value)}")
    return check_name(value, where)


def _number(value, where):
    if not is_number(value):
        raise MechanismError(f"{where}: expected a number, got {_describe(value)}")
    try:
        number = float(value)
    except OverflowError:
        raise MechanismError(f"{where}: expected a finite number, got a number too large "
                             f"for a float") from None
    if not math.isfinite(number):
        raise MechanismError(f"{where}: expected a finite number, got {_describe(value)}")
    return number


def _numbers(values, where):
    if not _is_sequence(values):
        raise MechanismError(f"{where}: expected a list of numbers, got {_describe(values)}")
    checked = []
    for position, value in enumerate(values):
        if not is_number(value):
            raise MechanismError(f"{where}: item {position}: expected a number, "
                                 f"got {_describe(value)}")
        checked.append(_number(value, f"{where}: item {position}"))
    return tuple(checked)


def _format(path):
    file_format = _FORMATS.get(path.suffix.lower())
    if file_format is None:
        found = f"extension {path.suffix!r}" if path.suffix else "no extension"
        raise MechanismError(_one_line(f"{path}: unknown file format: {found} "
                                       f"(expected .json, .yaml or .yml)"))
    return file_format
