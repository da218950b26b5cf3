"""Configurations of the command line: displacement rows ↔ points of the ambient space, and points on M.

``closedchain classify --batch`` and ``closedchain map`` take configurations
as *joint displacements from the mechanism's home*, exactly as ``--at`` does
(:func:`mechanisms.from_displacements`): a number for R and P joints, a pair
for U and C, a rotation vector for S; a displacement matrix has one column per
tangent coordinate (:mod:`classify.cli._names`).

This module imports NumPy and the kinematics: the commands import it when
they run, not at start-up.
"""

from __future__ import annotations

import numpy as np

from manifold import project_many, rotation_exp, rotation_log
from mechanisms.kinematics import closes, configuration_space, constraint, kinematics_of

from ._names import coordinate_columns

__all__ = [
    "PROJECTION_TOLERANCE", "displacement_vector", "points_of", "displacements_of", "joint_displacements",
    "off_manifold_row", "project_configurations",
]

#: ‖Φ‖ a projected configuration reaches (as :func:`manifold.project`)
PROJECTION_TOLERANCE = 1e-12


def displacement_vector(mechanism, displacements):
    """The displacement row, shape=[k], of a mapping joint name → displacement (checked before).

    Joints not named are at home (0).
    """
    vector = np.zeros(len(mechanism.coordinate_names))
    columns = coordinate_columns(mechanism)
    for name, value in displacements.items():
        vector[list(columns[name])] = np.atleast_1d(np.asarray(value, dtype=float))
    return vector


def points_of(mechanism, matrix):
    """The configurations ``home ⊕ displacements`` of a displacement matrix.

    Row by row what :func:`mechanisms.from_displacements` builds: each joint's
    entries set to its values, an S joint's rotation matrix the exponential of
    its rotation vector.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k]

    Returns
    -------
    points : ndarray, shape=[n, point_size]
    """
    compiled = kinematics_of(mechanism)
    matrix = np.asarray(matrix, dtype=float).reshape(-1, len(mechanism.coordinate_names))
    points = np.array(np.broadcast_to(compiled.ambient.neutral(), (len(matrix), compiled.ambient.point_size)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            points[:, parts[0]] = rotation_exp(matrix[:, list(indices)]).reshape(len(matrix), 9)
        else:
            for part, index in zip(parts, indices):
                points[:, part] = matrix[:, index:index + 1]
    return points


def displacements_of(mechanism, points):
    """The displacement matrix of configurations (the inverse of :func:`points_of`).

    Row by row :func:`mechanisms.to_displacements`: joint values as they are,
    an S joint's rotation vector the principal logarithm of its rotation.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]

    Returns
    -------
    matrix : ndarray, shape=[n, k]
    """
    compiled = kinematics_of(mechanism)
    points = np.asarray(points, dtype=float).reshape(-1, compiled.ambient.point_size)
    matrix = np.zeros((len(points), len(mechanism.coordinate_names)))
    columns = coordinate_columns(mechanism)
    for joint in mechanism.joints:
        parts, indices = compiled.point_parts[joint.name], columns[joint.name]
        if joint.type == "S":
            matrix[:, list(indices)] = rotation_log(points[:, parts[0]].reshape(-1, 3, 3))
        else:
            for part, index in zip(parts, indices):
                matrix[:, index] = points[:, part][:, 0]
    return matrix


def joint_displacements(mechanism, matrix):
    """The mappings joint name → displacement (a float for R and P, a list for S, U and C) of displacement rows.

    Parameters
    ----------
    mechanism : Mechanism
    matrix : ndarray, shape=[n, k] or [k]

    Returns
    -------
    list of dict (n of them), or one dict for a single row
    """
    matrix = np.asarray(matrix, dtype=float)
    layout = [(name, indices[0] if mechanism.joint(name).type in ("R", "P") else list(indices))
              for name, indices in coordinate_columns(mechanism).items()]
    rows = [{name: (values[where] if isinstance(where, int) else [values[index] for index in where])
             for name, where in layout} for values in np.atleast_2d(matrix).tolist()]
    return rows[0] if matrix.ndim == 1 else rows


def off_manifold_row(mechanism, points, tolerance):
    """The index of the first configuration that does not close the loops (None if all close), and its ‖Φ‖."""
    closed = np.asarray(closes(mechanism, points, tolerance), dtype=bool).reshape(-1)
    if closed.all():
        return None, 0.0
    index = int(np.flatnonzero(~closed)[0])
    return index, float(np.linalg.norm(constraint(mechanism, points[index])))


def project_configurations(mechanism, points, closed_tolerance, max_iterations=60):
    """Projection of a stack of configurations onto M (:func:`manifold.project_many`), as
    :func:`mechanisms.configuration` projects one.

    The configurations that already close (‖Φ‖ ≤ `closed_tolerance`, no
    half-turn) are kept as they are; the others are projected all at once
    until ‖Φ‖ ≤ :data:`PROJECTION_TOLERANCE`, and count as reached where
    they then close every loop (no half-turn).

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]
    closed_tolerance : float
        ``mechanisms.CLOSURE_TOLERANCE``.
    max_iterations : int

    Returns
    -------
    projected : ndarray, shape=[n, point_size]
    reached : ndarray of bool, shape=[n]
        Whether the projection converged to a configuration that closes every loop.
    distance : ndarray, shape=[n]
        Norm of the chart step from each point to its projection (0 where it closed; NaN where not reached).
    """
    ambient = kinematics_of(mechanism).ambient
    requested = np.asarray(points, dtype=float).reshape(-1, ambient.point_size)
    projected = requested.copy()
    moving = np.flatnonzero(~np.asarray(closes(mechanism, requested, closed_tolerance), dtype=bool).reshape(-1))
    reached = np.ones(len(projected), dtype=bool)
    distance = np.zeros(len(projected))
    if len(moving):
        projected[moving], converged = project_many(configuration_space(mechanism), requested[moving],
                                                    PROJECTION_TOLERANCE, max_iterations)
        reached[moving] = converged & np.asarray(closes(mechanism, projected[moving], np.inf), dtype=bool).reshape(-1)
        distance[moving] = np.linalg.norm(ambient.inverse_retract(requested[moving], projected[moving]), axis=-1)
    distance[~reached] = np.nan
    return projected, reached, distance
