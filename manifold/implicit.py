"""Implicit manifolds M = Φ⁻¹(0) ⊂ K and Gauss-Newton projection onto them.

Derivatives of Φ are taken in the recentred chart of the ambient space
(:meth:`AmbientSpace.retract`)::

    Φ(p ⊕ v) = Φ(p) + DΦ(p) v + ½ D²Φ(p)(v, v) + O(|v|³)

Units. A tangent vector v carries joint rates of mixed units (radians and
lengths). Every rank decision, minimum-norm step and orthonormal basis here
uses the *dimensionless* coordinates ``u = v / s`` with s the factors' scales
(:attr:`AmbientSpace.tangent_scales`: 1 for angles, a characteristic length
for translations), i.e. the inner product ``⟨v, w⟩_s = Σᵢ vᵢ wᵢ / sᵢ²``. A
change of the length unit multiplies the translations and their scales by
the same factor, so no decision depends on it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from .ambient import AmbientSpace
from .errors import ProjectionError
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, numerical_rank

__all__ = [
    "ImplicitManifold",
    "residual",
    "scaled_jacobian",
    "project",
    "tangent_basis",
    "normal_basis",
    "constraint_curvature",
]


@dataclass(frozen=True, eq=False)
class ImplicitManifold:
    """The level set ``{p ∈ K : Φ(p) = 0}``.

    Parameters
    ----------
    ambient : AmbientSpace
    constraint : callable
        ``Φ(point) -> array, shape=[..., c]``.
    constraint_jacobian : callable
        ``DΦ(point) -> array, shape=[..., c, k]`` in the recentred chart.
    constraint_hessian : callable, optional
        ``D²Φ(point) -> array, shape=[..., c, k, k]``, symmetric in the last two axes.
    is_solution : callable, optional
        ``is_solution(point) -> bool``: an extra check that a zero of Φ is a
        point of M (for constraint maps with spurious zeros). Default: always true.
    """

    ambient: AmbientSpace
    constraint: Callable
    constraint_jacobian: Callable
    constraint_hessian: Optional[Callable] = None
    is_solution: Optional[Callable] = None


def residual(manifold, point):
    """Euclidean norm of Φ(point), shape=[...]."""
    return np.linalg.norm(manifold.constraint(point), axis=-1)


def scaled_jacobian(manifold, point):
    """DΦ(point)·diag(s): the constraint Jacobian in dimensionless tangent coordinates u = v / s.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[..., point_size]

    Returns
    -------
    jacobian : ndarray, shape=[..., c, k]
    """
    return np.asarray(manifold.constraint_jacobian(point), dtype=float) * manifold.ambient.tangent_scales


def project(manifold, point, tolerance=1e-12, max_iterations=60, max_step=None):
    """Gauss-Newton projection of one point onto M.

    Iterates ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))``: the step of least
    dimensionless length (see the module's note on units).

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    tolerance : float
        Stop when ``|Φ(p)| ≤ tolerance``.
    max_iterations : int
    max_step : float, optional
        Largest allowed norm of one step (a damped iteration); default unlimited.

    Returns
    -------
    projected : ndarray, shape=[point_size]

    Raises
    ------
    ProjectionError
        If the residual does not fall below `tolerance`, or the limit is a
        spurious zero of Φ rejected by ``manifold.is_solution``.
    """
    point = np.array(point, dtype=float)
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    value = manifold.constraint(point)
    for _ in range(max_iterations):
        if np.linalg.norm(value) <= tolerance:
            break
        step = -scales * np.linalg.lstsq(scaled_jacobian(manifold, point), value, rcond=1e-12)[0]
        norm = np.linalg.norm(step)
        if max_step is not None and norm > max_step:
            step *= max_step / norm
        point = ambient.retract(point, step)
        value = manifold.constraint(point)
    final = float(np.linalg.norm(value))
    if not np.isfinite(final) or final > tolerance:
        raise ProjectionError(
            f"Gauss-Newton projection did not converge: residual {final:.3g} "
            f"> tolerance {tolerance:.3g} after {max_iterations} iterations"
        )
    if manifold.is_solution is not None and not manifold.is_solution(point):
        raise ProjectionError("Gauss-Newton converged to a spurious zero of the constraint map")
    return point


def tangent_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Basis of ker DΦ(point), orthonormal for ⟨·,·⟩_s, and the rank decision behind it.

    At a regular point this is a basis of the tangent space T_pM; at a
    singular point of M it spans the (larger) kernel of DΦ. The rank is that
    of the dimensionless Jacobian DΦ·diag(s) (:func:`scaled_jacobian`), and
    the columns are joint-rate vectors ``s·u`` with u orthonormal: the
    columns are orthonormal for the dimensionless inner product
    ``⟨v, w⟩_s = Σᵢ vᵢ wᵢ / sᵢ²`` (Euclidean where every scale is 1).

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]

    Returns
    -------
    basis : ndarray, shape=[k, k - rank]
    decision : RankDecision
        The rank of DΦ(point)·diag(s).
    """
    jacobian = scaled_jacobian(manifold, point)
    decision = numerical_rank(jacobian, rtol=rtol, atol=atol)
    _, _, vh = np.linalg.svd(jacobian, full_matrices=True)
    return manifold.ambient.tangent_scales[:, None] * vh[decision.rank:].T, decision


def normal_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Orthonormal basis of the row space of DΦ(point)·diag(s) (the normal space in dimensionless
    coordinates u = v / s), shape=[k, rank]."""
    jacobian = scaled_jacobian(manifold, point)
    decision = numerical_rank(jacobian, rtol=rtol, atol=atol)
    _, _, vh = np.linalg.svd(jacobian, full_matrices=True)
    return vh[: decision.rank].T.copy()


def constraint_curvature(manifold, point, basis, rtol=DEFAULT_RTOL):
    """Ambient accelerations of curves on M: ``x''(u, w) = −s·(DΦ·s)⁺ D²Φ(Bu, Bw)``.

    For a curve ``p ⊕ x(t)`` on M with ``x'(0) = B u``, the second-order
    term of Φ(p ⊕ x(t)) = 0 gives ``DΦ x'' + D²Φ(Bu, Bu) = 0``; this returns
    the solution of that equation of least dimensionless norm ``|x''/s|`` for
    every pair of basis vectors.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    basis : array_like, shape=[k, d]
        Tangent vectors (columns), usually a tangent basis.

    Returns
    -------
    acceleration : ndarray, shape=[k, d, d]
        ``acceleration[:, i, j] = x''(bᵢ, bⱼ)``; symmetric in ``i, j``.
    """
    basis = np.asarray(basis, dtype=float)
    scales = manifold.ambient.tangent_scales
    hessian = manifold.constraint_hessian(point)
    second = np.einsum("cab,ai,bj->cij", hessian, basis, basis)
    pseudo_inverse = np.linalg.pinv(scaled_jacobian(manifold, point), rcond=rtol)
    return -scales[:, None, None] * np.einsum("kc,cij->kij", pseudo_inverse, second)
