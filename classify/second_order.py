"""Second-order test: degenerate vs nondegenerate actuator singularities.

Park & Kim (1999, eqs. 9-10) separate the two cases
by the Hessian of ``f(p) = ½|π(p) − π(p̄)|²`` on M at p̄. In any chart u
of M, ``∂²f/∂uᵢ∂uⱼ(p̄) = Σ_a ∂π_a/∂uᵢ ∂π_a/∂uⱼ`` (the terms with
``π − π(p̄)`` vanish at p̄), i.e. the Hessian *is* G. At every actuator
singularity it is singular, so the test read literally cannot separate the
cases (the paper warns with x⁴ + y⁴). We test at the order where it works
(docs/second_order.rst):

* K = ker G ⊂ T_pM (locked-actuator infinitesimal motions), C = the
  orthogonal complement of range(Dπ T) in actuator space.
* For v ∈ K the actuators' second derivative along M is
  ``a''(v) = Dπ x''(v, v)``, ``x''(v, v) = −DΦ⁺ D²Φ(Tv, Tv)``; its
  components ``Q_e(v) = ⟨e, a''(v)⟩`` for a basis e of C are quadratic forms
  on K, and along K ``f ≈ ⅛ Σ_e Q_e(v)²``.
* nondegenerate: no common nonzero root of the Q_e on K (p̄ is isolated in
  its fibre);
* degenerate: a self-motion, certified by continuing the fibre
  ``{Φ = 0, π = π(p̄)}`` from p̄ along a common root to a finite distance;
* undetermined: the forms have a common root but no self-motion is found.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
import scipy.optimize

from manifold import ImplicitManifold, constraint_curvature, continue_curve, numerical_rank, tangent_basis

__all__ = [
    "SECOND_ORDER_RTOL", "SelfMotion", "SecondOrderResult", "second_order_test", "fibre", "idle_slice",
]

#: forms count as vanishing at v when sqrt(Σ Q_e(v)²) ≤ SECOND_ORDER_RTOL · c · s, with c the largest
#: ambient acceleration of unit-speed curves of M at p (at least 1) and s = σ₁(E^½ Dπ) (the actuator weights)
SECOND_ORDER_RTOL = 1e-6


@dataclass(frozen=True, eq=False)
class SelfMotion:
    """Certificate of a self-motion: a curve in the fibre of π through p̄.

    Attributes
    ----------
    direction : ndarray, shape=[k]
        Initial direction (joint rates), unit length.
    distance : float
        Distance reached from p̄ (scaled chart units).
    largest_residual : float
        Largest ‖(Φ, π − π(p̄))‖ along the curve.
    points : ndarray, shape=[steps, point_size]
    """

    direction: np.ndarray
    distance: float
    largest_residual: float
    points: np.ndarray


@dataclass(frozen=True, eq=False)
class SecondOrderResult:
    """Outcome of the second-order test.

    Attributes
    ----------
    degeneracy : {"degenerate", "nondegenerate", "undetermined"}
    forms : ndarray, shape=[c, κ, κ]
        The quadratic forms Q_e on K in an orthonormal basis of K.
    kernel : ndarray, shape=[k, κ]
        Basis of K as joint-rate vectors.
    smallest : float
        min over unit v ∈ K of sqrt(Σ Q_e(v)²): the margin of the decision.
    tolerance : float
    root : ndarray or None, shape=[k]
        The (near) common root, as a joint-rate vector.
    self_motion : SelfMotion or None
    reason : str
    """

    degeneracy: str
    forms: np.ndarray
    kernel: np.ndarray
    smallest: float
    tolerance: float
    root: Optional[np.ndarray]
    self_motion: Optional[SelfMotion]
    reason: str


def fibre(manifold, point, selection):
    """The fibre ``{q : Φ(q) = 0, S·(q ⊖ p̄) = 0}`` of the actuated coordinates through p̄.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : ndarray, shape=[point_size]
        p̄.
    selection : ndarray, shape=[a, k]
        Rows selecting the actuated coordinates (real or circle factors only).

    Returns
    -------
    ImplicitManifold
    """
    ambient = manifold.ambient
    base = np.asarray(point, dtype=float)

    def constraint(q):
        return np.concatenate([manifold.constraint(q), selection @ ambient.inverse_retract(base, q)], axis=-1)

    def jacobian(q):
        return np.concatenate([manifold.constraint_jacobian(q), selection], axis=-2)

    return ImplicitManifold(ambient, constraint, jacobian, is_solution=manifold.is_solution)


def idle_slice(manifold, point, basis, neighbours, selection, idle, rtol=1e-6):
    """M cut through p̄ transversally to its idle freedoms: ``M ∩ {Iᵀ(q ⊖ p̄) = 0}``.

    With idle freedoms (G of rank m − ι everywhere on M) every fibre of the
    actuators contains the ι-dimensional orbits of those freedoms, so the
    second-order test must look for self-motions *beyond* them. I, the idle
    directions at p̄, is the limit of ker G(q) at regular points q of M near
    p̄: the ι leading eigenvectors of the mean of the projectors onto
    ker G(q) over `neighbours` (the ι smallest right singular vectors of
    E^½Dπ at q), projected onto T_p̄M. On the slice, G has no
    idle freedom, and p̄ is isolated in the slice's fibre exactly when the
    fibre of M near p̄ is the idle orbit of p̄: the test run on the slice
    separates nondegenerate from degenerate (a self-motion on the slice is a
    genuine finite motion with the actuators locked, other than the idle one).

    Parameters
    ----------
    manifold : ImplicitManifold
    point : ndarray, shape=[point_size]
        p̄, a regular point of M.
    basis : ndarray, shape=[k, m]
        Orthonormal basis of T_p̄M.
    neighbours : ndarray, shape=[n, point_size]
        Points of M near p̄ (e.g. :attr:`manifold.LocalRank.neighbours`).
    selection : ndarray, shape=[a, k]
        Dπ (optionally weighted).
    idle : int
        ι, m minus the largest rank of G on M.
    rtol : float
        Rank cut of DΦ at the neighbours.

    Returns
    -------
    slice : ImplicitManifold or None
        None when no neighbour is a regular point of M.
    directions : ndarray, shape=[k, ι]
        I, orthonormal.
    """
    expected = basis.shape[1] - idle
    projector = np.zeros((basis.shape[0],) * 2)
    used = 0
    for neighbour in neighbours:
        tangent, _ = tangent_basis(manifold, neighbour, rtol=rtol)
        if tangent.shape[1] != basis.shape[1]:
            continue
        # the ι smallest right singular vectors: G has rank ≤ m − ι everywhere, so they are exact
        # kernel vectors, while the singularity's own small singular values grow with the distance
        kernel = tangent @ np.linalg.svd(selection @ tangent, full_matrices=True)[2][expected:].T
        projector += kernel @ kernel.T
        used += 1
    if not used:
        return None, np.zeros((basis.shape[0], 0))
    leading = np.linalg.eigh(projector / used)[1][:, ::-1][:, :idle]
    directions = np.linalg.qr(basis @ (basis.T @ leading))[0]
    ambient = manifold.ambient
    base = np.asarray(point, dtype=float)

    def constraint(q):
        return np.concatenate([manifold.constraint(q), ambient.inverse_retract(base, q) @ directions], axis=-1)

    def jacobian(q):
        rows = np.broadcast_to(directions.T, np.shape(q)[:-1] + directions.T.shape)
        return np.concatenate([manifold.constraint_jacobian(q), rows], axis=-2)

    def hessian(q):
        zeros = np.zeros(np.shape(q)[:-1] + (idle,) + (basis.shape[0],) * 2)
        return np.concatenate([manifold.constraint_hessian(q), zeros], axis=-3)

    return ImplicitManifold(ambient, constraint, jacobian, hessian, manifold.is_solution), directions


def _smallest_common_value(forms, rng, starts=64):
    """min over the unit sphere of sqrt(Σ_e (vᵀ Q_e v)²) and its argmin.

    dim K = 1: exact. dim K = 2: a dense scan of the half circle v = (cos t, sin t)
    refined by bounded minimisation (deterministic). Higher dimensions: the best of
    `starts` random unit vectors refined by least squares (a missed common root is possible; the
    reported minimum shows the margin).
    """
    dimension = forms.shape[-1]
    if forms.shape[0] == 0:
        return 0.0, np.eye(dimension)[:, 0]

    def value(vector):
        vector = vector / np.linalg.norm(vector)
        return float(np.sqrt(np.sum(np.einsum("i,eij,j->e", vector, forms, vector) ** 2)))

    if dimension == 1:
        return value(np.ones(1)), np.ones(1)
    if dimension == 2:
        angles = np.linspace(0.0, np.pi, 721)
        values = [value(np.array([np.cos(a), np.sin(a)])) for a in angles]
        best = int(np.argmin(values))
        step = angles[1] - angles[0]
        result = scipy.optimize.minimize_scalar(lambda a: value(np.array([np.cos(a), np.sin(a)])),
                                                bounds=(angles[best] - step, angles[best] + step),
                                                method="bounded", options={"xatol": 1e-12})
        angle = result.x if result.fun <= values[best] else angles[best]
        vector = np.array([np.cos(angle), np.sin(angle)])
        return value(vector), vector
    candidates = rng.standard_normal((starts, dimension))
    best = min(candidates, key=value)

    def residuals(vector):
        vector = vector / np.linalg.norm(vector)
        return np.einsum("i,eij,j->e", vector, forms, vector)

    result = scipy.optimize.least_squares(residuals, best / np.linalg.norm(best), xtol=1e-15, ftol=1e-15,
                                          gtol=1e-15)
    vector = result.x / np.linalg.norm(result.x)
    if value(vector) > value(best):
        vector = best / np.linalg.norm(best)
    return value(vector), vector


def second_order_test(manifold, point, basis, selection, rng, rtol=1e-6, scale=None,
                      second_order_rtol=SECOND_ORDER_RTOL, length=0.1, step=0.01):
    """Classify an actuator singularity as degenerate, nondegenerate or undetermined.

    Parameters
    ----------
    manifold : ImplicitManifold
        The C-space, with its constraint Hessian.
    point : ndarray, shape=[point_size]
        p̄, a regular point of M at an actuator singularity.
    basis : ndarray, shape=[k, m]
        Orthonormal basis T of T_pM.
    selection : ndarray, shape=[a, k]
        Dπ (optionally weighted).
    rng : numpy.random.Generator
    rtol : float
        Relative cut for the rank of Dπ T, as in :func:`manifold.numerical_rank`.
    scale : float, optional
        Reference scale of that cut; default σ₁(Dπ).
    second_order_rtol : float
        Relative cut for the forms (see :data:`SECOND_ORDER_RTOL`).
    length, step : float
        Continuation length and step for the self-motion certificate.

    Returns
    -------
    SecondOrderResult
    """
    block = selection @ basis
    left, _, right = np.linalg.svd(block, full_matrices=True)
    scale = float(np.linalg.norm(selection, 2)) if scale is None else scale
    rank = numerical_rank(block, rtol=rtol, scale=scale).rank
    kernel_coordinates = right[rank:].T                      # [m, κ]
    complement = left[:, rank:]                              # [a, c]
    kernel = basis @ kernel_coordinates                      # [k, κ]
    curvature = constraint_curvature(manifold, point, kernel)          # [k, κ, κ]
    forms = np.einsum("ae,ak,kij->eij", complement, selection, curvature)
    curvature_scale = max(1.0, float(np.max(np.abs(constraint_curvature(manifold, point, basis)), initial=0.0)))
    tolerance = second_order_rtol * curvature_scale * scale
    smallest, vector = _smallest_common_value(forms, rng)
    if smallest > tolerance:
        return SecondOrderResult("nondegenerate", forms, kernel, smallest, tolerance, None, None,
                                 "the forms Q_e have no common nonzero root on ker G")
    root = kernel @ vector
    along = fibre(manifold, point, selection)
    for sign in (1.0, -1.0):
        certificate = continue_curve(along, point, sign * root, length=length, step=step)
        if certificate.reached:
            motion = SelfMotion(certificate.direction, certificate.distance,
                                certificate.largest_residual, certificate.points)
            return SecondOrderResult("degenerate", forms, kernel, smallest, tolerance, root, motion,
                                     "the fibre of the actuators continues along a common root")
    return SecondOrderResult("undetermined", forms, kernel, smallest, tolerance, root, None,
                             "the forms Q_e vanish on a direction of ker G but no self-motion was found "
                             "(higher order needed)")
