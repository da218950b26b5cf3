"""Configurations: points of the ambient space built from joint displacements.

A configuration is ``home ⊕ displacement``: the home (all joint values zero,
rotations identity) moved by the joint values the user gives (docs/design.rst,
"Mechanism file"). A configuration that does not close the loops is refused
unless it is projected onto the C-space.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from manifold import ProjectionError, project, rotation_exp, rotation_log

from .errors import ConfigurationError, MechanismError
from .io import check_displacement
from .kinematics import closure_failure, configuration_space, kinematics_of

__all__ = [
    "CLOSURE_TOLERANCE", "home", "validate_displacements", "from_displacements",
    "to_displacements", "configuration", "Projected",
]

#: largest ‖Φ‖ (dimensionless rows) for a configuration to count as closed
CLOSURE_TOLERANCE = 1e-9


def home(mechanism):
    """The home configuration, shape=[point_size]."""
    return kinematics_of(mechanism).ambient.neutral()


def validate_displacements(mechanism, displacements, where="displacements"):
    """Check a mapping joint name -> displacement against a mechanism.

    A number for R and P joints, 3 numbers (a rotation vector) for S, 2 numbers
    for U and C (:func:`mechanisms.io.check_displacement`). Raises
    :class:`ConfigurationError` naming the joint.
    """
    if not isinstance(displacements, dict):
        raise ConfigurationError(f"{where}: expected a mapping from joint names to displacements, "
                                 f"got {type(displacements).__name__}")
    joints = {joint.name: joint for joint in mechanism.joints}
    for name, value in displacements.items():
        if name not in joints:
            raise ConfigurationError(f"{where}: joint {name!r}: unknown joint")
        try:
            check_displacement(value, joints[name], f"{where}: joint {name!r}")
        except MechanismError as error:
            raise ConfigurationError(str(error)) from None


def from_displacements(mechanism, displacements, where="displacements"):
    """The point ``home ⊕ displacements`` (joints not named stay at home).

    Parameters
    ----------
    mechanism : Mechanism
    displacements : dict
        Joint name -> displacement.

    Returns
    -------
    point : ndarray, shape=[point_size]
    """
    validate_displacements(mechanism, displacements, where)
    compiled = kinematics_of(mechanism)
    point = compiled.ambient.neutral()
    for joint in mechanism.joints:
        parts = compiled.point_parts[joint.name]
        if joint.name not in displacements:
            continue
        value = displacements[joint.name]
        if joint.type == "S":
            point[parts[0]] = rotation_exp(np.asarray(value, dtype=float)).ravel()
        else:
            values = np.atleast_1d(np.asarray(value, dtype=float))
            for part, entry in zip(parts, values):
                point[part] = entry
    return point


def to_displacements(mechanism, point):
    """The displacement mapping of a point (inverse of :func:`from_displacements`)."""
    compiled = kinematics_of(mechanism)
    point = np.asarray(point, dtype=float)
    balls = [joint.name for joint in mechanism.joints if joint.type == "S"]
    logarithms = dict(zip(balls, rotation_log(np.stack(
        [point[compiled.point_parts[name][0]].reshape(3, 3) for name in balls]
    )).tolist())) if balls else {}  # one call for every ball joint
    result = {}
    for joint in mechanism.joints:
        parts = compiled.point_parts[joint.name]
        if joint.type == "S":
            result[joint.name] = logarithms[joint.name]
        elif len(parts) == 1:
            result[joint.name] = float(point[parts[0]][0])
        else:
            result[joint.name] = [float(point[part][0]) for part in parts]
    return result


@dataclass(frozen=True, eq=False)
class Projected:
    """A configuration and how far projection moved it.

    Attributes
    ----------
    point : ndarray, shape=[point_size]
    requested : ndarray, shape=[point_size]
    distance : float
        Norm of the chart step from the requested point to `point` (0 when it closed).
    """

    point: np.ndarray
    requested: np.ndarray
    distance: float


#: what the refusal of a configuration that does not close advises by default
REMEDY = "give closing values or use --project"


def configuration(mechanism, displacements=None, project_onto=False, where="displacements", remedy=REMEDY):
    """A closed configuration from displacements, refused or projected if it does not close.

    Parameters
    ----------
    mechanism : Mechanism
    displacements : dict, optional
        Joint name -> displacement; default the home.
    project_onto : bool
        Project onto the C-space (Gauss-Newton) when the loops do not close.
    where : str
        What the displacements are, for messages (``--at``).
    remedy : str
        What the refusal advises (a command with more ways than ``--project`` says them).

    Returns
    -------
    Projected

    Raises
    ------
    ConfigurationError
        If the configuration does not close and `project_onto` is false, or projection fails.
    """
    if displacements is not None and not isinstance(displacements, Mapping):
        raise ConfigurationError(f"{where}: expected a mapping of joint names to displacements, got "
                                 f"{type(displacements).__name__}")
    requested = from_displacements(mechanism, displacements or {}, where)
    failure = closure_failure(mechanism, requested, CLOSURE_TOLERANCE)
    if failure is None:
        return Projected(requested, requested, 0.0)
    if not project_onto:
        raise ConfigurationError(f"{where}: {failure[1]}; {remedy}")
    manifold = configuration_space(mechanism)
    try:
        point = project(manifold, requested)
    except ProjectionError as error:
        raise ConfigurationError(f"{where}: projection onto the configuration space failed: {error}") from None
    distance = float(np.linalg.norm(manifold.ambient.inverse_retract(requested, point)))
    return Projected(point, requested, distance)
