"""MuJoCo MJCF → :class:`~mechanisms.mechanism.Mechanism`, through the ``mujoco`` package (the ``mjcf`` extra).

MuJoCo compiles the file (``mujoco.MjModel.from_xml_path``, after a read with
the size limit of URDF files), so its includes, meshes and other asset files
are found from the file's folder, as MuJoCo finds them. When it cannot
compile the file with its asset files (meshes, height fields, textures,
skins: a mesh file missing), the file is compiled without them, a geom that
names one becoming a small sphere: they do not move the bodies, joints and
sites, and, as for a URDF, are not needed; the notes name the files and
MuJoCo's reason. Its model gives
the tree: bodies (``body_parentid``, ``body_pos``, ``body_quat`` at the
reference configuration), their joints in order (``hinge`` → ``R``,
``slide`` → ``P``, ``ball`` → ``S``, about ``jnt_pos`` / along ``jnt_axis``
in the body frame; several joints in one body are chained through
intermediate links ``body#1``, …; a ``free`` joint is held fixed and said so),
the loop closures from ``<equality>``: ``connect`` (a ``3d`` closure of the
two anchors, ``eq_data[0:3]`` on the first body and ``eq_data[3:6]`` on the
second) and ``weld`` (a ``6d`` closure, as MuJoCo's residual: the first
body's pose times ``relpose``, ``eq_data[3:10]``, is the second body's pose
moved to its ``anchor``, ``eq_data[0:3]``, unrotated; MuJoCo's compiler
fills ``relpose`` from the reference configuration when the file gives none;
with ``torquescale`` 0 the rotation is not held, and the weld is a ``3d``
closure of those two points, said in the notes), and the actuated joints from
``<actuator>`` elements that drive a joint (an actuator on a tendon, site or
body is named in the notes and not counted). Inactive equalities are
not closures (the notes say so); a ``joint`` or ``tendon`` equality (a coupling of values, not a
loop closure) is refused, naming it. Keyframes are left out and named in the
notes: a keyframe's ``qpos`` need not close the loops, and a mechanism's
named configurations are displacements from its closed home.
Assembly and building are those of :func:`mechanisms.urdf.import_tree`.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from .closures import Closures
from .errors import MechanismError
from .urdf import KinematicTree, TreeJoint, URDF_SIZE_LIMIT, import_tree, mechanism_name

__all__ = ["read_mjcf", "tree_from_mjcf"]


def _pose(position, quaternion):
    w, x, y, z = np.asarray(quaternion, dtype=float) / np.linalg.norm(quaternion)
    rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rotation, position
    return matrix


def _translation(vector):
    matrix = np.eye(4)
    matrix[:3, 3] = vector
    return matrix


class _Names:
    """Names of one kind of element (links, joints or frames): the file's own first, then made-up ones.

    A name the import makes up (an unnamed element's ``body3``, an intermediate link ``a#1``, a fixed joint
    ``a#fixed``, a connect's frames ``equality1:A``) never takes a name the file gives: it gets ``~2``, ``~3``…
    (an unnamed connect called like a named one replaced its frames and dropped a closure; a body named
    ``a#1`` made the tree a cycle, and the import never ended).
    """

    def __init__(self, given):
        self.taken = {name for name in given if name}

    def made_up(self, candidate):
        name, number = candidate, 1
        while name in self.taken:
            number += 1
            name = f"{candidate}~{number}"
        self.taken.add(name)
        return name


def tree_from_mjcf(model, source="MJCF"):
    """(kinematic tree, closures) of a compiled ``mujoco.MjModel``."""
    import mujoco

    def labelled(kind, count, fallback):
        """The names of the `count` elements of `kind` (an unnamed one's made up), and their :class:`_Names`."""
        given = [mujoco.mj_id2name(model, kind, index) for index in range(count)]
        names = _Names(given)
        return [item or names.made_up(f"{fallback}{index}") for index, item in enumerate(given)], names

    objects = mujoco.mjtObj
    bodies, link_names = labelled(objects.mjOBJ_BODY, model.nbody, "body")
    joint_labels, joint_names = labelled(objects.mjOBJ_JOINT, model.njnt, "joint")
    sites, frame_names = labelled(objects.mjOBJ_SITE, model.nsite, "site")
    equalities = labelled(objects.mjOBJ_EQUALITY, model.neq, "equality")[0]
    links, joints, notes = [bodies[0]], [], []
    for body in range(1, model.nbody):
        parent = bodies[model.body_parentid[body]]
        placement = _pose(model.body_pos[body], model.body_quat[body])
        start, count = model.body_jntadr[body], model.body_jntnum[body]
        if count <= 0:
            joints.append(TreeJoint(joint_names.made_up(f"{bodies[body]}#fixed"), "fixed", parent, bodies[body],
                                    placement))
            links.append(bodies[body])
            continue
        for offset in range(count):
            index = start + offset
            joint_name = joint_labels[index]
            child = bodies[body] if offset == count - 1 else link_names.made_up(f"{bodies[body]}#{offset + 1}")
            links.append(child)
            position = np.array(model.jnt_pos[index], dtype=float)
            axis = np.array(model.jnt_axis[index], dtype=float)
            kind = int(model.jnt_type[index])
            if kind == int(mujoco.mjtJoint.mjJNT_FREE):
                joints.append(TreeJoint(joint_name, "fixed", parent, child, placement))
                notes.append(f"free joint {joint_name!r} held fixed")
            else:
                joint_type = {int(mujoco.mjtJoint.mjJNT_HINGE): "R", int(mujoco.mjtJoint.mjJNT_SLIDE): "P",
                              int(mujoco.mjtJoint.mjJNT_BALL): "S"}[kind]
                axes = () if joint_type == "S" else (axis / np.linalg.norm(axis),)
                joints.append(TreeJoint(joint_name, joint_type, parent, child, placement @ _translation(position),
                                        axes, _translation(-position)))
            parent, placement = child, np.eye(4)
    frames = {}
    for site in range(model.nsite):
        frames[sites[site]] = (bodies[model.site_bodyid[site]], _pose(model.site_pos[site], model.site_quat[site]))
    loops, types = [], []
    for index in range(model.neq):
        label = equalities[index]
        if not model.eq_active0[index]:
            notes.append(f"equality {label!r} is inactive (active=\"false\"): not a loop closure")
            continue
        kind = int(model.eq_type[index])
        data = np.asarray(model.eq_data[index], dtype=float)
        ends = (int(model.eq_obj1id[index]), int(model.eq_obj2id[index]))
        weld = kind == int(mujoco.mjtEq.mjEQ_WELD)
        if weld and data[10] == 0:  # torquescale 0: MuJoCo's rotation rows are zero, the anchor is held alone
            notes.append(f"weld {label!r} has torquescale 0 (its rotation is not held): a 3d closure, a ball")
        closure = "6d" if weld and data[10] != 0 else "3d"
        if int(model.eq_objtype[index]) == int(objects.mjOBJ_SITE):
            loops.append((sites[ends[0]], sites[ends[1]]))
            types.append(closure)
            continue
        first, second = (bodies[item] for item in ends)
        anchors = frame_names.made_up(f"{label}:A"), frame_names.made_up(f"{label}:B")
        if kind == int(mujoco.mjtEq.mjEQ_CONNECT):
            frames[anchors[0]] = (first, _translation(data[0:3]))
            frames[anchors[1]] = (second, _translation(data[3:6]))
        elif weld:  # MuJoCo holds body1's pose times relpose (data[3:10]) at body2's pose moved to its anchor
            frames[anchors[0]] = (first, _pose(data[3:6], data[6:10]))
            frames[anchors[1]] = (second, _translation(data[0:3]))
        else:
            kinds = {int(mujoco.mjtEq.mjEQ_JOINT): "joint", int(mujoco.mjtEq.mjEQ_TENDON): "tendon"}
            raise MechanismError(f"{source}: equality {label!r}: a {kinds.get(kind, 'non-geometric')} equality is "
                                 f"not supported (only connect and weld, the loop closures; a coupling of joint or "
                                 f"tendon values is not one)")
        loops.append(anchors)
        types.append(closure)
    actuated, elsewhere = [], []
    actuators = labelled(objects.mjOBJ_ACTUATOR, model.nu, "actuator")[0]
    for index in range(model.nu):
        if int(model.actuator_trntype[index]) == int(mujoco.mjtTrn.mjTRN_JOINT):
            joint_name = joint_labels[int(model.actuator_trnid[index][0])]
            if joint_name not in actuated:
                actuated.append(joint_name)
        else:
            elsewhere.append(actuators[index])
    if elsewhere:
        notes.append(f"actuators that drive no joint (a tendon, site or body) are not counted: {', '.join(elsewhere)}")
    if model.nkey:
        keys = labelled(objects.mjOBJ_KEY, model.nkey, "key")[0]
        notes.append(f"keyframes left out (a keyframe's qpos need not close the loops, and a mechanism's named "
                     f"configurations are displacements from its closed home): {', '.join(map(repr, keys))}")
    notes.insert(0, f"world body {bodies[0]!r} is the ground")
    tree = KinematicTree("mjcf", bodies[0], tuple(links), tuple(joints), frames, tuple(notes))
    return tree, Closures(tuple(loops), tuple(types), tuple(actuated), {})


def read_mjcf(path):
    """Import an MJCF file: assembled, as a mechanism (:class:`mechanisms.urdf.Imported`).

    Raises
    ------
    MechanismError
        One line starting with the file: MuJoCo's own compiler errors are wrapped.
    """
    from ._text import _path, read_text_file

    path = _path(path)
    read_text_file(path, limit=URDF_SIZE_LIMIT)  # its errors (no such file, too large, not text), one line
    try:
        import mujoco
    except ImportError:
        raise MechanismError(f"{path}: reading MJCF needs the mujoco package: pip install closedchain[mjcf]") from None
    previous = mujoco.get_mju_user_warning()
    warned = []  # MuJoCo prints its warnings on stdout: kept here, for the notes (a NaN… is refused below)
    mujoco.set_mju_user_warning(lambda message: warned.append(" ".join(str(message).split())))
    try:
        with warnings.catch_warnings(record=True) as caught:  # MjSpec.compile warns in Python, not through it
            warnings.simplefilter("always")
            model, stripped = _compile(mujoco, path)
    finally:
        mujoco.set_mju_user_warning(previous)
    warned.extend(" ".join(str(item.message).split()) for item in caught)
    _check_finite(model, path)
    tree, closures = tree_from_mjcf(model, str(path))
    imported = import_tree(tree, closures, mechanism_name(path), str(path),
                           description=f"imported from the MJCF {path.name}")
    notes = tuple(f"MuJoCo warned: {message}" for message in warned) + stripped
    return replace(imported, notes=imported.notes + notes)


def _compile(mujoco, path):
    """(MuJoCo's model of the file at `path`, notes): its includes, meshes and other asset files are found as
    MuJoCo finds them, from the file's folder (``MjSpec.from_file``). When MuJoCo cannot compile the file as it
    is and it has asset files (meshes, height fields, textures, skins), it is compiled without them, as they do
    not move the bodies, joints and sites (a missing mesh file, as for a URDF, is not needed), and the notes say
    so; when that fails too, MuJoCo's first error is raised.

    Raises
    ------
    MechanismError
        One line: MuJoCo's error.
    """
    try:
        return mujoco.MjModel.from_xml_path(str(path)), ()
    except Exception as error:  # MuJoCo's compiler errors (ValueError...), one line
        reason = " ".join(str(error).split()) or type(error).__name__
        failure = MechanismError(f"{path}: MJCF: cannot compile: {reason}"[:400])
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        files = _strip_asset_files(mujoco, spec)
        if not files:
            raise failure
        model = spec.compile()
    except Exception:
        raise failure from None
    shown = ", ".join(repr(name) for name in files[:6]) + (f" and {len(files) - 6} more" if len(files) > 6 else "")
    return model, (f"compiled without its meshes and other asset files ({shown}), as MuJoCo could not compile "
                   f"it with them ({reason[:200]}); they do not move the bodies, joints and sites",)


def _strip_asset_files(mujoco, spec):
    """Remove from `spec` the assets read from files (meshes, height fields, textures, skins), a geom that names
    one becoming a small sphere (its body keeps a mass); return the files' names."""
    files = []
    for kind in ("meshes", "hfields", "textures", "skins"):
        for asset in list(getattr(spec, kind)):
            name = getattr(asset, "file", "")
            cubes = [item for item in getattr(asset, "cubefiles", ()) if item]
            if name or cubes:
                files.extend([name] if name else cubes)
                spec.delete(asset)
    if not files:
        return files
    shaped = {int(mujoco.mjtGeom.mjGEOM_MESH), int(mujoco.mjtGeom.mjGEOM_HFIELD), int(mujoco.mjtGeom.mjGEOM_SDF)}
    for geom in spec.geoms:
        if int(geom.type) in shaped or geom.meshname or geom.hfieldname:
            geom.type, geom.meshname, geom.hfieldname = mujoco.mjtGeom.mjGEOM_SPHERE, "", ""
            geom.size = [0.01, 0.0, 0.0]
        geom.material = ""
    for material in spec.materials:
        material.textures = [""] * len(material.textures)
    return files


#: the compiled model's arrays the import reads: (object type, what they hold, columns of positions or None)
_GEOMETRY = {"body_pos": ("BODY", "pos", slice(None)), "body_quat": ("BODY", "orientation", None),
             "jnt_pos": ("JOINT", "pos", slice(None)), "jnt_axis": ("JOINT", "axis", None),
             "site_pos": ("SITE", "pos", slice(None)), "site_quat": ("SITE", "orientation", None),
             "eq_data": ("EQUALITY", "anchor or relpose", slice(0, 6))}


def _check_finite(model, path):
    """MechanismError naming the element of the first non-finite geometry (MuJoCo accepts NaN and inf, with a
    warning) or of the first position beyond ±COORDINATE_LIMIT (as in a mechanism file)."""
    import mujoco
    import numpy as np

    from .joints import COORDINATE_LIMIT

    for field, (kind, meaning, positions) in _GEOMETRY.items():
        values = np.asarray(getattr(model, field), dtype=float)
        if not values.size:
            continue
        values = values.reshape(len(values), -1)  # one row per element
        bad = ~np.all(np.isfinite(values), axis=1)
        if positions is not None:
            bad |= np.any(np.abs(np.nan_to_num(values[:, positions])) > COORDINATE_LIMIT, axis=1)
        if np.any(bad):
            index = int(np.flatnonzero(bad)[0])
            element = mujoco.mj_id2name(model, getattr(mujoco.mjtObj, f"mjOBJ_{kind}"), index) or f"number {index}"
            what = ("is not finite (NaN or infinity)" if not np.all(np.isfinite(values[index]))
                    else f"is beyond ±{COORDINATE_LIMIT:g} (as in a mechanism file)")
            raise MechanismError(f"{path}: MJCF: {kind.lower()} {element!r}: its {meaning} {what}")
    axial = np.isin(model.jnt_type, [int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)])
    lengths = np.linalg.norm(np.asarray(model.jnt_axis, dtype=float).reshape(-1, 3), axis=1)
    if np.any(axial & ~(lengths > 0.5)):  # MuJoCo normalises the axis: 0 where it was zero or overflowed
        index = int(np.flatnonzero(axial & ~(lengths > 0.5))[0])
        element = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, index) or f"number {index}"
        raise MechanismError(f"{path}: MJCF: joint {element!r}: its axis has no direction (MuJoCo compiled it to "
                             f"0 0 0: a zero axis, or one too large to normalise)")
