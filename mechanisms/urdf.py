"""URDF with loop closures → :class:`~mechanisms.mechanism.Mechanism`, assembled.

A URDF is a tree of links and joints; the loops of a parallel robot are cut
open and listed beside it (:mod:`mechanisms.closures`). Import goes in four
steps:

1. **Read** the URDF with ``yourdfpy`` (meshes are never loaded; a
   ``<!DOCTYPE>`` or ``<!ENTITY>`` is refused) and check it is a tree: every
   joint's links exist, every link has at most one parent joint, one root.
2. **Normalise** the joints (:class:`KinematicTree`): ``revolute`` and
   ``continuous`` are ``R``, ``prismatic`` is ``P``, ``fixed`` joints are
   merged into their parent link; a ``floating`` joint from the root link
   is held fixed (the floating base of a legged robot), and the root link is
   the ground — both stated in the notes. A ``planar`` joint, a ``floating``
   joint elsewhere and a ``<mimic>`` joint on a loop are refused, naming the
   joint (a mimic joint on no loop is left out with the rest of its
   dangling chain). The closures file may re-type a joint: ``SPHERICAL``
   (a ball joint at the joint origin), ``FIXED``, ``UJOINT_AB`` (a revolute
   about the joint frame's axis A, then one about its moved axis B); the
   older files' ``rotule_name`` re-types by name pattern, and a ``name_mot``
   entry that names no joint actuates the movable joints whose names contain
   it, as the collection's loader reads them (:mod:`mechanisms.closures`;
   the notes say so).
3. **Assemble**: a URDF's zero configuration rarely closes the loops. The
   closure map (per loop: for ``6d`` the rotation vector of
   :math:`R_A^{\\mathsf T} R_B` and :math:`R_A^{\\mathsf T}(p_B - p_A)/L`;
   for ``3d`` the second part only; L the characteristic length of the tree;
   both in frame A's coordinates, as Pinocchio's ``LOCAL`` contacts) is
   driven to zero from the zero configuration by the framework's
   Gauss–Newton projection (:func:`manifold.project`, minimum-norm steps), so
   the configuration reached is the closed one nearest the zero
   configuration. In frame A's coordinates the map does not change when a
   joint that carries both frames moves (a humanoid's hip above its knee
   linkage), so such joints stay at zero.
   The distance moved (dimensionless joint coordinates) and the residual are
   reported; where the loops cannot be closed the error names the loops
   with the largest residuals.
4. **Build** the mechanism at the closed configuration, its home: each
   joint's point and axes in the ground frame there; a ``6d`` closure welds
   the two links into one (the mechanism's link keeps the first link's
   name); a ``3d`` closure is an ``S`` joint at the common origin. Joints on
   no loop (a dangling chain that moves nothing of the loops) are left out
   and named in the notes, as are joints locked by a weld.

Frame names resolve as Pinocchio's ``Model.getFrameId`` does for a model
built from the URDF: a link's name is its frame, a joint's name is the frame
of its child link at the joint (the two coincide).

The tree representation and the assembly (:func:`import_tree`) serve MJCF
too (:mod:`mechanisms.mjcf`).
"""

from __future__ import annotations

import io
import os
import warnings
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .closures import Closures, read_closures, universal_axes
from .errors import MechanismError
from .joints import EndEffector, Joint
from .mechanism import Mechanism

__all__ = ["TreeJoint", "KinematicTree", "Imported", "read_urdf", "tree_from_urdf", "import_tree", "retype",
           "looks_like_urdf", "ASSEMBLY_TOLERANCE", "URDF_SIZE_LIMIT"]

#: largest residual of the dimensionless closure map accepted at the assembled configuration
ASSEMBLY_TOLERANCE = 1e-9
#: largest URDF file read (bytes): URDFs carry inertias and visuals, so more than a mechanism file's 1 MiB
URDF_SIZE_LIMIT = 16 * 2 ** 20
#: largest Gauss–Newton step while assembling (dimensionless: radians, lengths over L)
_MAX_STEP = 0.5
_ITERATIONS = 200
#: how many loops an assembly failure names
_NAMED_LOOPS = 3
_COORDINATES = {"R": ("S1",), "P": ("R",), "S": ("SO3",), "U": ("S1", "S1")}


@dataclass(frozen=True, eq=False)
class TreeJoint:
    """One joint of a kinematic tree.

    Parameters
    ----------
    name : str
    type : {"R", "P", "S", "U", "fixed"}
    parent, child : str
        Link names; the joint moves `child` relative to `parent`.
    placement : ndarray, shape=[4, 4]
        The joint frame in the parent link's frame at zero.
    axes : tuple of ndarray, shape=[3]
        Unit axes in the joint frame: one for R and P, two for U (the
        second moved by the first rotation), none for S and fixed.
    child_offset : ndarray, shape=[4, 4], optional
        The child link's frame in the moved joint frame (identity for URDF).
    """

    name: str
    type: str
    parent: str
    child: str
    placement: np.ndarray
    axes: tuple = ()
    child_offset: np.ndarray = None


@dataclass(frozen=True, eq=False)
class KinematicTree:
    """A tree of links and joints, with named frames.

    Parameters
    ----------
    name : str
    root : str
        The fixed link.
    links : tuple of str
    joints : tuple of TreeJoint
        Each link but the root is the child of exactly one.
    frames : dict
        Frame name → (link, ndarray [4, 4] pose in the link frame), for names
        that are not link names (a link's own frame is the identity on it).
    notes : tuple of str
        What reading the source decided (a fixed floating base, ignored tags).
    mimics : tuple of str
        The joints with a URDF ``<mimic>`` tag: a coupling of joint values that is not a loop closure. They may
        only be on no loop (left out); on a loop the import is refused.
    """

    name: str
    root: str
    links: tuple
    joints: tuple
    frames: dict = field(default_factory=dict)
    notes: tuple = ()
    mimics: tuple = ()

    def frame(self, name, where):
        """(link, pose in the link's frame) of a frame name; MechanismError naming `where` if unknown."""
        if name in self.frames:
            return self.frames[name]
        if name in self.links:
            return name, np.eye(4)
        known = sorted(set(self.links) | set(self.frames))
        shown = ", ".join(known[:12]) + (", ..." if len(known) > 12 else "")
        raise MechanismError(f"{where}: unknown frame {name!r} (no link or joint of that name; known: {shown})")


@dataclass(frozen=True, eq=False)
class Imported:
    """A tree with closures, assembled and built as a mechanism.

    Attributes
    ----------
    mechanism : Mechanism
        Its home is the closed configuration reached.
    notes : tuple of str
        What the import decided (fixed base, merged and dropped joints, welds).
    distance : float
        Dimensionless length (radians; lengths over L) of the displacement
        from the zero configuration to the closed one.
    residual : float
        Norm of the dimensionless closure map at the closed configuration.
    values : dict
        Joint name → its value at the closed configuration in the source's
        coordinates (angle or length; two angles for U; a 3×3 rotation matrix
        for S, relative to the joint frame).
    loop_residuals : tuple of float
        Per closure, the norm of its rows there.
    tree : KinematicTree
    closures : Closures
    description : str
        The source and the notes, for a mechanism file's ``description``.
    """

    mechanism: Mechanism
    notes: tuple
    distance: float
    residual: float
    values: dict
    loop_residuals: tuple
    tree: KinematicTree
    closures: Closures
    description: str = ""

    def to_dict(self):
        """The JSON-ready account of the import (``closedchain classify`` prints it as ``import``)."""
        return {"assembly_distance": self.distance, "assembly_residual": self.residual,
                "loops": len(self.closures.loops), "notes": list(self.notes)}


# ----------------------------------------------------------------------------------------------- geometry

_IDENTITY_3 = np.eye(3)
_IDENTITY_4 = np.eye(4)


def _rotation(axis, angle):
    """Rotation matrix about a unit axis (Rodrigues)."""
    x, y, z = axis
    skew = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return _IDENTITY_3 + np.sin(angle) * skew + (1.0 - np.cos(angle)) * (skew @ skew)


def _homogeneous(rotation=None, translation=None):
    matrix = _IDENTITY_4.copy()
    if rotation is not None:
        matrix[:3, :3] = rotation
    if translation is not None:
        matrix[:3, 3] = translation
    return matrix


def _unit(axis, where):
    axis = np.asarray(axis, dtype=float)
    norm = np.linalg.norm(axis)
    if axis.shape != (3,) or not np.all(np.isfinite(axis)) or norm < 1e-12:
        raise MechanismError(f"{where}: field 'axis': expected a nonzero finite 3-vector, got {axis.tolist()}")
    return axis / norm


# ----------------------------------------------------------------------------------------------- URDF

def _check_tree(links, joints, source):
    """Refuse missing links, a link with two parents, no root or several roots, and cycles."""
    names = set(links)
    parent_of = {}
    for joint in joints:
        for role, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in names:
                raise MechanismError(f"{source}: joint {joint.name!r}: field '{role}': unknown link {link!r}")
        if joint.child in parent_of:
            raise MechanismError(f"{source}: joint {joint.name!r}: field 'child': link {joint.child!r} already has "
                                 f"the parent joint {parent_of[joint.child]!r} (a URDF is a tree; cut the loop and "
                                 f"list it in the closures file)")
        parent_of[joint.child] = joint.name
    roots = [link for link in links if link not in parent_of]
    if not roots:
        raise MechanismError(f"{source}: the joints form a cycle: no link is without a parent joint")
    children = {}
    for joint in joints:
        children.setdefault(joint.parent, []).append(joint.child)
    seen, queue = {roots[0]}, deque([roots[0]])
    while queue:
        for child in children.get(queue.popleft(), ()):
            if child not in seen:
                seen.add(child)
                queue.append(child)
    unreached = [link for link in links if link not in seen]
    if unreached:
        if len(roots) > 1:
            raise MechanismError(f"{source}: several root links {roots[:6]} (a URDF has one root; is a joint "
                                 f"missing?)")
        raise MechanismError(f"{source}: the joints form a cycle through link {unreached[0]!r}")
    return roots[0]


def _parse_urdf(text, source):
    """The yourdfpy robot of a URDF text, with every parser error as one MechanismError line."""
    lowered = text.lower()  # the whole text (a DOCTYPE after a long comment set attribute defaults unseen)
    if "<!doctype" in lowered or "<!entity" in lowered:
        raise MechanismError(f"{source}: URDF: a <!DOCTYPE> or <!ENTITY> declaration is not accepted")
    import logging

    import yourdfpy  # imported when used: it imports trimesh

    logging.getLogger("yourdfpy").setLevel(logging.CRITICAL)
    reason = _diagnosis(text)  # the parser recovers from broken XML: refuse it first
    if reason is not None:
        raise MechanismError(f"{source}: URDF: cannot parse: {reason}"[:400])
    try:
        # an infinite rpy (refused later, naming the joint; in a visual, never read) made trimesh's euler_matrix
        # print numpy's RuntimeWarnings: the parser's warnings are not the user's
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            model = yourdfpy.URDF.load(io.BytesIO(text.encode("utf-8")), build_scene_graph=False, load_meshes=False,
                                       build_collision_scene_graph=False, load_collision_meshes=False)
    except Exception as error:  # the parser's own errors (lxml, ValueError, KeyError...), wrapped in one line
        reason = " ".join(str(error).split()) or type(error).__name__
        raise MechanismError(f"{source}: URDF: cannot parse: {reason}"[:400]) from None
    return model.robot


#: deepest nesting of elements read (lxml's limit, beyond which the parser recovers with what it has read)
NESTING_LIMIT = 256
#: per URDF element, the attributes and sub-elements (with their attribute) that the kinematics needs
_REQUIRED = {"link": (("name",), ()), "joint": (("name", "type"), (("parent", "link"), ("child", "link")))}


def _diagnosis(text):
    """What makes a text no URDF, in the file's own terms (None when nothing does): not well-formed XML (which the
    parser would recover from, reading what it can), a root element other than ``<robot>``, a xacro file, a link
    or joint without a required attribute or sub-element. The DOCTYPE and ENTITY declarations were refused
    before.
    """
    from xml.etree import ElementTree

    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as error:
        return f"not well-formed XML ({error})"
    if root.tag != "robot":
        return f"the root element is <{root.tag}>, not <robot> (is this a URDF file?)"
    depth, level = 0, [(root, 1)]
    while level and depth <= NESTING_LIMIT:  # the parser reads no deeper, and said only "no link"
        element, depth = level.pop()
        level.extend((child, depth + 1) for child in element)
    if depth > NESTING_LIMIT:
        return f"elements nested more than {NESTING_LIMIT} deep (the URDF parser reads no deeper)"
    if "xmlns:xacro" in text or any("${" in value for element in root.iter() for value in element.attrib.values()):
        return "a xacro file (macros, ${...} expressions): expand it first, e.g. `xacro robot.urdf.xacro > robot.urdf`"
    if not root.get("name"):
        return "<robot>: attribute 'name' is missing"
    for element in root:
        if element.tag not in _REQUIRED:
            continue
        attributes, children = _REQUIRED[element.tag]
        label = f"<{element.tag}> {element.get('name')!r}" if element.get("name") else f"a <{element.tag}>"
        for attribute in attributes:
            if not element.get(attribute):
                return f"{label}: attribute '{attribute}' is missing"
        for child, attribute in children:
            found = element.find(child)
            if found is None or not found.get(attribute):
                return f"{label}: <{child} {attribute}=\"...\"/> is missing"
        for part in element.iter():
            for attribute in _VECTORS.get(part.tag, ()):
                value = part.get(attribute)
                reason = None if value is None else _vector_fault(value)
                if reason is not None:
                    return f"{label}: <{part.tag} {attribute}={value[:40]!r}>: {reason}"
    return None


#: the attributes of three numbers, per element (in joints, links' inertial, visual and collision)
_VECTORS = {"origin": ("xyz", "rpy"), "axis": ("xyz",)}


def _vector_fault(text):
    """What is wrong with `text` as three numbers separated by spaces, or None (the words inf and nan pass:
    they are refused later, naming the joint), beyond ±COORDINATE_LIMIT included (as in a mechanism file)."""
    from ._numerals import Underflow, decimal_number, is_word
    from .joints import COORDINATE_LIMIT

    parts = text.split()
    try:
        values = [decimal_number(item) for item in parts]
    except ValueError as error:
        if isinstance(error, Underflow):
            return str(error)
        values = None
    if values is None or len(values) != 3:
        return "expected three numbers"
    if any(abs(value) > COORDINATE_LIMIT for value, item in zip(values, parts) if not is_word(item)):
        return f"a number beyond ±{COORDINATE_LIMIT:g} (as in a mechanism file)"  # 1e400 and 5000 digits too
    return None


def looks_like_urdf(path):
    """Whether an XML file's root element is ``<robot>`` (a URDF saved as ``.xml``), from its first 64 KiB.

    The file is opened without blocking and read only when it is a regular file: False for a FIFO, a device or a
    folder (which the reader then refuses, :func:`mechanisms.io.read_text_file`), and for a path that cannot be
    opened.
    """
    import re
    import stat

    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError):
        return False
    try:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):
            return False
        with os.fdopen(descriptor, "rb") as stream:
            descriptor = None
            head = stream.read(65536).decode("utf-8", errors="replace")
    except OSError:
        return False
    finally:
        if descriptor is not None:
            os.close(descriptor)
    head = re.sub(r"<!--.*?-->|<\?.*?\?>", "", head, flags=re.DOTALL)
    match = re.search(r"<\s*([A-Za-z_][\w.:-]*)", head)
    return match is not None and match.group(1) == "robot"


def tree_from_urdf(text, source="URDF"):
    """The kinematic tree of a URDF text (fixed joints kept; see :func:`import_tree`).

    Parameters
    ----------
    text : str
    source : str
        Starts every error message.

    Returns
    -------
    KinematicTree
    """
    robot = _parse_urdf(text, source)
    links = tuple(link.name for link in robot.links)
    if not links:
        raise MechanismError(f"{source}: URDF: no link")
    seen = set()
    for link in links:
        if link in seen:
            raise MechanismError(f"{source}: link {link!r}: two <link> elements have this name (link names must be "
                                 f"unique: rename one, and the joints that name it)")
        seen.add(link)
    joints, notes, mimics = [], [], []
    for joint in robot.joints:
        where = f"{source}: joint {joint.name!r}"
        if joint.name in {other.name for other in joints}:
            raise MechanismError(f"{where}: duplicate joint name")
        placement = np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)
        if placement.shape != (4, 4) or not np.all(np.isfinite(placement)):
            raise MechanismError(f"{where}: field 'origin': not a finite pose")
        if joint.type in ("revolute", "continuous", "prismatic"):
            axis = _unit(np.array([1.0, 0.0, 0.0]) if joint.axis is None else joint.axis, where)
            kind, axes = ("P" if joint.type == "prismatic" else "R"), (axis,)
        elif joint.type in ("fixed", "floating"):
            kind, axes = "fixed", ()
        else:
            raise MechanismError(f"{where}: field 'type': a {joint.type!r} joint is not supported (revolute, "
                                 f"continuous, prismatic, fixed; floating only for the base)")
        if getattr(joint, "mimic", None) is not None:
            mimics.append(joint.name)
        joints.append(TreeJoint(joint.name, kind, joint.parent, joint.child, placement, axes))
    root = _check_tree(links, joints, source)
    notes.insert(0, f"base link {root!r} fixed as the ground (a floating base is held fixed)")
    for joint in robot.joints:
        if joint.type != "floating":
            continue
        if joint.parent != root:
            raise MechanismError(f"{source}: joint {joint.name!r}: field 'type': a floating joint inside the tree "
                                 f"(its parent {joint.parent!r} is not the base link {root!r}) is not supported: "
                                 f"a free body is not a mechanism's link")
        notes.append(_floating_note(joint.name))
    frames = {joint.name: (joint.child, np.eye(4)) for joint in joints if joint.name not in links}
    return KinematicTree(robot.name or "robot", root, links, tuple(joints), frames, tuple(notes),
                         tuple(mimics))


def _floating_note(name, retyped=None):
    """The note of a floating base joint: held fixed, or `retyped` by the closures file (:func:`retype`)."""
    said = "held fixed" if retyped is None else f"re-typed {retyped} by the closures file"
    return f"floating joint {name!r} (the floating base) {said}"


def retype(tree, closures, source="closures file"):
    """The tree with the closures file's ``joint_name``/``joint_type`` re-typings applied.

    ``SPHERICAL``: a ball joint at the joint origin; ``FIXED``: merged;
    ``UJOINT_AB``: a universal joint about the joint frame's axes A then B.
    The older files' ``rotule_name`` pattern (:attr:`Closures.spherical_pattern`)
    re-types as ``SPHERICAL`` every revolute or prismatic joint whose name
    contains it and that ``joint_name`` does not re-type, as their loader did;
    the notes name them. A ``joint_name`` that names no joint is skipped, as
    the collection's loader skips it (it re-types the model's joints whose
    names are listed), and named in the notes, never silently.
    """
    by_name = {joint.name: joint for joint in tree.joints}
    retyped = {name: joint_type for name, joint_type in closures.retyped.items() if name in by_name}
    notes = []
    unknown = [name for name in closures.retyped if name not in by_name]
    if unknown:
        notes.append(f"joint_name {', '.join(repr(name) for name in unknown)}: no joint of that name, re-typing not "
                     f"applied (the collection's loader skips such names too)")
    pattern = closures.spherical_pattern
    if pattern is not None:
        matched = [joint.name for joint in tree.joints
                   if pattern in joint.name and joint.type in ("R", "P") and joint.name not in retyped]
        retyped.update({name: "SPHERICAL" for name in matched})
        said = f"joints re-typed SPHERICAL (their names contain it): {', '.join(matched)}" if matched else \
            "no joint's name contains it"
        notes.append(f"rotule_name {pattern!r}: {said}")
    if not retyped and not notes:
        return tree
    joints = []
    for joint in tree.joints:
        joint_type = retyped.get(joint.name)
        if joint_type == "SPHERICAL":
            joint = TreeJoint(joint.name, "S", joint.parent, joint.child, joint.placement, (), joint.child_offset)
        elif joint_type == "FIXED":
            joint = TreeJoint(joint.name, "fixed", joint.parent, joint.child, joint.placement, (), joint.child_offset)
        elif joint_type is not None:
            first, second = universal_axes(joint_type)
            joint = TreeJoint(joint.name, "U", joint.parent, joint.child, joint.placement,
                              (np.eye(3)[first], np.eye(3)[second]), joint.child_offset)
        joints.append(joint)
    kept = []
    for note in tree.notes:  # a floating base re-typed is no longer held fixed: said so, not the opposite
        name = next((name for name in retyped if note == _floating_note(name)), None)
        kept.append(note if name is None else _floating_note(name, retyped[name]))
    return KinematicTree(tree.name, tree.root, tree.links, tuple(joints), tree.frames, (*kept, *notes),
                         tree.mimics)


# ----------------------------------------------------------------------------------------------- assembly

@dataclass(frozen=True, eq=False)
class _Bodies:
    """Links merged through fixed joints into bodies, and the movable joints between them."""

    body: dict          # link -> body (the name of its root-most link)
    offset: dict        # link -> its pose in its body's frame
    movable: tuple      # TreeJoint, in breadth-first order from the root
    placements: tuple   # per movable joint: the joint frame in its parent body's frame
    parents: tuple      # per movable joint: parent body
    children: tuple     # per movable joint: child body
    merged: tuple       # names of the fixed joints merged


def _bodies(tree):
    by_parent = {}
    for joint in tree.joints:
        by_parent.setdefault(joint.parent, []).append(joint)
    body, offset = {tree.root: tree.root}, {tree.root: np.eye(4)}
    movable, placements, parents, children, merged = [], [], [], [], []
    queue = deque([tree.root])
    while queue:
        link = queue.popleft()
        for joint in by_parent.get(link, ()):
            child_offset = np.eye(4) if joint.child_offset is None else joint.child_offset
            if joint.type == "fixed":
                body[joint.child] = body[link]
                offset[joint.child] = offset[link] @ joint.placement @ child_offset
                merged.append(joint.name)
            else:
                body[joint.child] = joint.child
                offset[joint.child] = np.eye(4)
                movable.append(joint)
                placements.append(offset[link] @ joint.placement)
                parents.append(body[link])
                children.append(joint.child)
            queue.append(joint.child)
    return _Bodies(body, offset, tuple(movable), tuple(placements), tuple(parents), tuple(children), tuple(merged))


class _Closure:
    """The closure map of a tree with loops, as an implicit manifold of its joint coordinates."""

    def __init__(self, tree, bodies, loops, length):
        from manifold import AmbientSpace

        self.tree, self.bodies, self.length = tree, bodies, length
        self.loops = loops  # (kind, body A, offset A, body B, offset B)
        factors, self.columns = [], []
        for joint in bodies.movable:
            start = sum(3 if factor == "SO3" else 1 for factor in factors)
            factors.extend(_COORDINATES[joint.type])
            self.columns.append(range(start, start + (3 if joint.type == "S" else len(_COORDINATES[joint.type]))))
        scales = [length if factor == "R" else 1.0 for factor in factors]
        self.ambient = AmbientSpace(tuple(factors), tuple(scales))
        self.point_slices = []
        position = 0
        for joint in bodies.movable:
            size = 9 if joint.type == "S" else len(_COORDINATES[joint.type])
            self.point_slices.append(slice(position, position + size))
            position += size
        # ancestors: body -> boolean mask of the coordinates moving it
        k = self.ambient.dim
        self.moves = {tree.root: np.zeros(k, dtype=bool)}
        for joint, parent, child, columns in zip(bodies.movable, bodies.parents, bodies.children, self.columns):
            mask = self.moves[parent].copy()
            mask[list(columns)] = True
            self.moves[child] = mask
        self.rows = sum(6 if kind == "6d" else 3 for kind, *_ in loops)

    def kinematics(self, point):
        """(body poses, per movable joint its frame before its motion and the world twists of its coordinates)."""
        poses = {self.tree.root: _IDENTITY_4}
        frames, twists = [], np.zeros((self.ambient.dim, 6))
        turning_columns, turning_axes, turning_origins = [], [], []  # the rotations' twists, crossed at once
        for joint, placement, parent, child, columns, part in zip(
                self.bodies.movable, self.bodies.placements, self.bodies.parents, self.bodies.children,
                self.columns, self.point_slices):
            frame = poses[parent] @ placement
            rotation, origin = frame[:3, :3], frame[:3, 3]
            values = point[part]
            if joint.type == "R":
                motion = _homogeneous(_rotation(joint.axes[0], values[0]))
                axes = [rotation @ joint.axes[0]]
            elif joint.type == "P":
                motion = _homogeneous(translation=joint.axes[0] * values[0])
                twists[columns[0], 3:] = rotation @ joint.axes[0]
                axes = []
            elif joint.type == "U":
                first = _rotation(joint.axes[0], values[0])
                motion = _homogeneous(first @ _rotation(joint.axes[1], values[1]))
                axes = [rotation @ joint.axes[0], rotation @ first @ joint.axes[1]]
            else:  # S: a rotation matrix, perturbed on the right (the chart R exp(δ))
                turned = values.reshape(3, 3)
                motion = _homogeneous(turned)
                axes = list((rotation @ turned).T)
            for column, axis in zip(columns, axes):
                turning_columns.append(column)
                turning_axes.append(axis)
                turning_origins.append(origin)
            frames.append(frame)
            poses[child] = frame @ motion if joint.child_offset is None else frame @ motion @ joint.child_offset
        if turning_columns:
            axes = np.asarray(turning_axes)
            twists[turning_columns, :3] = axes
            twists[turning_columns, 3:] = -np.cross(axes, np.asarray(turning_origins))
        return poses, frames, twists

    def _frames(self, poses):
        return [(kind, poses[body_a] @ offset_a, poses[body_b] @ offset_b, body_a, body_b)
                for kind, body_a, offset_a, body_b, offset_b in self.loops]

    def constraint(self, point):
        from manifold import rotation_log

        poses, _, _ = self.kinematics(np.asarray(point, dtype=float))
        rows = []
        for kind, first, second, _, _ in self._frames(poses):
            if kind == "6d":
                rows.append(rotation_log(first[:3, :3].T @ second[:3, :3]))
            rows.append(first[:3, :3].T @ (second[:3, 3] - first[:3, 3]) / self.length)
        return np.concatenate(rows) if rows else np.zeros(0)

    def jacobian(self, point):
        """DΦ in the recentred chart: exact translation rows, rotation rows exact at a closed configuration.

        Both parts are in frame A's coordinates, so a joint that carries both frames (a common ancestor, sign 0)
        has a zero column: d(R_A^T (p_B - p_A)) = R_A^T (s (v + ω × p_B)) with s = 1 for a joint moving B only,
        -1 for A only, 0 for both (the rotation of the gap by a common joint cancels the gap's own change).
        """
        poses, _, twists = self.kinematics(np.asarray(point, dtype=float))
        blocks = []
        omega, velocity = twists[:, :3], twists[:, 3:]
        for kind, first, second, body_a, body_b in self._frames(poses):
            sign = (self.moves[body_b].astype(float) - self.moves[body_a].astype(float))[:, None]
            rotation = first[:3, :3]
            if kind == "6d":
                blocks.append((sign * omega @ rotation).T)
            blocks.append((sign * (velocity + np.cross(omega, second[:3, 3])) @ rotation).T / self.length)
        return np.vstack(blocks) if blocks else np.zeros((0, self.ambient.dim))

    def loop_residuals(self, point):
        value = self.constraint(point)
        sizes = [6 if kind == "6d" else 3 for kind, *_ in self.loops]
        return [float(np.linalg.norm(part)) for part in np.split(value, np.cumsum(sizes)[:-1])] if sizes else []


def _length(tree, bodies):
    """The largest distance between two joint origins or frames of one body at zero (1 if none)."""
    carried = {}
    for joint, placement, parent in zip(bodies.movable, bodies.placements, bodies.parents):
        carried.setdefault(parent, []).append(placement[:3, 3])
        carried.setdefault(joint.child, []).append(np.zeros(3))
    for name in tree.frames:
        link, pose = tree.frames[name]
        carried.setdefault(bodies.body[link], []).append((bodies.offset[link] @ pose)[:3, 3])
    spread = 0.0
    for points in carried.values():
        points = np.asarray(points)
        if len(points) > 1:
            spread = max(spread, float(np.max(np.linalg.norm(points[:, None] - points[None], axis=-1))))
    return spread if spread > 1e-9 else 1.0


def _assemble(closure, loop_names, source):
    """The closed configuration nearest zero by Gauss–Newton (:func:`manifold.project`), or a MechanismError."""
    from manifold import ImplicitManifold, ProjectionError, project

    manifold = ImplicitManifold(closure.ambient, closure.constraint, closure.jacobian)
    start = closure.ambient.neutral()
    if closure.rows == 0:
        return start
    try:
        return project(manifold, start, tolerance=ASSEMBLY_TOLERANCE * 1e-2, max_iterations=_ITERATIONS,
                       max_step=_MAX_STEP)
    except ProjectionError:
        pass
    point = start  # the same damped iteration, kept to name the loops that stay open
    scales = closure.ambient.tangent_scales
    for _ in range(_ITERATIONS):
        step = -scales * np.linalg.lstsq(closure.jacobian(point) * scales, closure.constraint(point), rcond=1e-12)[0]
        norm = np.linalg.norm(step / scales)
        if norm > _MAX_STEP:
            step *= _MAX_STEP / norm
        point = closure.ambient.retract(point, step)
    residuals = closure.loop_residuals(point)
    open_loops = [index for index in range(len(residuals)) if residuals[index] > ASSEMBLY_TOLERANCE]
    worst = sorted(open_loops or range(len(residuals)), key=lambda index: -residuals[index])[:_NAMED_LOOPS]
    named = "; ".join(f"loop {index + 1} {list(loop_names[index])} residual {residuals[index]:.3g}" for index in worst)
    raise MechanismError(f"{source}: the loops cannot be closed (Gauss–Newton from the zero configuration stalls at "
                         f"residual {np.linalg.norm(closure.constraint(point)):.3g} > {ASSEMBLY_TOLERANCE:g}): "
                         f"{named}")


class _Union:
    def __init__(self):
        self.parent = {}

    def find(self, name):
        while self.parent.get(name, name) != name:
            name = self.parent[name]
        return name

    def join(self, keep, other):
        self.parent[self.find(other)] = self.find(keep)


def _joint_values(joint, values):
    if joint.type in ("R", "P"):
        return float(values[0])
    if joint.type == "U":
        return [float(values[0]), float(values[1])]
    return values.reshape(3, 3).copy()


def import_tree(tree, closures, name=None, source="robot", description=None):
    """Assemble a kinematic tree with its closures and build the mechanism (see the module's steps 2–4).

    Parameters
    ----------
    tree : KinematicTree
        Re-typings already applied (:func:`retype`).
    closures : Closures
    name : str, optional
        The mechanism's name (default the tree's).
    source : str
        Starts every error message.
    description : str, optional
        Prepended to the mechanism's description.

    Returns
    -------
    Imported

    Raises
    ------
    MechanismError
        An unknown frame or actuated joint (naming the field and item), a
        fixed or spherical joint listed as actuated, loops that cannot close.
    """
    bodies = _bodies(tree)
    motors, motor_notes = _motors(tree, bodies, closures.actuated, source)
    loops = []
    for index, ((first, second), kind) in enumerate(zip(closures.loops, closures.types)):
        where = f"{source}: field 'closed_loop': item {index}"
        link_a, pose_a = tree.frame(first, where)
        link_b, pose_b = tree.frame(second, where)
        loops.append((kind, bodies.body[link_a], bodies.offset[link_a] @ pose_a,
                      bodies.body[link_b], bodies.offset[link_b] @ pose_b))
    end_effector = None
    if closures.end_effector is not None:
        frame, output = closures.end_effector
        link, pose = tree.frame(frame, f"{source}: field 'end_effector': field 'frame'")
        end_effector = (bodies.body[link], bodies.offset[link] @ pose, output, closures.end_effector_axis)
    length = _length(tree, bodies)
    closure = _Closure(tree, bodies, loops, length)
    point = _assemble(closure, closures.loops, source)
    residuals = closure.loop_residuals(point)
    distance = float(np.linalg.norm(closure.ambient.inverse_retract(closure.ambient.neutral(), point)
                                    / closure.ambient.tangent_scales))
    poses, frames, _ = closure.kinematics(point)
    mechanism, notes = _build(tree, bodies, closures, closure, point, poses, frames, name or tree.name, description,
                              end_effector, source, motors)
    notes = (*closures.notes, *tree.notes, *motor_notes, *notes,
             f"assembled from the zero configuration: moved by {distance:.3g} (radians; lengths over "
             f"{length:.3g}), closure residual {float(np.linalg.norm(closure.constraint(point))):.1e}")
    text = "\n".join(([description] if description else []) + list(notes))
    values = {joint.name: _joint_values(joint, point[part])
              for joint, part in zip(bodies.movable, closure.point_slices)}
    return Imported(mechanism, tuple(notes), distance, float(np.linalg.norm(closure.constraint(point))), values,
                    tuple(residuals), tree, closures, text)


def _motors(tree, bodies, entries, source):
    """The actuated joints named by the ``name_mot`` entries, and notes on the entries read as patterns.

    An entry that is the exact name of a joint names it alone; an entry that names no joint selects every movable
    joint whose name contains it (the collection's loader, ``ActuationModel``, matches ``entry in name``). A fixed
    or spherical joint cannot be actuated; an entry that selects nothing is refused, naming it.
    """
    movable = {joint.name: joint for joint in bodies.movable}
    all_names = {joint.name for joint in tree.joints}
    motors, notes = [], []
    for index, entry in enumerate(entries):
        where = f"{source}: field 'name_mot': item {index}"
        if entry in all_names:
            names = [entry]
        else:
            names = [name for name in movable if entry in name]
            if not names:
                raise MechanismError(f"{where}: unknown joint {entry!r} (no joint has that name, and no movable "
                                     f"joint's name contains it)")
            notes.append(f"name_mot {entry!r} names no joint: read as a pattern, as the collection's loader does, it "
                         f"actuates the joints whose names contain it: {_listing(names)}")
        for name in names:
            if name not in movable:
                raise MechanismError(f"{where}: joint {name!r} is fixed and cannot be actuated")
            if movable[name].type == "S":
                raise MechanismError(f"{where}: joint {name!r} is spherical and cannot be actuated")
            if name not in motors:
                motors.append(name)
    return tuple(motors), notes


def _build(tree, bodies, closures, closure, point, poses, frames, name, description, end_effector=None,
           source="robot", motors=None):
    union = _Union()
    notes = []
    if bodies.merged:
        notes.append(f"{len(bodies.merged)} fixed joint(s) merged into their links")
    welded, idle = [], []
    for (kind, body_a, _, body_b, _), pair in zip(closure.loops, closures.loops):
        if kind != "6d":
            continue
        if union.find(body_a) != union.find(body_b):
            union.join(body_a, body_b)
            welded.append(f"{body_b!r} into {body_a!r}")
        else:  # dropped without a word before (the 3d case below says so)
            idle.append(f"6d closure {list(pair)} joins one rigid link: left out")
    if welded:
        notes.append("6d closures weld links: " + ", ".join(welded))
    notes += idle
    actuated = set(closures.actuated if motors is None else motors)
    joints, locked = [], []
    for joint, frame, parent, child, part in zip(bodies.movable, frames, bodies.parents, bodies.children,
                                                 closure.point_slices):
        links = (union.find(parent), union.find(child))
        if links[0] == links[1]:
            locked.append(joint.name)
            continue
        rotation, origin = frame[:3, :3], tuple(frame[:3, 3])
        fields = {"actuated": joint.name in actuated}
        if joint.type == "R":
            fields.update(point=origin, axis=tuple(rotation @ joint.axes[0]))
        elif joint.type == "P":
            fields.update(axis=tuple(rotation @ joint.axes[0]))
        elif joint.type == "S":
            fields.update(point=origin)
        else:
            turned = rotation @ _rotation(joint.axes[0], point[part][0])
            fields.update(point=origin, axes=(tuple(rotation @ joint.axes[0]), tuple(turned @ joint.axes[1])))
        joints.append(Joint(joint.name, joint.type, links, **fields))
    if locked:
        notes.append(f"joints locked by a weld, left out: {', '.join(locked)}")
    names = {joint.name for joint in joints}
    for (kind, body_a, offset_a, body_b, offset_b), pair in zip(closure.loops, closures.loops):
        if kind != "3d":
            continue
        links = (union.find(body_a), union.find(body_b))
        if links[0] == links[1]:
            notes.append(f"3d closure {list(pair)} joins one rigid link: left out")
            continue
        centre = ((poses[body_a] @ offset_a)[:3, 3] + (poses[body_b] @ offset_b)[:3, 3]) / 2
        joint_name = f"{pair[0]}--{pair[1]}"
        while joint_name in names:
            joint_name += "_"
        names.add(joint_name)
        joints.append(Joint(joint_name, "S", links, point=tuple(centre)))
    ground = union.find(tree.root)
    joints, dropped = _prune(joints, ground)
    if dropped:
        lost = [joint.name for joint in dropped if joint.actuated]
        notes.append(f"joints on no loop left out (each adds free coordinates): {_listing([j.name for j in dropped])}"
                     + (f"; actuated among them: {_listing(lost)}" if lost else ""))
    left = [joint.name for joint in dropped if joint.name in tree.mimics]
    if left:
        notes.append(f"<mimic> joints on no loop, left out with their coupling: {_listing(left)}")
    if not joints:
        raise MechanismError(f"{name}: no movable joint is left to analyse")
    effector = None
    if end_effector is not None:
        body, offset, output, axis = end_effector
        link = union.find(body)
        if link not in {name for joint in joints for name in joint.links}:
            raise MechanismError(f"{source}: field 'end_effector': field 'frame': {closures.end_effector[0]!r} is on "
                                 f"link {body!r}, which is left out (on no loop) or not moved by any joint")
        frame = poses[body] @ offset
        point = None if output == "orientation" else tuple(frame[:3, 3])
        effector = EndEffector(link, point, output, None if axis is None else tuple(frame[:3, :3] @ axis))
    return Mechanism(name, "spatial", joints, ground, effector), notes


def _listing(names, shown=12):
    """Names joined by commas, the first `shown` of them and how many more."""
    names = list(names)
    more = len(names) - shown
    return ", ".join(names[:shown]) + (f" and {more} more ({len(names)} in all)" if more > 0 else "")


def _prune(joints, ground):
    """Leave out, repeatedly, the joints to links (other than the ground) that no other joint names, when there
    are loops: a dangling chain moves nothing of the loops."""
    joints = list(joints)
    links = {link for joint in joints for link in joint.links}
    if len(joints) - len(links) + 1 <= 0:
        return joints, []
    dropped = []
    while True:
        degree = {}
        for joint in joints:
            for link in joint.links:
                degree[link] = degree.get(link, 0) + 1
        leaves = [joint for joint in joints
                  if any(degree[link] == 1 and link != ground for link in joint.links)]
        if not leaves:
            return joints, dropped
        dropped.extend(leaves)
        joints = [joint for joint in joints if joint not in leaves]


# ----------------------------------------------------------------------------------------------- entry point

def mechanism_name(path):
    """The name of an imported mechanism: the file's stem, or its folder's name for a generic ``robot.*``."""
    path = Path(path)
    if path.stem in ("robot", "model", "scene") and path.parent.name:
        return path.parent.name
    return path.stem


def read_urdf(path, closures=None):
    """Import a URDF and its closures file: assembled, as a mechanism (see the module's steps).

    Parameters
    ----------
    path : str or os.PathLike
    closures : str or os.PathLike or Closures, optional
        The closures file (or its contents); without it the URDF is a tree.

    Returns
    -------
    Imported

    Raises
    ------
    MechanismError
        One line starting with the file that names the field.
    """
    from ._text import _path, read_text_file

    path = _path(path)
    text = read_text_file(path, limit=URDF_SIZE_LIMIT)
    source = str(path)
    if closures is None:
        closures_source, closures = source, Closures()
    elif isinstance(closures, Closures):
        closures_source = "closures"
    else:
        closures_source = str(closures)
        closures = read_closures(closures)
    tree = retype(tree_from_urdf(text, source), closures, closures_source)
    imported = import_tree(tree, closures, mechanism_name(path), closures_source,
                           description=f"imported from the URDF {path.name} (robot {tree.name!r})")
    coupled = [joint.name for joint in imported.mechanism.joints if joint.name in tree.mimics]
    if coupled:
        raise MechanismError(f"{source}: joint {coupled[0]!r}: a <mimic> joint on a loop is not supported (its "
                             f"value is coupled to another joint's, a constraint that is not a loop closure); remove "
                             f"the tag to let it move freely, or re-type it FIXED in the closures file")
    return imported
