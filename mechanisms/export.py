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
importer finds it closed. URDF link and joint names are the mechanism's;
inertias are not written (kinematics only). URDF has no end-effector: it is
written as a link ``end_effector`` fixed to the end-effector's link with its
origin at the end-effector's point (the link's origin for an orientation),
and named in the closures file's ``end_effector`` key with its output (and a
``tool``'s ``axis``: the link frames are parallel to the ground's at home, so
the axis is written as it is).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from xml.etree import ElementTree

import numpy as np

from .closures import Closures, closures_to_dict

__all__ = ["Exported", "export_urdf", "write_urdf"]


@dataclass(frozen=True)
class Exported:
    """The URDF text and the closures of a mechanism."""

    urdf: str
    closures: Closures


def _spatial(mechanism, joint):
    """(point, axis, axes) of a joint in 3-D."""
    if mechanism.space == "planar":
        point = None if joint.point is None else (*joint.point, 0.0)
        if joint.type == "P":
            return None, (*joint.axis, 0.0), None
        return point, (0.0, 0.0, 1.0), None
    if mechanism.space == "spherical":
        return (0.0, 0.0, 0.0), joint.axis, None
    return joint.point, joint.axis, joint.axes


def _vector(values):
    return " ".join(repr(float(value)) for value in values)


def export_urdf(mechanism):
    """The URDF and closures of a mechanism (see the module's note).

    Parameters
    ----------
    mechanism : Mechanism

    Returns
    -------
    Exported
    """
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

    def write_joint(joint, parent, child):
        point, axis, axes = _spatial(mechanism, joint)
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
            names = [add_joint(f"{joint.name}_1", "revolute", parent, cross, here, first, made_up=True),
                     add_joint(f"{joint.name}_2", "revolute" if joint.type == "U" else "prismatic", cross, child,
                               here, second, made_up=True)]
        if joint.actuated:
            actuated.extend(names)

    add_link(mechanism.ground)
    placed, used = {mechanism.ground}, set()
    queue = deque([mechanism.ground])
    while queue:
        link = queue.popleft()
        for joint in mechanism.joints:
            if joint.name in used or link not in joint.links:
                continue
            other = joint.links[1] if joint.links[0] == link else joint.links[0]
            if other in placed:
                continue
            used.add(joint.name)
            placed.add(other)
            add_link(other)
            if joint.links[0] == link:
                write_joint(joint, link, other)
            else:  # traversed backwards: the same joint from its second link (values change sign)
                write_joint(_reversed(joint), link, other)
            queue.append(other)
    for joint in mechanism.joints:
        if joint.name in used:
            continue
        first, second = joint.links
        point, _, _ = _spatial(mechanism, joint)
        here = origins[first] if point is None else np.asarray(point, dtype=float)
        if joint.type == "S":
            sides = []
            for side, link in (("A", first), ("B", second)):
                frame = add_link(f"{joint.name}_{side}", made_up=True)
                add_joint(f"{joint.name}_{side}_frame", "fixed", link, frame, here, made_up=True)
                sides.append(frame)
            loops.append(tuple(sides))
            types.append("3d")
            continue
        leaf = add_link(f"{joint.name}_B", made_up=True)
        write_joint(joint, first, leaf)
        anchor = add_link(f"{joint.name}_A", made_up=True)
        add_joint(f"{anchor}_frame", "fixed", second, anchor, origins[leaf], made_up=True)
        loops.append((leaf, anchor))
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
    return Exported(text, Closures(tuple(loops), tuple(types), tuple(actuated), retyped, effector, effector_axis))


def _reversed(joint):
    """The joint seen from its second link: R, P, C axes reversed; a U's axes swapped (and reversed)."""
    from dataclasses import replace

    links = tuple(reversed(joint.links))
    if joint.axis is not None:
        return replace(joint, links=links, axis=tuple(-value for value in joint.axis))
    if joint.axes is not None:
        return replace(joint, links=links, axes=(tuple(-v for v in joint.axes[1]), tuple(-v for v in joint.axes[0])))
    if joint.type == "R":  # planar: reversing the rotation is not needed for the geometry (axis +z either way)
        return replace(joint, links=links)
    return replace(joint, links=links)


def write_urdf(mechanism, path, closures_path):
    """Write the URDF of a mechanism to `path` and its closures file (YAML) to `closures_path`."""
    import yaml

    from ._text import write_text_file

    exported = export_urdf(mechanism)
    write_text_file(path, exported.urdf)
    write_text_file(closures_path, yaml.safe_dump(closures_to_dict(exported.closures), sort_keys=False,
                                                  default_flow_style=None))
    return exported
