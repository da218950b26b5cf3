"""Configurations along a path of M, and the singular configurations the path crosses.

A comparison "along a path through singularities" needs the singular
configurations themselves, not only points near them: between two
consecutive points of a path where ``det(E^½ Dπ T)`` (or ``det(H^½ Df T)``,
or the bordered ``det[DΦ·diag(s); (T/s)ᵀ]``) changes sign, with T an
orthonormal tangent basis carried continuously along the path, the path
crosses an actuator (or end-effector, or C-space) singularity, which
:func:`singular_crossings` locates by bisection on M.
"""

from __future__ import annotations

import numpy as np

from manifold import (
    DEFAULT_RTOL, ProjectionError, continue_curve, numerical_rank, project, scaled_jacobian, tangent_basis,
)

from .metrics import metric_root
from .survey import decision_blocks

__all__ = ["path_configurations", "singular_crossings"]


def path_configurations(model, point, count, step=0.05, direction=None, rtol=DEFAULT_RTOL):
    """Configurations along a curve of M through `point`, both ways (``count`` on each side at most).

    Continues M along `direction` (default the first tangent direction at
    `point`) with :func:`manifold.continue_curve`; for a one-degree-of-freedom
    mechanism this is the path of the mechanism itself, through every fold of
    its inputs or outputs.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    count : int
    step : float
        Distance between successive configurations (coordinate scales).
    direction : ndarray, shape=[k], optional
    rtol : float

    Returns
    -------
    points : ndarray, shape=[≤ 2 count + 1, point_size]
        In order along the path.
    steps : ndarray of int, shape=[≤ 2 count + 1]
        Signed index of each point along the path (0 at `point`).
    """
    if direction is None:
        direction = tangent_basis(model.manifold, point, rtol=rtol)[0][:, 0]
    sides = [continue_curve(model.manifold, point, sign * direction, length=count * step, step=step).points[1:]
             [:count] for sign in (-1.0, 1.0)]
    points = np.concatenate([sides[0][::-1], np.asarray(point, dtype=float)[None], sides[1]])
    steps = np.arange(-len(sides[0]), len(sides[1]) + 1)
    return points, steps


def _aligned_basis(model, point, previous, rtol):
    """A tangent basis at `point` turned to be closest to `previous` (orthogonal Procrustes in the inner product
    ``⟨v, w⟩_s = Σ vᵢ wᵢ / sᵢ²`` in which the bases are orthonormal: in the plain product of joint
    coordinates, a slide's scale s = 200 outweighs the angles, and the turn could mirror the basis between two
    close points)."""
    basis = tangent_basis(model.manifold, point, rtol=rtol)[0]
    if previous is None or basis.shape != previous.shape:
        return basis
    scales = model.manifold.ambient.tangent_scales[:, None]
    left, _, right = np.linalg.svd((basis / scales).T @ (previous / scales))
    return basis @ left @ right


def _raw_determinants(model, point, basis, jacobian=None):
    """``(det(E^½ Dπ T), det(H^½ Df T), det[DΦ·diag(s); (T/s)ᵀ])``, each None where the matrix is not square.

    The third is the classical test function of branch points in continuation (the Jacobian bordered by the
    carried tangent basis): it changes sign where the path crosses a simple bifurcation of M, a C-space
    singularity (a parallelogram flattening into an antiparallelogram). `jacobian`: DΦ·diag(s) at `point`,
    if the caller has it.
    """
    actuator = model.actuators @ basis
    values = [np.linalg.det(actuator) if actuator.shape[0] == actuator.shape[1] else None, None, None]
    if model.end_effector_dimension:
        output = metric_root(model.end_effector_metric) @ model.end_effector_jacobian(point) @ basis
        values[1] = np.linalg.det(output) if output.shape[0] == output.shape[1] else None
    scales = model.manifold.ambient.tangent_scales
    jacobian = scaled_jacobian(model.manifold, point) if jacobian is None else jacobian
    bordered = np.vstack([jacobian, (basis / scales[:, None]).T])
    values[2] = np.linalg.det(bordered) if bordered.shape[0] == bordered.shape[1] else None
    return values


def _determinants(model, point, basis, rtol):
    """:func:`_raw_determinants`, each None too where the rank decision of :func:`classify.classify`
    (:func:`classify.survey.decision_blocks`) finds the map singular: only the signs at regular points
    bracket a crossing (at a singular point, or along a branch singular throughout, the sign of a determinant
    that is zero but for rounding means nothing)."""
    jacobian = scaled_jacobian(model.manifold, point)
    values = _raw_determinants(model, point, basis, jacobian)
    blocks = decision_blocks(model, point, basis)
    for which, (block, scale) in enumerate((blocks[:2], blocks[2:])):
        if values[which] is not None and numerical_rank(block, rtol=rtol, scale=scale).rank < len(block):
            values[which] = None
    if values[2] is not None and numerical_rank(jacobian, rtol=rtol).rank < len(jacobian):
        values[2] = None
    return values


def singular_crossings(model, points, rtol=DEFAULT_RTOL, tolerance=1e-12, max_bisections=80):
    """The actuator and end-effector singularities crossed between consecutive points of a path.

    With T carried continuously along the path (each basis turned to the
    previous one), ``det(E^½ Dπ T)`` and ``det(H^½ Df T)`` are continuous; a
    sign change between two consecutive points, both regular for the kind
    (the rank decision of :func:`classify.classify`), brackets a singularity,
    found by bisection: the midpoint ``p ⊕ ½ (q ⊖ p)`` projected back onto M.
    A singular point of the path (its start, say) is no crossing: it is on
    the path already. Only square maps (as many inputs, or outputs, as
    degrees of freedom) are followed. A C-space singularity the path crosses
    (a simple bifurcation of M) is found the same way from the sign of
    ``det[DΦ·diag(s); (T/s)ᵀ]`` where DΦ has full row rank on M (not for an
    overconstrained chain).

    Parameters
    ----------
    model : Model
    points : array_like, shape=[count, point_size]
        Consecutive points of a curve of M, closely spaced (as from
        :func:`path_configurations`).
    rtol : float
    tolerance : float
        Bisect until the bracket is shorter than this (coordinate scales).
    max_bisections : int

    Returns
    -------
    list of (int, ndarray, str)
        ``(index, point, "actuator" | "end_effector" | "cspace")`` in order along the
        path: the singular point lies between ``points[index]`` and
        ``points[index + 1]``.
    """
    manifold, ambient = model.manifold, model.manifold.ambient
    scales = ambient.tangent_scales
    points = np.asarray(points, dtype=float)
    bases, values = [], []
    for point in points:
        bases.append(_aligned_basis(model, point, bases[-1] if bases else None, rtol))
        values.append(_determinants(model, point, bases[-1], rtol))
    found = []
    for index in range(len(points) - 1):
        for which, kind in enumerate(("actuator", "end_effector", "cspace")):
            first, second = values[index][which], values[index + 1][which]
            if first is None or second is None or first * second >= 0:
                continue
            low, high, low_basis, low_value, high_value = points[index], points[index + 1], bases[index], first, second
            found_kind = kind
            for _ in range(max_bisections):
                if np.linalg.norm(ambient.inverse_retract(low, high) / scales) < tolerance:
                    break
                try:
                    middle = project(manifold, ambient.retract(low, 0.5 * ambient.inverse_retract(low, high)))
                except ProjectionError:
                    break
                middle_basis = _aligned_basis(model, middle, low_basis, rtol)
                middle_value = _raw_determinants(model, middle, middle_basis)[which]
                if middle_value is None:  # ker DΦ grew: the midpoint is a C-space singularity (to the rank cut)
                    low = high = middle
                    low_value = high_value = 0.0
                    found_kind = "cspace"
                    break
                if middle_value * low_value > 0:
                    low, low_basis, low_value = middle, middle_basis, middle_value
                else:
                    high, high_value = middle, middle_value
            if found_kind == kind or (index, found_kind) not in [(item[0], item[2]) for item in found]:
                found.append((index, low if abs(low_value) < abs(high_value) else high, found_kind))
    return found
