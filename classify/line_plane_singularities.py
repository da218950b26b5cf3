"""The singularity polynomial of a line-plane 5-SPU, its scale-free margin, its reading, and the leg Jacobian.

The parallel singularities of a design (Borràs, Thomas & Torras 2011) at a
pose (p, i) are the zeros of the singularity polynomial (17), the product
of the B-line B_μ and the point A (19) where Λ meets Π: singular iff A lies
on the B-line of its own coordinate μ along Λ (18), or, when Λ is parallel
to Π, iff Λ lies in Π or is parallel to B∞ (20). The 6 × 6 matrix of the
legs' line coordinates (:func:`leg_jacobian`) tests the same locus without
the cofactors.

References
----------
Borràs, Thomas & Torras 2011, eqs. (17)-(20), Section III-C; equation (2)
is lost from the text, its vector forms are (17) and (22).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .line_plane_design import cofactors, normalised
from .line_plane_pencil import _oriented_normalised_b_line

__all__ = ["SingularityReading", "singularity_polynomial", "singularity_margin", "singularity_reading",
           "leg_jacobian", "jacobian_determinant"]


@dataclass(frozen=True)
class SingularityReading:
    """The geometric reading of (17) at a pose (Section III-C).

    Attributes
    ----------
    singular : bool
    margin : float
        :func:`singularity_margin`.
    parallel : bool
        w = 0 (Λ parallel to Π): singular iff Λ lies in Π or is parallel to B∞ (20).
    intersection : ndarray, shape=[2], or None
        A (19): where Λ meets Π (None when parallel).
    z : float or None
        μ = −p_z/w: the coordinate along Λ of A, whose B-line B_μ decides.
    distance : float or None
        Signed distance from A to the B-line B_μ (None when parallel, or B_μ at
        infinity), positive on the side of B_μ that holds the centroid ā of the
        base attachments (as :func:`~classify.line_plane_pencil.oriented_b_line`):
        it does not change with the leg numbering or the sign of i.
    """

    singular: bool
    margin: float
    parallel: bool
    intersection: object = None
    z: object = None
    distance: object = None


def _pose(position, direction):
    position = np.asarray(position, dtype=float)
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction, axis=-1, keepdims=True)
    return position, direction


def _factors(values, position, direction):
    """The two 3-vectors of (17): ℓ = w(C₂, C₃, C₆) − p_z(C₄, C₅, C₁) and a = (pₓw − p_zu, p_yw − p_zv, w)."""
    c1, c2, c3, c4, c5, c6 = values
    p_x, p_y, p_z = np.moveaxis(position, -1, 0)
    u, v, w = np.moveaxis(direction, -1, 0)
    line = w[..., None] * np.array([c2, c3, c6]) - p_z[..., None] * np.array([c4, c5, c1])
    point = np.stack([p_x * w - p_z * u, p_y * w - p_z * v, w], axis=-1)
    return line, point


def singularity_polynomial(design, position, direction):
    """The singularity polynomial (17) at poses (p, i).

    [w (C₂ C₃ C₆) − p_z (C₄ C₅ C₁)] · (pₓw − p_zu, p_yw − p_zv, w)ᵀ

    Parameters
    ----------
    design : LinePlaneDesign
    position : array_like, shape=[..., 3]
        p, the point of Λ with coordinate z = 0.
    direction : array_like, shape=[..., 3]
        i (normalised here).

    Returns
    -------
    ndarray, shape=[...]
        Zero exactly at the parallel singularities (in the units of the raw cofactors).

    References
    ----------
    Borràs, Thomas & Torras 2011 eq. (17), the vector form of the lost (2).
    """
    position, direction = _pose(position, direction)
    line, point = _factors(cofactors(design), position, direction)
    return np.sum(line * point, axis=-1)


def _normalised_pose(design, position, direction):
    """(p, i) in the frame of :func:`~classify.line_plane_design.normalised`: p' = (p + z̄ i − (x̄, ȳ, 0)) / L."""
    centre, length = design.centre, design.characteristic_length
    return (position + centre[2] * direction - np.array([centre[0], centre[1], 0.0])) / length, direction


def singularity_margin(design, position, direction):
    """``|ℓ·a|`` / (‖ℓ‖‖a‖) of (17), in the normalised design: 0 on the singularity locus, shape=[...].

    ℓ is the B-line B_μ (μ = −p_z/w) and a the point A (19) where Λ meets Π,
    both homogeneous (scaled by w): the margin is the cosine of the angle
    between them, dimensionless and unchanged by a rigid motion of the base
    frame, a shift of the origin of Λ and a scaling of all lengths. It is 0
    when ℓ or a vanishes (Λ in Π).
    """
    position, direction = _pose(position, direction)
    position, direction = _normalised_pose(design, position, direction)
    line, point = _factors(cofactors(normalised(design)), position, direction)
    scale = np.linalg.norm(line, axis=-1) * np.linalg.norm(point, axis=-1)
    value = np.abs(np.sum(line * point, axis=-1))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(scale > 0, value / np.where(scale > 0, scale, 1.0), 0.0)


def singularity_reading(design, position, direction, rtol=1e-9):
    """The geometric reading of (17) at one pose (Section III-C).

    Singular iff the point A (19) where Λ meets Π lies on the B-line of its
    own coordinate μ = −p_z/w along Λ (18); when Λ is parallel to Π (w = 0),
    iff Λ lies in Π or is parallel to B∞ (20).

    Parameters
    ----------
    design : LinePlaneDesign
    position, direction : array_like, shape=[3]
    rtol : float
        Cut on :func:`singularity_margin`; also the cut ``|w|`` ≤ rtol of "parallel".

    Returns
    -------
    SingularityReading
    """
    position, direction = _pose(position, direction)
    margin = float(singularity_margin(design, position, direction))
    singular = margin <= rtol
    p_x, p_y, p_z = position
    u, v, w = direction
    if abs(w) <= rtol:
        return SingularityReading(singular, margin, True)
    mu = -p_z / w
    intersection = np.array([p_x + mu * u, p_y + mu * v])
    # the distance in the normalised frame (A′ = p′ + μ′i, μ′ = (μ − z̄)/L), times L: it moves with the frame
    primed, _ = _normalised_pose(design, position, direction)
    primed = primed[:2] - primed[2] / w * direction[:2]
    line = _oriented_normalised_b_line(design, mu)
    length = design.characteristic_length
    distance = None if np.isnan(line[0]) else float(length * (line[:2] @ primed + line[2]))
    return SingularityReading(singular, margin, False, intersection, float(mu), distance)


def leg_jacobian(design, position, direction):
    """The 6 × 6 matrix of the legs' line coordinates and the spin about Λ, shape=[..., 6, 6].

    Row k ≤ 5: (dₖ, zₖ i × dₖ), dₖ = bₖ − aₖ, so that lₖ l̇ₖ = dₖ·ṗ + zₖ (i × dₖ)·ω
    for a platform velocity ṗ and an angular velocity ω of Λ (i̇ = ω × i);
    row 6: (0, i), picking out the spin ω·i that no leg sees. Its determinant
    vanishes iff the five leg rows are dependent on the 5-dimensional motions
    of Λ: an independent test of the singularity locus, computed without the
    cofactors.
    """
    position, direction = _pose(position, direction)
    base = np.column_stack([design.base, np.zeros(5)])
    attachments = position[..., None, :] + design.platform[:, None] * direction[..., None, :]
    legs = attachments - base
    moments = design.platform[:, None] * np.cross(direction[..., None, :], legs)
    rows = np.concatenate([legs, moments], axis=-1)
    spin = np.concatenate([np.zeros_like(direction), direction], axis=-1)[..., None, :]
    return np.concatenate([rows, spin], axis=-2)


def jacobian_determinant(design, position, direction, normalise=True):
    """det :func:`leg_jacobian`, shape=[...]; with `normalise`, over the product of its row norms (``|·|`` ≤ 1).

    The normalised value (Hadamard's ratio) is dimensionless and 0 exactly at
    the singularities.
    """
    matrix = leg_jacobian(design, position, direction)
    value = np.linalg.det(matrix)
    if normalise:
        value = value / np.prod(np.linalg.norm(matrix, axis=-1), axis=-1)
    return value
