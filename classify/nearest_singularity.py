"""The actuator singularity nearest a point that the first-order test calls singular.

The first-order test calls p̄ actuator-singular when the actuator block's
next singular value is below its cut (relative 1e-6, :func:`manifold.numerical_rank`):
a point 1e-9 from a degenerate singularity along M is called singular, but
the fibre of the actuators through it is no curve (its inputs are those of a
regular point), so no self-motion can be certified from it and the second
order test would end undetermined (a five-bar at Park & Kim 1999 §3.4's
coincident elbows, moved 1e-11 along M). The self-motion is certified
instead from the point p* nearest p̄ where the rank has really dropped,
found by Gauss–Newton steps of least norm on the extended system of a
singular point (Moore & Spence, *The calculation of turning points of
nonlinear equations*, SIAM J. Numer. Anal. 17, 1980, with the
normalisation ``lᵀφ = 1``; here κ kernel vectors at once)::

    Φ(q) = 0,   DΦ(q) W = 0,   S W = 0,   W₀ᵀ W = I,

with W (k×κ) a basis of the locked-actuator motions at q (S: the actuator
rows), W₀ that at p̄ (κ = dim ker G at p̄): at a solution dim ker G ≥ κ,
the rank p̄ was given. W keeps its components from one recentred chart to
the next, so the derivative of DΦ W along a step adds the charts' bracket
(:meth:`manifold.AmbientSpace.bracket`) to D²Φ. Everything is in dimensionless coordinates
u = δ / s, so that p* depends neither on the unit of length nor on the
tangent basis. The search only proposes p*; the verdict stays with the
self-motion certificate from p*, which must pass at its own cut.
"""

from __future__ import annotations

import numpy as np

from manifold import hessian_form, scaled_jacobian

__all__ = ["NEAREST_SINGULARITY_DISTANCE", "nearest_singularity"]

#: farthest p* may lie from p̄ (dimensionless ‖(p* ⊖ p̄)/s‖): a point called singular at the first-order cut
#: rtol = 1e-6 lies about rtol·σ₁/‖∇σ‖ from the singular set (7e-6 at the five-bar's coincident elbows); 100·rtol
#: leaves room, and stays 100 times below the certificate's first step
NEAREST_SINGULARITY_DISTANCE = 1e-4
#: Gauss–Newton steps at most (the extended system is regular at a generic point of the singular set:
#: quadratic convergence, three or four steps from a point at the cut)
NEAREST_SINGULARITY_STEPS = 12


def nearest_singularity(manifold, point, kernel, selection, max_steps=NEAREST_SINGULARITY_STEPS):
    """The point p* of M nearest `point` where the locked-actuator motions span at least `kernel`'s dimension.

    Parameters
    ----------
    manifold : ImplicitManifold
        M (or a slice of it), with its constraint Hessian or Hessian form (:func:`manifold.hessian_form`).
    point : ndarray, shape=[point_size]
        p̄, a point of M called actuator-singular.
    kernel : ndarray, shape=[k, κ]
        The locked-actuator motions at p̄ (ker G as joint-rate vectors), κ ≥ 1.
    selection : ndarray, shape=[a, k]
        The actuator rows (dimensionless, :func:`classify.metrics.unit_rows`).
    max_steps : int

    Returns
    -------
    nearest : ndarray, shape=[point_size]
        p*: the last iterate, where the residual of the extended system stopped falling.
    distance : float
        ‖(p* ⊖ p̄)/s‖, dimensionless.
    residual : float
        ‖(Φ, DΦ W, S W, W₀ᵀW − I)‖ at p*.

    Examples
    --------
    A parabola π = q₁ − q₀² on the line: the actuator q₁ alone is singular only at q₀ = 0.

    >>> from classify.nearest_singularity import nearest_singularity
    >>> from manifold import AmbientSpace, ImplicitManifold
    >>> line = ImplicitManifold(AmbientSpace(("R", "R")), lambda q: q[..., 1:] - q[..., :1] ** 2,
    ...                         lambda q: np.stack([-2 * q[..., :1], np.ones_like(q[..., :1])], axis=-1),
    ...                         constraint_hessian=lambda q: np.array([[[-2.0, 0.0], [0.0, 0.0]]]))
    >>> nearest, distance, residual = nearest_singularity(line, np.array([1e-7, 1e-14]),
    ...                                                   np.array([[1.0], [2e-7]]), np.array([[0.0, 1.0]]))
    >>> bool(np.allclose(nearest, 0.0, atol=1e-20)), residual < 1e-20
    (True, True)
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    size = len(scales)
    start = np.asarray(point, dtype=float)
    reference = np.linalg.qr(np.asarray(kernel, dtype=float) / scales[:, None])[0]       # W₀ / s, orthonormal
    count = reference.shape[1]
    identity = np.eye(count)
    scaled_selection = np.asarray(selection, dtype=float) * scales

    def residual_of(current, motions):
        return np.concatenate([np.ravel(manifold.constraint(current)),
                               np.ravel(scaled_jacobian(manifold, current) @ motions),
                               np.ravel(scaled_selection @ motions), np.ravel(reference.T @ motions - identity)])

    current, motions = start, reference.copy()
    residual = residual_of(current, motions)
    norm = float(np.linalg.norm(residual))
    for _ in range(max_steps):
        if norm == 0.0:
            break
        jacobian = scaled_jacobian(manifold, current)                                      # [n, k]
        # d/du [DΦ(q ⊕ s u) W] at u = 0: D²Φ(s eᵢ, W) in the chart at q, and the charts' bracket (W keeps its
        # components from one chart to the next)
        directions, vectors = np.diag(scales), motions * scales[:, None]
        curvature = (hessian_form(manifold, current, directions, vectors)
                     + np.einsum("nl,lij->nij", jacobian / scales, ambient.bracket(directions, vectors)))  # [n, k, κ]
        rows = jacobian.shape[0]
        by_point = np.concatenate([jacobian, curvature.transpose(0, 2, 1).reshape(rows * count, size),
                                   np.zeros((len(scaled_selection) * count + count * count, size))])
        by_motions = np.concatenate([np.zeros((rows, size * count)), np.kron(jacobian, identity),
                                     np.kron(scaled_selection, identity), np.kron(reference.T, identity)])
        step = np.linalg.lstsq(np.concatenate([by_point, by_motions], axis=1), residual, rcond=None)[0]
        candidate = ambient.retract(current, -scales * step[:size])
        candidate_motions = motions - step[size:].reshape(size, count)
        candidate_residual = residual_of(candidate, candidate_motions)
        candidate_norm = float(np.linalg.norm(candidate_residual))
        if not candidate_norm < norm:
            break
        current, motions, residual, norm = candidate, candidate_motions, candidate_residual, candidate_norm
    distance = float(np.linalg.norm(ambient.inverse_retract(start, current) / scales))
    return current, distance, norm
