"""A mechanism as a URDF and its closures file (the convention read by :mod:`mechanisms.urdf`), for Pinocchio.

The joint graph is cut into a tree grown breadth-first from the ground
(joints in file order, as :mod:`mechanisms.kinematics` grows its spanning
tree); every remaining joint (a chord) closes a loop:

* a chord ``S`` joint becomes a ``3d`` closure between two frames at its
  centre, one fixed on each of its links (links ``<joint>_A``, ``<joint>_B``
  joined by ``fixed`` joints);
* any other chord is written as a tree joint from its first link to a new
  leaf link ``<joint>_B``, welded (``6d``) to a frame ``<joint>_A`` fixed on
  its second link, coinciding at home.

Every link frame is parallel to the ground frame at home, with its origin at
the point of the joint that carries it (the origin of its parent's frame for
a ``P`` joint). ``R`` and ``P`` joints are ``revolute`` and ``prismatic``
with wide limits (±1000); ``S`` is a ``revolute`` re-typed
``SPHERICAL`` in the closures file; ``U`` and ``C`` are two joints,
``<joint>_1`` and ``<joint>_2``, through a link ``<joint>_cross`` (a ``U``
about its first then its second axis; a ``C`` turning then sliding). A
planar mechanism is drawn in the plane z = 0 (axes +z), a spherical one about
the origin. The URDF's zero configuration is the mechanism's home, so the
importer finds it closed.

Joint values are kept: a joint the tree reaches from its second link is
written from that link with its axis reversed (−z for a planar ``R``), so
that its URDF value is the mechanism's joint value (the motion of the second
listed link relative to the first); a ``U`` so reached turns about its
second axis first, and its two URDF joints are named so that ``<joint>_1``
still carries the angle about the first axis and ``<joint>_2`` the other.
Only an ``S`` so reached cannot keep them (a ball joint has no axis to
reverse): it comes back with its links listed the other way, as every joint
so reached does, and its rotation vector negated. The tree is therefore
grown through the other joints first, so that the ball joints close the
loops wherever they can (written as ``3d`` closures, as they are): then a
second round trip keeps every joint as the first gave it.

URDF link and joint names are the mechanism's, and every name must be text
XML 1.0 can hold (no control character but tab, newline and carriage return):
another is refused, naming the joint or link and the field. A chord ``S``
joint named ``A--B`` (the name the importer gives a ``3d`` closure between
frames ``A`` and ``B``) is written with the frames ``A`` and ``B`` when
these names are free, and a welded chord's pair is written ``[<joint>_A,
<joint>_B]`` (the importer names the welded link after the first frame's
link, the chord's second link): a mechanism read from an exported URDF
exports and imports again with the same names.

Inertias are not written (kinematics only), and neither are the joints'
weights, a file's named configurations and its description, which URDF and
the closures file have no place for: :attr:`Exported.notes` names what was
left out. URDF has no end-effector: it is
written as a link ``end_effector`` fixed to the end-effector's link with its
origin at the end-effector's point (the link's origin for an orientation),
and named in the closures file's ``end_effector`` key with its output (and a
``tool``'s ``axis``: the link frames are parallel to the ground's at home, so
the axis is written as it is).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from .closures import Closures, closures_to_dict
from .errors import MechanismError

__all__ = ["Exported", "export_urdf", "write_urdf", "left_out"]


@dataclass(frozen=True)
class Exported:
    """The URDF text and the closures of a mechanism.

    Attributes
    ----------
    urdf : str
    closures : Closures
    notes : tuple of str
        What the pair does not hold and was left out: joint weights other than 1 (naming the joints), the
        named configurations, the description.
    """

    urdf: str
    closures: Closures
    notes: tuple = ()


def _xml_fault(text):
    """The first character of `text` that XML 1.0 cannot hold (its ``Char`` production), or None."""
    for character in text:
        code = ord(character)
        if not (code in (0x9, 0xA, 0xD) or 0x20 <= code <= 0xD7FF or 0xE000 <= code <= 0xFFFD
                or 0x10000 <= code <= 0x10FFFF):
            return character
    return None


def _check_names(mechanism):
    """Refuse a name that a URDF cannot hold, naming the joint or link and the field (before anything is written).

    Raises
    ------
    MechanismError
    """
    def check(where, name, what):
        character = _xml_fault(name)
        if character is not None:
            raise MechanismError(f"{where}: the character U+{ord(character):04X} cannot be written in a URDF (XML 1.0 "
                                 f"cannot hold it): rename the {what}")

    check(f"field 'name': {mechanism.name!r}", mechanism.name, "mechanism")
    check(f"field 'ground': {mechanism.ground!r}", mechanism.ground, "ground link")
    for joint in mechanism.joints:
        check(f"joint {joint.name!r}: field 'name'", joint.name, "joint")
        for link in joint.links:
            check(f"joint {joint.name!r}: field 'links': link {link!r}", link, "link")


def _number(value):
    return f"{value:.15g}"


def left_out(mechanism, configurations=None, description=None):
    """What a URDF and its closures file cannot hold of a mechanism (and its file), one note each.

    Parameters
    ----------
    mechanism : Mechanism
    configurations : mapping, optional
        The named configurations of its file (name → displacements).
    description : str, optional
        The description of its file.

    Returns
    -------
    tuple of str
        Joint weights other than 1 (naming the joints and their weights), the named configurations (naming
        them), the description.
    """
    notes = []
    weighted = [joint for joint in mechanism.joints if joint.weight != 1.0]
    if weighted:
        shown = ", ".join(f"{joint.name} ({_number(joint.weight)})" for joint in weighted[:12])
        more = f" and {len(weighted) - 12} more" if len(weighted) > 12 else ""
        notes.append(f"not written (a URDF and its closures file hold no joint weights): the weights of {shown}"
                     f"{more}; read back, every joint weighs 1: the same kinds, other proper values (λ)")
    if configurations:
        names = list(configurations)
        shown = ", ".join(names[:12]) + (f" and {len(names) - 12} more" if len(names) > 12 else "")
        notes.append(f"not written (a URDF and its closures file hold no named configurations): the "
                     f"configuration(s) {shown}")
    if description:
        notes.append("not written (a URDF and its closures file hold no description): the description")
    return tuple(notes)


def _spatial(mechanism, joint, reverse=False):
    """(point, axis, axes) of a joint in 3-D; with `reverse`, as seen from its second link, its values kept: the
    axis reversed (−z for a planar R), a U's axes swapped and reversed."""
    if mechanism.space == "planar":
        point = None if joint.point is None else (*joint.point, 0.0)
        axis, axes = ((*joint.axis, 0.0) if joint.type == "P" else (0.0, 0.0, 1.0)), None
        if joint.type == "P":
            point = None
    elif mechanism.space == "spherical":
        point, axis, axes = (0.0, 0.0, 0.0), joint.axis, None
    else:
        point, axis, axes = joint.point, joint.axis, joint.axes
    if reverse:
        if axis is not None:
            axis = tuple(-value for value in axis)
        if axes is not None:
            axes = (tuple(-value for value in axes[1]), tuple(-value for value in axes[0]))
    return point, axis, axes


def _vector(values):
    return " ".join(repr(float(value)) for value in values)


def export_urdf(mechanism, configurations=None, description=None):
    """The URDF and closures of a mechanism (see the module's note).

    Parameters
    ----------
    mechanism : Mechanism
    configurations : mapping, optional
        The named configurations of its file: not written, named in the notes.
    description : str, optional
        The description of its file: not written, said in the notes.

    Returns
    -------
    Exported

    Raises
    ------
    MechanismError
        A name XML 1.0 cannot hold (a control character), naming the joint or link and the field.
    """
    _check_names(mechanism)
    robot = ElementTree.Element("robot", name=mechanism.name)
    origins = {mechanism.ground: np.zeros(3)}
    links = [mechanism.ground]
    actuated, retyped, loops, types = [], {}, [], []
    # names made up here never take one the mechanism has (a mechanism read from an exported URDF has links
    # named P_B, P_A, end_effector...): a made-up name gets "_" appended until it is free
    taken_links, taken_joints = set(mechanism.links), {joint.name for joint in mechanism.joints}

    def fresh(name, taken):
        while name in taken:
            name += "_"
        taken.add(name)
        return name

    def add_link(name, made_up=False):
        name = fresh(name, taken_links) if made_up else name
        ElementTree.SubElement(robot, "link", name=name)
        links.append(name)
        return name

    def add_joint(name, kind, parent, child, origin, axis=None, made_up=False):
        name = fresh(name, taken_joints) if made_up else name
        element = ElementTree.SubElement(robot, "joint", name=name, type=kind)
        ElementTree.SubElement(element, "origin", xyz=_vector(origin - origins[parent]), rpy="0 0 0")
        ElementTree.SubElement(element, "parent", link=parent)
        ElementTree.SubElement(element, "child", link=child)
        if axis is not None:
            ElementTree.SubElement(element, "axis", xyz=_vector(np.asarray(axis) / np.linalg.norm(axis)))
        if kind in ("revolute", "prismatic"):
            ElementTree.SubElement(element, "limit", lower="-1e3", upper="1e3", effort="1", velocity="1")
        origins[child] = np.asarray(origin, dtype=float)
        return name

    def write_joint(joint, parent, child, reverse=False):
        point, axis, axes = _spatial(mechanism, joint, reverse)
        here = origins[parent] if point is None else np.asarray(point, dtype=float)
        if joint.type in ("R", "P"):
            add_joint(joint.name, "revolute" if joint.type == "R" else "prismatic", parent, child, here, axis)
            names = [joint.name]
        elif joint.type == "S":
            add_joint(joint.name, "revolute", parent, child, here, (0.0, 0.0, 1.0))
            retyped[joint.name] = "SPHERICAL"
            names = []
        else:
            cross = add_link(f"{joint.name}_cross", made_up=True)
            first, second = (axes if joint.type == "U" else (axis, axis))
            # a U seen from its second link turns about its second axis first: its URDF joints are named so
            # that <joint>_1 carries the angle about the first axis (a C's turn and slide commute)
            labels = ("_2", "_1") if reverse and joint.type == "U" else ("_1", "_2")
            names = [add_joint(f"{joint.name}{labels[0]}", "revolute", parent, cross, here, first, made_up=True),
                     add_joint(f"{joint.name}{labels[1]}", "revolute" if joint.type == "U" else "prismatic", cross,
                               child, here, second, made_up=True)]
            if reverse and joint.type == "U":
                names.reverse()
        if joint.actuated:
            actuated.extend(names)

    add_link(mechanism.ground)
    placed, used = {mechanism.ground}, set()
    def place(joint, link, other):
        used.add(joint.name)
        placed.add(other)
        add_link(other)
        # traversed backwards: the same joint from its second link, axes reversed (its values kept)
        write_joint(joint, link, other, reverse=joint.links[0] != link)
        queue.append(other)

    # the tree: breadth first through every joint but the S joints, which close the loops where they can (a ball
    # joint in the tree reached from its second link cannot keep its values; as a closure it is written as is)
    queue = deque([mechanism.ground])
    while True:
        while queue:
            link = queue.popleft()
            for joint in mechanism.joints:
                if joint.type == "S" or joint.name in used or link not in joint.links:
                    continue
                other = joint.links[1] if joint.links[0] == link else joint.links[0]
                if other not in placed:
                    place(joint, link, other)
        ball = next((joint for joint in mechanism.joints if joint.type == "S" and joint.name not in used
                     and (joint.links[0] in placed) != (joint.links[1] in placed)), None)
        if ball is None:
            break
        link = ball.links[0] if ball.links[0] in placed else ball.links[1]
        place(ball, link, ball.links[1] if link == ball.links[0] else ball.links[0])
    for joint in mechanism.joints:
        if joint.name in used:
            continue
        first, second = joint.links
        point, _, _ = _spatial(mechanism, joint)
        here = origins[first] if point is None else np.asarray(point, dtype=float)
        if joint.type == "S":
            sides = []
            for side, link, frame in zip("AB", (first, second), _ball_frames(joint.name, taken_links)):
                frame = add_link(frame or f"{joint.name}_{side}", made_up=True)
                add_joint(f"{frame}_frame", "fixed", link, frame, here, made_up=True)
                sides.append(frame)
            loops.append(tuple(sides))
            types.append("3d")
            continue
        leaf = add_link(f"{joint.name}_B", made_up=True)
        write_joint(joint, first, leaf)
        anchor = add_link(f"{joint.name}_A", made_up=True)
        add_joint(f"{anchor}_frame", "fixed", second, anchor, origins[leaf], made_up=True)
        loops.append((anchor, leaf))  # the welded link is named after the first frame's link: the chord's second
        types.append("6d")
    effector, effector_axis = None, None
    if mechanism.end_effector is not None:
        link = mechanism.end_effector.link
        point = mechanism.end_effector.point
        here = origins[link] if point is None else np.array([*point, 0.0][:3])
        frame = add_link("end_effector", made_up=True)
        add_joint(f"{frame}_frame", "fixed", link, frame, here, made_up=True)
        effector, effector_axis = (frame, mechanism.end_effector.output), mechanism.end_effector.axis
    ElementTree.indent(robot)
    text = ElementTree.tostring(robot, encoding="unicode") + "\n"
    return Exported(text, Closures(tuple(loops), tuple(types), tuple(actuated), retyped, effector, effector_axis),
                    left_out(mechanism, configurations, description))


def _ball_frames(name, taken):
    """The two frames of a chord S joint named ``A--B`` (as the importer names a ``3d`` closure between frames A
    and B): (A, B) at the first ``--`` that gives two free, different names; else (None, None), made-up names."""
    start = name.find("--")
    while start > 0:
        first, second = name[:start], name[start + 2:]
        if second and first != second and first not in taken and second not in taken:
            return first, second
        start = name.find("--", start + 1)
    return None, None


def write_urdf(mechanism, path, closures_path, configurations=None, description=None):
    """Write the URDF of a mechanism to `path` and its closures file (YAML) to `closures_path`.

    Nothing is written when the mechanism cannot be exported (a name XML cannot hold); `configurations` and
    `description` (of its file) are not written, and named in the notes (:func:`export_urdf`)."""
    import yaml

    from ._text import write_text_file

    exported = export_urdf(mechanism, configurations, description)
    closures = yaml.safe_dump(closures_to_dict(exported.closures), sort_keys=False, default_flow_style=None)
    try:
        before = Path(path).read_bytes() if Path(path).is_file() else None
    except OSError:
        before = None
    write_text_file(path, exported.urdf)
    try:
        write_text_file(closures_path, closures)
    except MechanismError:  # no URDF without its closures: the file is put back as it was
        try:
            if before is None:
                Path(path).unlink()
            else:
                Path(path).write_bytes(before)
        except OSError:
            pass
        raise
    return exported
