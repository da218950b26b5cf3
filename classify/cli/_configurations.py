"""Configurations of the command line: displacement rows ↔ points of the ambient space (from
:mod:`classify.displacements`), and points on M.

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

from manifold import project_many
from mechanisms.kinematics import closes, configuration_space, constraint, kinematics_of

# the conversions live in the core (:mod:`classify.displacements`); their names stay importable from here
from ..displacements import displacement_vector, displacements_of, joint_displacements, points_of

__all__ = [
    "PROJECTION_TOLERANCE", "displacement_vector", "points_of", "displacements_of", "joint_displacements",
    "off_manifold_row", "project_configurations",
]

#: ‖Φ‖ a projected configuration reaches (as :func:`manifold.project`)
PROJECTION_TOLERANCE = 1e-12


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
