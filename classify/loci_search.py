"""Singularities searched for as the zeros of a singular value on M: C-space, and actuator under redundancy.

Besides the C-space points the traced curves pass through, 1- and 2-dof
loci with the kind ``cspace`` search for them deliberately
(:func:`search_cspace`): σ_r, the r-th singular value of DΦ·diag(s) (r the
constraint rank of M's regular points), vanishes on M exactly at the
C-space singularities (Park & Kim 1999, Section 3), so from the points
where σ_r is locally smallest — over the assembled grid (2 dof), along the
traced branches (1 dof) — Gauss–Newton on ``(Φ, σ_r)`` finds the C-space
singularities near them whether or not an actuator or end-effector locus
passes through them. The coverage's ``cspace_search`` counts the seeds, the
points found and those the classification confirms.

With more actuated coordinates than degrees of freedom, the actuator
singularities are the zeros of the smallest singular value of the stacked
constraint and actuator rows (:func:`redundant_actuator_function`), searched
for the same way.

References
----------
Park & Kim 1999, Section 3.
"""

from __future__ import annotations

import numpy as np

from .loci_curves import _DIFFERENCE, TOLERANCE, _distances, _residuals

__all__ = ["CSPACE_TOLERANCE", "CSPACE_ITERATIONS", "cspace_function", "redundant_actuator_function",
           "search_cspace"]

#: ‖(Φ, σ_r)‖ of a C-space singularity found by :func:`search_cspace` (σ_r's gradient is a difference quotient
#: of DΦ, step 1e-6, whose error keeps σ_r from falling much below 1e-9), and the most Gauss–Newton steps to it
CSPACE_TOLERANCE = 1e-8
CSPACE_ITERATIONS = 200


def cspace_function(model, rank):
    """σ_r(p), the r-th largest singular value of DΦ(p)·diag(s), and its gradient on the ambient space.

    Zero on M iff rank DΦ < r, r the constraint rank of M's regular points: a
    C-space singularity (Park & Kim 1999, Section 3). Its gradient in the
    tangent coordinates is ``∂_j σ_r = u_rᵀ ∂_j(DΦ·diag(s)) v_r`` (u_r, v_r the
    singular vectors of σ_r; ∂_j DΦ by central differences, step 1e-6,
    dimensionless), the derivative of σ_r wherever it is a simple singular
    value, and a one-sided one at σ_r = 0.

    Parameters
    ----------
    model : Model
    rank : int
        r (the survey's constraint rank).

    Returns
    -------
    value : callable
        ``value(points [n, point_size]) -> [n]``.
    gradient : callable
        ``gradient(points [n, point_size]) -> [n, k]``.
    """
    manifold = model.manifold
    scales = manifold.ambient.tangent_scales

    def jacobian(points):
        return np.asarray(manifold.constraint_jacobian(points), dtype=float) * scales

    return _singular_value_function(manifold.ambient, jacobian, rank)


def redundant_actuator_function(model):
    """σ_k(p), the k-th (smallest) singular value of ``[DΦ(p)·diag(s); U·diag(s)]``, and its gradient.

    U the unit actuator rows (as :func:`~classify.loci_signs.sign_functions`). With more actuated
    coordinates than degrees of freedom (redundant actuation: r + a > k) the
    stacked matrix is not square, and the actuator singularities — ker DΦ ∩
    ker Dπ ≠ 0, a motion with every actuator still (Park & Kim 1999,
    Section 3) — are where its rank drops below k: the zeros of σ_k on M,
    which does not change sign there (so they are searched for, as the
    C-space singularities are, not traced by a sign change).

    Parameters
    ----------
    model : Model

    Returns
    -------
    value : callable
        ``value(points [n, point_size]) -> [n]``.
    gradient : callable
        ``gradient(points [n, point_size]) -> [n, k]`` (as :func:`cspace_function`).
    """
    from .survey import unit_actuator_rows

    manifold = model.manifold
    scales = manifold.ambient.tangent_scales
    actuators = unit_actuator_rows(model)[0] * scales

    def stacked(points):
        points = np.asarray(points, dtype=float)
        constraint_rows = np.asarray(manifold.constraint_jacobian(points), dtype=float) * scales
        return np.concatenate([constraint_rows, np.broadcast_to(actuators, points.shape[:-1] + actuators.shape)],
                              axis=-2)

    return _singular_value_function(manifold.ambient, stacked, manifold.ambient.dim)


def _singular_value_function(ambient, matrix, index):
    """The `index`-th largest singular value of ``matrix(points)`` [n, rows, k] and its gradient
    ``u_iᵀ ∂_j matrix v_i`` (∂_j by central differences, step 1e-6 dimensionless)."""
    scales = ambient.tangent_scales

    def value(points):
        return np.linalg.svd(matrix(np.atleast_2d(points)), compute_uv=False)[:, index - 1]

    def gradient(points):
        points = np.atleast_2d(points)
        left, _, right = np.linalg.svd(matrix(points))
        steps = np.eye(ambient.dim) * (_DIFFERENCE * scales)
        forward = matrix(ambient.retract(points[:, None, :], steps[None]))
        backward = matrix(ambient.retract(points[:, None, :], -steps[None]))
        derivative = (forward - backward) / (2 * _DIFFERENCE * scales)[None, :, None, None]
        return np.einsum("nc,njcd,nd->nj", left[:, :, index - 1], derivative, right[:, index - 1, :])

    return value, gradient


def _zero_manifold(model, value, gradient):
    """{Φ = 0, σ = 0} (σ a singular-value function: :func:`cspace_function`, :func:`redundant_actuator_function`)
    as an implicit manifold, for the Gauss–Newton corrector."""
    from manifold import ImplicitManifold

    manifold = model.manifold

    def constraint(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        rows = np.concatenate([np.asarray(manifold.constraint(flat), dtype=float), value(flat)[:, None]], axis=-1)
        return rows.reshape(points.shape[:-1] + rows.shape[-1:])

    def jacobian(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        rows = np.concatenate([np.asarray(manifold.constraint_jacobian(flat), dtype=float).reshape(
            len(flat), -1, manifold.ambient.dim), gradient(flat)[:, None, :]], axis=1)
        return rows.reshape(points.shape[:-1] + rows.shape[-2:])

    return ImplicitManifold(ambient=manifold.ambient, constraint=constraint, constraint_jacobian=jacobian,
                            is_solution=manifold.is_solution)


def search_cspace(model, survey, seeds, step):
    """C-space singularities searched for from seed configurations: each seed corrected onto {Φ = 0, σ_r = 0}.

    Gauss–Newton (:func:`manifold.project`, steps of at most 4 `step`) on
    ``(Φ, σ_r)`` (:func:`cspace_function`) from each seed, to ``‖(Φ, σ_r)‖ ≤``
    :data:`CSPACE_TOLERANCE` in at most :data:`CSPACE_ITERATIONS` steps
    (at a C-space singularity, where branches cross, the Jacobian of
    ``(Φ, σ_r)`` loses rank and Gauss–Newton converges only linearly, halving
    σ_r about every other step), then Φ to :data:`~classify.loci_curves.TOLERANCE` on M; a seed
    whose corrector fails, or that lands within `step` of a point already
    found, gives nothing. A search, not a trace:
    it finds the C-space singularities near the seeds whether or not an
    actuator or end-effector locus passes through them (the caller confirms
    them with the classification).

    Parameters
    ----------
    model : Model
    survey : Survey
    seeds : ndarray, shape=[n, point_size]
        Configurations on (or near) M: local minima of σ_r over a grid or along a branch.
    step : float
        Dimensionless: the corrector's step bound / 4, and the distance under which two points are one.

    Returns
    -------
    points : ndarray, shape=[m, point_size]
    residuals : ndarray, shape=[m]
        ``‖(Φ, σ_r)‖`` at each.
    """
    return _search_zeros(model, *cspace_function(model, survey.constraint_rank), seeds, step)


def _search_zeros(model, value, gradient, seeds, step):
    """The zeros on M of a singular-value function near the seeds (:func:`search_cspace`)."""
    from manifold import project_each

    curve = _zero_manifold(model, value, gradient)
    ambient = curve.ambient
    near, reached = project_each(curve, np.atleast_2d(seeds), tolerance=CSPACE_TOLERANCE,
                                 max_iterations=CSPACE_ITERATIONS, max_step=4 * step)
    near, reached = project_each(model.manifold, near[reached], tolerance=TOLERANCE)  # Φ to the loci's (≪ 1e-8)
    found = []
    for on in near[reached]:  # project_each applied is_solution (the curve's is M's)
        if found and _distances(ambient, on[None], np.array(found))[0] < step:
            continue
        found.append(on)
    points = np.array(found).reshape(-1, ambient.point_size)
    return points, _residuals(curve, points) if len(points) else np.zeros(0)
