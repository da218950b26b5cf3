"""Moving the home of a mechanism, and other changes of description.

The same physical mechanism can be described from any assembled
configuration as its home, in any base frame, with either sign of each joint
axis. These operations build the other descriptions, so that tests can check
that the classification does not depend on them (docs/design.rst, "Metrics").
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import _groups as groups
from .kinematics import link_pose
from .mechanism import Mechanism

__all__ = ["rehome", "move_base", "flip_axis", "scale_lengths"]


def _transform_point(space, pose, point):
    if point is None or space == "spherical":
        return point
    size = groups.MATRIX_SIZE[space]
    return tuple(pose[: size - 1, : size - 1] @ np.asarray(point) + pose[: size - 1, size - 1])


def _transform_axis(space, pose, axis):
    if axis is None:
        return None
    if space == "planar":
        return tuple(pose[:2, :2] @ np.asarray(axis))
    return tuple(pose[:3, :3] @ np.asarray(axis))


def _moved(mechanism, first_pose, second_pose, name_suffix=""):
    """A copy of the mechanism with each joint's geometry moved by its links' poses."""
    space = mechanism.space
    joints = []
    for joint in mechanism.joints:
        first, second = first_pose(joint.links[0]), second_pose(joint.links[1])
        axes = None
        if joint.axes is not None:
            axes = (_transform_axis(space, first, joint.axes[0]), _transform_axis(space, second, joint.axes[1]))
        joints.append(dataclasses.replace(
            joint, point=_transform_point(space, first, joint.point),
            axis=_transform_axis(space, first, joint.axis), axes=axes))
    end_effector = mechanism.end_effector
    if end_effector is not None and end_effector.point is not None:
        pose = first_pose(end_effector.link)
        axis = None if end_effector.axis is None else _transform_axis(space, pose, end_effector.axis)
        end_effector = dataclasses.replace(end_effector, point=_transform_point(space, pose, end_effector.point),
                                           axis=axis)
    return Mechanism(mechanism.name + name_suffix, space, joints, mechanism.ground, end_effector)


def rehome(mechanism, point):
    """The same mechanism described with the configuration `point` as its home.

    Every joint's geometry is fixed in its first link (a U joint's second
    axis in its second link) and is carried there by the link poses at
    `point`. The returned mechanism's home is the physical configuration
    `point` of the given one, but its end-effector frame keeps the link's
    orientation at `point` as its reference.

    Parameters
    ----------
    mechanism : Mechanism
    point : array_like, shape=[point_size]
        A closed configuration.

    Returns
    -------
    Mechanism
    """
    from .configuration import CLOSURE_TOLERANCE
    from .kinematics import closes

    point = np.asarray(point, dtype=float)
    if point.ndim != 1:
        raise ValueError(f"rehome: expected one configuration (a 1-D point), got shape {point.shape}")
    if not bool(closes(mechanism, point, CLOSURE_TOLERANCE)):
        raise ValueError("rehome: the point does not close the loops (a configuration of M is needed; project it "
                         "first)")
    poses = {link: link_pose(mechanism, link, point) for link in mechanism.links}
    return _moved(mechanism, poses.__getitem__, poses.__getitem__)


def move_base(mechanism, pose):
    """The same mechanism with all home geometry moved by the rigid motion `pose`.

    Parameters
    ----------
    mechanism : Mechanism
    pose : array_like, shape=[n, n]
        A homogeneous matrix of the mechanism's group (SE(2), SO(3) or SE(3)).
    """
    pose = np.asarray(pose, dtype=float)
    size = groups.MATRIX_SIZE[mechanism.space]
    if pose.shape != (size, size) or not np.all(np.isfinite(pose)):
        raise ValueError(f"move_base: expected a finite {size}×{size} matrix for a {mechanism.space} mechanism, "
                         f"got shape {pose.shape}")
    rotation = pose[:3, :3] if mechanism.space != "planar" else pose[:2, :2]
    homogeneous = mechanism.space != "spherical"
    if (not np.allclose(rotation.T @ rotation, np.eye(len(rotation)), atol=1e-9)
            or np.linalg.det(rotation) < 0
            or (homogeneous and not np.allclose(pose[-1], np.eye(size)[-1], atol=0))):
        raise ValueError("move_base: expected a rigid motion (an orthonormal rotation of determinant 1"
                         + (", bottom row 0 … 0 1)" if homogeneous else ")"))
    return _moved(mechanism, lambda link: pose, lambda link: pose)


def flip_axis(mechanism, name):
    """The same mechanism with the axis of joint `name` reversed (planar R: links swapped).

    The joint value changes sign; every other coordinate is unchanged.
    """
    if name not in {joint.name for joint in mechanism.joints}:
        raise ValueError(f"flip_axis: {mechanism.name!r} has no joint {name!r}")
    joints = []
    for joint in mechanism.joints:
        if joint.name == name:
            if joint.axis is not None:
                joint = dataclasses.replace(joint, axis=tuple(-value for value in joint.axis))
            elif joint.type == "R":
                joint = dataclasses.replace(joint, links=tuple(reversed(joint.links)))
            else:
                raise ValueError(f"joint {name!r}: only joints with one axis (R, P, C) can be flipped")
        joints.append(joint)
    return Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, mechanism.end_effector)


def scale_lengths(mechanism, factor):
    """The same mechanism drawn in another unit of length: every point multiplied by `factor`.

    Axes are unchanged; a prismatic (or cylindrical) displacement of the
    scaled mechanism is `factor` times the original one, angles are equal.
    No classification verdict, rank or relative margin may change
    (docs/design.rst, "Metrics"): a file in micrometres is an ordinary file.

    Parameters
    ----------
    mechanism : Mechanism
    factor : float
        Positive and finite.

    Returns
    -------
    Mechanism
    """
    if isinstance(factor, (bool, np.bool_, str)):
        raise ValueError(f"Expected a positive finite factor, got {factor!r}")
    factor = float(factor)
    if not (np.isfinite(factor) and factor > 0):
        raise ValueError(f"Expected a positive finite factor, got {factor!r}")

    def scaled(point):
        return None if point is None else tuple(factor * np.asarray(point, dtype=float))

    spherical = mechanism.space == "spherical"
    joints = [joint if spherical else dataclasses.replace(joint, point=scaled(joint.point))
              for joint in mechanism.joints]
    end_effector = mechanism.end_effector
    if end_effector is not None and end_effector.point is not None and not spherical:
        end_effector = dataclasses.replace(end_effector, point=scaled(end_effector.point))
    return Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, end_effector)
