"""MuJoCo MJCF → :class:`~mechanisms.mechanism.Mechanism`, through the ``mujoco`` package (the ``mjcf`` extra).

MuJoCo compiles the file's text (``mujoco.MjModel.from_xml_string``, read with
the size limit of URDF files); its model gives
the tree: bodies (``body_parentid``, ``body_pos``, ``body_quat`` at the
reference configuration), their joints in order (``hinge`` → ``R``,
``slide`` → ``P``, ``ball`` → ``S``, about ``jnt_pos`` / along ``jnt_axis``
in the body frame; several joints in one body are chained through
intermediate links ``body#1``, …; a ``free`` joint is held fixed and said so),
the loop closures from ``<equality>``: ``connect`` (a ``3d`` closure of the
two anchors, ``eq_data[0:3]`` on the first body and ``eq_data[3:6]`` on the
second) and ``weld`` (a ``6d`` closure: the second body at ``relpose``,
``eq_data[3:10]``, from the first), and the actuated joints from
``<actuator>`` elements that drive a joint (an actuator on a tendon, site or
body is named in the notes and not counted). Inactive equalities are
not closures (the notes say so); a ``joint`` or ``tendon`` equality (a coupling of values, not a
loop closure) is refused, naming it.
Assembly and building are those of :func:`mechanisms.urdf.import_tree`.
"""

from __future__ import annotations

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


def tree_from_mjcf(model, source="MJCF"):
    """(kinematic tree, closures) of a compiled ``mujoco.MjModel``."""
    import mujoco

    def name(kind, index, fallback):
        return mujoco.mj_id2name(model, kind, index) or f"{fallback}{index}"

    bodies = [name(mujoco.mjtObj.mjOBJ_BODY, index, "body") for index in range(model.nbody)]
    links, joints, notes = [bodies[0]], [], []
    for body in range(1, model.nbody):
        parent = bodies[model.body_parentid[body]]
        placement = _pose(model.body_pos[body], model.body_quat[body])
        start, count = model.body_jntadr[body], model.body_jntnum[body]
        if count <= 0:
            joints.append(TreeJoint(f"{bodies[body]}#fixed", "fixed", parent, bodies[body], placement))
            links.append(bodies[body])
            continue
        for offset in range(count):
            index = start + offset
            joint_name = name(mujoco.mjtObj.mjOBJ_JOINT, index, "joint")
            child = bodies[body] if offset == count - 1 else f"{bodies[body]}#{offset + 1}"
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
        frames[name(mujoco.mjtObj.mjOBJ_SITE, site, "site")] = (
            bodies[model.site_bodyid[site]], _pose(model.site_pos[site], model.site_quat[site]))
    loops, types = [], []
    for index in range(model.neq):
        if not model.eq_active0[index]:
            notes.append(f"equality {name(mujoco.mjtObj.mjOBJ_EQUALITY, index, 'equality')!r} is inactive "
                         f"(active=\"false\"): not a loop closure")
            continue
        kind = int(model.eq_type[index])
        data = np.asarray(model.eq_data[index], dtype=float)
        objects = (int(model.eq_obj1id[index]), int(model.eq_obj2id[index]))
        if int(model.eq_objtype[index]) == int(mujoco.mjtObj.mjOBJ_SITE):
            first, second = (frames_name for frames_name in (name(mujoco.mjtObj.mjOBJ_SITE, item, "site")
                                                             for item in objects))
            loops.append((first, second))
            types.append("3d" if kind == int(mujoco.mjtEq.mjEQ_CONNECT) else "6d")
            continue
        first, second = (bodies[item] for item in objects)
        label = name(mujoco.mjtObj.mjOBJ_EQUALITY, index, "equality")
        if kind == int(mujoco.mjtEq.mjEQ_CONNECT):
            frames[f"{label}:A"] = (first, _translation(data[0:3]))
            frames[f"{label}:B"] = (second, _translation(data[3:6]))
            types.append("3d")
        elif kind == int(mujoco.mjtEq.mjEQ_WELD):
            frames[f"{label}:A"] = (first, _pose(data[3:6], data[6:10]))
            frames[f"{label}:B"] = (second, np.eye(4))
            types.append("6d")
        else:
            kinds = {int(mujoco.mjtEq.mjEQ_JOINT): "joint", int(mujoco.mjtEq.mjEQ_TENDON): "tendon"}
            raise MechanismError(f"{source}: equality {label!r}: a {kinds.get(kind, 'non-geometric')} equality is "
                                 f"not supported (only connect and weld, the loop closures; a coupling of joint or "
                                 f"tendon values is not one)")
        loops.append((f"{label}:A", f"{label}:B"))
    actuated, elsewhere = [], []
    for index in range(model.nu):
        if int(model.actuator_trntype[index]) == int(mujoco.mjtTrn.mjTRN_JOINT):
            joint_name = name(mujoco.mjtObj.mjOBJ_JOINT, int(model.actuator_trnid[index][0]), "joint")
            if joint_name not in actuated:
                actuated.append(joint_name)
        else:
            elsewhere.append(name(mujoco.mjtObj.mjOBJ_ACTUATOR, index, "actuator"))
    if elsewhere:
        notes.append(f"actuators that drive no joint (a tendon, site or body) are not counted: {', '.join(elsewhere)}")
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
    text = read_text_file(path, limit=URDF_SIZE_LIMIT)
    try:
        import mujoco
    except ImportError:
        raise MechanismError(f"{path}: reading MJCF needs the mujoco package: pip install closedchain[mjcf]") from None
    previous = mujoco.get_mju_user_warning()
    warned = []  # MuJoCo prints its warnings on stdout: kept here, for the notes (a NaN… is refused below)
    mujoco.set_mju_user_warning(lambda message: warned.append(" ".join(str(message).split())))
    try:
        model = mujoco.MjModel.from_xml_string(text)
    except Exception as error:  # MuJoCo's compiler errors (ValueError...), one line
        reason = " ".join(str(error).split()) or type(error).__name__
        raise MechanismError(f"{path}: MJCF: cannot compile: {reason}"[:400]) from None
    finally:
        mujoco.set_mju_user_warning(previous)
    _check_finite(model, path)
    tree, closures = tree_from_mjcf(model, str(path))
    imported = import_tree(tree, closures, mechanism_name(path), str(path),
                           description=f"imported from the MJCF {path.name}")
    return replace(imported, notes=imported.notes + tuple(f"MuJoCo warned: {message}" for message in warned))


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
