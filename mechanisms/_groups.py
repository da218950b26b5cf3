"""Matrix representations of the three motion groups (private helpers).

============  =============  ======  ============================  ============
space         group          matrix  twist order                   loop rows
============  =============  ======  ============================  ============
planar        SE(2)          3×3     (ω, vx, vy)                   3
spherical     SO(3)          3×3     (ωx, ωy, ωz)                  3
spatial       SE(3)          4×4     (ωx, ωy, ωz, vx, vy, vz)      6
============  =============  ======  ============================  ============

A twist matrix ``X̂`` of a rotation about a line satisfies ``X̂³ = −X̂``, one
of a translation ``X̂² = 0``; their exponentials have closed forms
(Rodrigues). The loop-closure rows ``L(T)`` are *linear* in the entries of
the loop product T: the skew part of the rotation block,
``½ vee(R − Rᵀ)``, and the translation divided by the characteristic length.
They vanish at T = I; the only other zeros are half-turns, which
:func:`is_identity_rotation` rejects.
"""

from __future__ import annotations

import numpy as np

MATRIX_SIZE = {"planar": 3, "spherical": 3, "spatial": 4}
LOOP_ROWS = {"planar": 3, "spherical": 3, "spatial": 6}
ROTATION_ROWS = {"planar": 1, "spherical": 3, "spatial": 3}


def skew(vector):
    """The 3×3 matrix ω̂ with ω̂ x = ω × x."""
    x, y, z = vector
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def rotation_twist(space, axis=None, point=None):
    """Twist matrix of a unit right-handed rotation about a line (planar: about +z)."""
    if space == "planar":
        px, py = point
        return np.array([[0.0, -1.0, py], [1.0, 0.0, -px], [0.0, 0.0, 0.0]])
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    if space == "spherical":
        return skew(axis)
    matrix = np.zeros((4, 4))
    matrix[:3, :3] = skew(axis)
    matrix[:3, 3] = np.cross(point, axis)
    return matrix


def translation_twist(space, axis):
    """Twist matrix of a unit translation along `axis`."""
    axis = np.asarray(axis, dtype=float)
    axis = axis / np.linalg.norm(axis)
    size = MATRIX_SIZE[space]
    matrix = np.zeros((size, size))
    matrix[: size - 1, size - 1] = axis
    return matrix


def exp_rotation(twist, angle):
    """``exp(angle · X̂) = I + sin(angle) X̂ + (1 − cos(angle)) X̂²`` for ``X̂³ = −X̂``.

    Parameters
    ----------
    twist : ndarray, shape=[n, n]
    angle : ndarray, shape=[...]

    Returns
    -------
    ndarray, shape=[..., n, n]
    """
    angle = np.asarray(angle, dtype=float)[..., None, None]
    identity = np.eye(twist.shape[0])
    return identity + np.sin(angle) * twist + (1.0 - np.cos(angle)) * (twist @ twist)


def exp_translation(twist, distance):
    """``exp(distance · X̂) = I + distance · X̂`` for ``X̂² = 0``, shape=[..., n, n]."""
    distance = np.asarray(distance, dtype=float)[..., None, None]
    return np.eye(twist.shape[0]) + distance * twist


def ball_matrix(rotation, point):
    """``[[R, p − R p], [0, 1]]``: rotation R about the point p, shape=[..., 4, 4]."""
    shape = rotation.shape[:-2]
    matrix = np.zeros(shape + (4, 4))
    matrix[..., :3, :3] = rotation
    matrix[..., :3, 3] = point - rotation @ point
    matrix[..., 3, 3] = 1.0
    return matrix


def inverse(space, matrix):
    """Inverse of group elements, shape=[..., n, n]."""
    if space == "spherical":
        return np.swapaxes(matrix, -1, -2)
    size = MATRIX_SIZE[space]
    rotation_t = np.swapaxes(matrix[..., : size - 1, : size - 1], -1, -2)
    result = np.zeros_like(matrix)
    result[..., : size - 1, : size - 1] = rotation_t
    result[..., : size - 1, size - 1] = -np.einsum("...ij,...j->...i", rotation_t, matrix[..., : size - 1, size - 1])
    result[..., size - 1, size - 1] = 1.0
    return result


def loop_rows(space, matrix, length):
    """The linear closure rows L(M) of a (batch of) matrix, shape=[..., rows].

    Rotation rows ``½ vee(R − Rᵀ)`` first, then translation rows divided by `length`.
    Linear in M, so it applies unchanged to derivatives of the loop product.
    """
    if space == "planar":
        return np.stack([0.5 * (matrix[..., 1, 0] - matrix[..., 0, 1]),
                         matrix[..., 0, 2] / length, matrix[..., 1, 2] / length], axis=-1)
    rotation = np.stack([0.5 * (matrix[..., 2, 1] - matrix[..., 1, 2]),
                         0.5 * (matrix[..., 0, 2] - matrix[..., 2, 0]),
                         0.5 * (matrix[..., 1, 0] - matrix[..., 0, 1])], axis=-1)
    if space == "spherical":
        return rotation
    return np.concatenate([rotation, matrix[..., :3, 3] / length], axis=-1)


def vee(space, matrix):
    """Twist coordinates of a Lie-algebra matrix, shape=[..., dim] (order as in the table)."""
    if space == "planar":
        return np.stack([matrix[..., 1, 0], matrix[..., 0, 2], matrix[..., 1, 2]], axis=-1)
    rotation = np.stack([matrix[..., 2, 1], matrix[..., 0, 2], matrix[..., 1, 0]], axis=-1)
    if space == "spherical":
        return rotation
    return np.concatenate([rotation, matrix[..., :3, 3]], axis=-1)


def is_identity_rotation(space, matrix):
    """True where the rotation block has positive trace (excludes the half-turn zeros of L)."""
    size = MATRIX_SIZE[space]
    block = matrix if space == "spherical" else matrix[..., : size - 1, : size - 1]
    return np.trace(block, axis1=-2, axis2=-1) > 0.0
