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

Sparsity. A manifold may declare where DΦ can be nonzero
(:class:`JacobianPattern`, with ``constraint_jacobian_entries`` giving the
entries there): after permuting rows and columns DΦ is block diagonal
(:mod:`manifold.blocks`). From :data:`BLOCK_THRESHOLD` coordinates on
(:func:`handled_by_blocks`), :func:`project`, :func:`jacobian_rank`,
:func:`tangent_basis`, :func:`normal_basis` and :func:`constraint_curvature` work block by block
(blocks of one shape in one batched SVD): the same decisions (every cut is
relative to σ₁ of the whole DΦ, as for the dense matrix) at a cost that
grows with the blocks, not with k². Below the threshold everything is dense,
as for any manifold without a pattern. D²Φ is contracted by
``constraint_hessian_form`` where the manifold gives one
(:func:`hessian_form`), never formed as a c×k×k array.
:func:`project_many` projects a stack of points at once, and
:func:`minimum_norm_steps` gives Gauss-Newton's steps for a stack, block by
block there too (blocks of one shape of every point in one batched SVD).
A block's rows depend on its columns only, and no two blocks share a row or
a column, so M is the product of the blocks' zero sets and the free
columns: :func:`settle_blocks` projects a stack of far points block by
block, drawing again the blocks that do not settle (a random start in a
product of many loops nearly always has one loop stuck).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np

from . import blocks as blocks_module
from .ambient import AmbientSpace
from .blocks import JacobianPattern, apply_pseudo_inverse, block_rank, block_vectors, decompose
from .errors import ProjectionError
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, numerical_rank, rank_of_values

__all__ = [
    "BLOCK_THRESHOLD",
    "SPARSE_BLOCK_COLUMNS",
    "CHUNK_ENTRIES",
    "JacobianPattern",
    "ImplicitManifold",
    "handled_by_blocks",
    "residual",
    "scaled_jacobian",
    "jacobian_rank",
    "hessian_form",
    "project",
    "settle_blocks",
    "project_many",
    "project_each",
    "jacobian_ranks",
    "takes_stacks",
    "minimum_norm_steps",
    "scaled_singular_values",
    "tangent_basis",
    "sparse_tangent_basis",
    "normal_basis",
    "constraint_curvature",
]

#: from this many coordinates k on, a manifold with a :class:`JacobianPattern` is handled block by block
#: (below it, dense: small mechanisms keep exactly the dense computations)
BLOCK_THRESHOLD = 64
#: blocks with more columns than this are solved by LSQR (scipy.sparse) in projection steps, not by a dense SVD
SPARSE_BLOCK_COLUMNS = 1024
#: relative cut of the minimum-norm Gauss-Newton step (as ``numpy.linalg.lstsq(rcond=...)``)
STEP_RCOND = 1e-12
#: floats of work memory per chunk of array work: of :func:`constraint_curvature` per chunk of basis columns on
#: the block path, and of the callers that read it at call time to size their own chunks
CHUNK_ENTRIES = 2 ** 20
#: a projection handled block by block stops when the residual fell by less than 1% over this many iterations
STALL_WINDOW = 10
#: damping of a damped projection's first step, and its bounds, relative to σ₁² of DΦ·diag(s): the
#: Levenberg-Marquardt step ``−(JᵀJ + μ σ₁² I)⁻¹ Jᵀ Φ``; μ shrinks 10× after a step that lowers ‖Φ‖ and
#: grows 4× after one that does not, and the search gives up past the largest (a critical point of ‖Φ‖²
#: that is no zero). The smallest, STEP_RCOND², leaves the step Gauss-Newton's along every singular value
#: above Gauss-Newton's own cut (σ ≥ STEP_RCOND σ₁), so a well-posed but ill-conditioned map converges
DAMPING_START, DAMPING_SMALLEST, DAMPING_LARGEST = 1e-3, STEP_RCOND ** 2, 1e8


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
    pattern : JacobianPattern, optional
        Where DΦ can be nonzero (constant over K). With
        `constraint_jacobian_entries`, large manifolds are handled block by
        block (see the module's note on sparsity).
    constraint_jacobian_entries : callable, optional
        ``entries(point) -> array, shape=[..., nnz]``: DΦ at the pattern, in its order.
    constraint_hessian_form : callable, optional
        ``form(point, left, right) -> array, shape=[..., c, i, j]``:
        ``D²Φ(point)(left[:, i], right[:, j])`` without the c×k×k Hessian.
    closing : ImplicitManifold, optional
        The same M as the zero set of another map without Φ's spurious zeros, with its Jacobian:
        :func:`manifold.sample_manifold` projects random points of K onto it first, then onto
        Φ (e.g. a mechanism's loops, whose Φ also vanishes at half-turns).
    """

    ambient: AmbientSpace
    constraint: Callable
    constraint_jacobian: Callable
    constraint_hessian: Optional[Callable] = None
    is_solution: Optional[Callable] = None
    pattern: Optional[JacobianPattern] = None
    constraint_jacobian_entries: Optional[Callable] = None
    constraint_hessian_form: Optional[Callable] = None
    closing: Optional["ImplicitManifold"] = None


def handled_by_blocks(manifold):
    """Whether the functions here take DΦ of `manifold` block by block (see the module's note on sparsity).

    So they do when the manifold declares where DΦ can be nonzero (a
    :class:`JacobianPattern`) with ``constraint_jacobian_entries`` giving
    the entries there, and has at least :data:`BLOCK_THRESHOLD` coordinates
    k (read at call time); else DΦ is taken densely, as for any manifold
    without a pattern. Callers that work on stacks of points ask it too, to
    take the path the single calls take.

    Parameters
    ----------
    manifold : ImplicitManifold

    Returns
    -------
    bool
    """
    return (manifold.pattern is not None and manifold.constraint_jacobian_entries is not None
            and manifold.pattern.shape[1] >= BLOCK_THRESHOLD)


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


def jacobian_rank(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """The rank decision of DΦ(point)·diag(s) (:func:`manifold.numerical_rank`), block by block when
    the manifold has a pattern and k ≥ :data:`BLOCK_THRESHOLD`.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]

    Returns
    -------
    decision : RankDecision
    """
    if not handled_by_blocks(manifold):
        return numerical_rank(scaled_jacobian(manifold, point), rtol=rtol, atol=atol)
    point = _one_point(manifold, point, "jacobian_rank")  # NaN would end in LAPACK's 'SVD did not converge'
    shape = manifold.pattern.shape
    if min(shape) == 0:
        return block_rank([], shape, rtol=rtol, atol=atol)
    values = [np.linalg.svd(blocks, compute_uv=False) for blocks in blocks_module.scaled_blocks(manifold, point)]
    return block_rank(values, shape, rtol=rtol, atol=atol)


def jacobian_ranks(manifold, points, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """:func:`jacobian_rank` at each point of a stack [n, point_size]: the singular values of the whole stack at
    once (:func:`scaled_singular_values`) where Φ and DΦ take stacks (:func:`takes_stacks`), else point by point.

    Returns
    -------
    decisions : list of RankDecision
    """
    points = _finite_points(manifold, points, "jacobian_ranks")
    if len(points) < 2 or not takes_stacks(manifold, points[:2]):
        return [jacobian_rank(manifold, point, rtol=rtol, atol=atol) for point in points]
    return [rank_of_values(values, rtol=rtol, atol=atol) for values in scaled_singular_values(manifold, points)]


def takes_stacks(manifold, points):
    """Whether Φ and DΦ of `manifold` at a stack of points [n, point_size] equal their values point by point.

    Their contract (``shape=[..., c]``) says they take stacks; a map written
    for one point, indexing ``p[0]``, breaks it, and where the shapes happen
    to fit without an error. Checked at the given points (callers pass
    two), to 1e-9 of each array's largest entry or 1e-9 where that entry is
    below 1 (Φ near M is small: DΦ carries the check there), DΦ by its
    entries where the manifold is handled block by block (no dense c × k
    matrix): callers take a stack at once where this holds, else one point
    at a time.
    """
    jacobian = manifold.constraint_jacobian_entries if handled_by_blocks(manifold) else manifold.constraint_jacobian
    for function in (manifold.constraint, jacobian):
        try:
            stacked = np.asarray(function(points), dtype=float)
            single = np.array([np.asarray(function(point), dtype=float) for point in points])
        except Exception:  # noqa: BLE001 — a map that fails on a stack, however it fails, takes one point
            return False
        if stacked.shape != single.shape or not np.allclose(stacked, single, rtol=0.0,
                                                            atol=1e-9 * np.max(np.abs(single), initial=1.0)):
            return False
    return True


# --------------------------------------------------------------------------- second derivatives

def hessian_form(manifold, point, left, right=None):
    """``D²Φ(point)(left[:, i], right[:, j])``, shape=[c, i, j].

    Uses the manifold's ``constraint_hessian_form`` when it has one (no
    c×k×k array), else contracts ``constraint_hessian``.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    left : array_like, shape=[k, i]
    right : array_like, shape=[k, j], optional
        Default `left`.
    """
    left = np.asarray(left, dtype=float)
    right = left if right is None else np.asarray(right, dtype=float)
    if manifold.constraint_hessian_form is not None:
        return np.asarray(manifold.constraint_hessian_form(point, left, right), dtype=float)
    return np.einsum("cab,ai,bj->cij", manifold.constraint_hessian(point), left, right)


# --------------------------------------------------------------------------- projection

def _one_point(manifold, point, caller):
    """`point` as a float array of shape [point_size] with finite coordinates, or a ValueError naming `caller`
    (NaN ended in LAPACK's 'SVD did not converge'; a stack in a matrix-shape error of its own)."""
    point = np.array(point, dtype=float)
    size = manifold.ambient.point_size
    if point.shape != (size,):
        raise ValueError(f"{caller}: expected one point of shape ({size},), got shape {point.shape}")
    if not np.all(np.isfinite(point)):
        raise ValueError(f"{caller}: the point has non-finite coordinates (NaN or infinity)")
    return point


def _finite_points(manifold, points, caller):
    """`points` as a float array of shape [n, point_size] with finite coordinates, or a ValueError naming `caller`
    (as :func:`_one_point` for each point; a reshape with -1 fails where point_size is 0)."""
    points = np.asarray(points, dtype=float)
    size = manifold.ambient.point_size
    if points.shape == (0,) and size:  # no points (an empty list)
        points = points.reshape(0, size)
    if points.ndim < 1 or points.shape[-1] != size:
        raise ValueError(f"{caller}: expected points of shape (n, {size}), got shape {points.shape}")
    points = points.reshape(math.prod(points.shape[:-1]), size)
    if not np.all(np.isfinite(points)):
        raise ValueError(f"{caller}: a point has non-finite coordinates (NaN or infinity)")
    return points


def project(manifold, point, tolerance=1e-12, max_iterations=60, max_step=None, damped=False):
    """Gauss-Newton projection of one point onto M.

    Iterates ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))``: the step of least
    dimensionless length (see the module's note on units; block by block for
    a large manifold with a pattern, see the note on sparsity).

    With `damped`, Levenberg-Marquardt instead (Nocedal & Wright, *Numerical
    Optimization*, 2nd ed., §10.3): ``p ← p ⊕ (−s·(JᵀJ + μ σ₁² I)⁻¹ Jᵀ Φ(p))``
    with ``J = DΦ(p)·s``, a step kept only where it lowers ‖Φ‖ (μ:
    :data:`DAMPING_START` and its bounds). For far starts: capped
    Gauss-Newton can stall, or circle between a few points, far from M (of
    48 random starts of an RSUR loop's closing map, 13 were still at
    residuals ≈ 1.5 after 100 iterations; damped, none). A manifold handled
    block by block keeps Gauss-Newton
    and its stall test (its blocks are independent problems: one damping
    and one acceptance for all of them would hold each back by the others).

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    tolerance : float
        Stop when ``|Φ(p)| ≤ tolerance``.
    max_iterations : int
    max_step : float, optional
        Largest allowed dimensionless norm ``‖step / s‖`` of one step (a
        capped iteration: radians and lengths over their scale, so that the
        cap does not depend on the unit of length); default unlimited. For
        a manifold handled block by block, the largest norm of each block's
        part of the step: the blocks are independent
        problems, and one cap on the whole step would slow each block down
        by the number of the others.
    damped : bool
        Levenberg-Marquardt steps, each kept only where it lowers ‖Φ‖ (see
        above); a manifold handled block by block ignores it.

    Returns
    -------
    projected : ndarray, shape=[point_size]

    Raises
    ------
    ProjectionError
        If the residual does not fall below `tolerance`, or the limit is a
        spurious zero of Φ rejected by ``manifold.is_solution``. A damped
        projection gives up at a critical point of ‖Φ‖² that is no zero
        (no step lowers ‖Φ‖ up to the largest damping). A manifold
        handled block by block also gives up as soon as the residual has
        fallen by less than 1% over :data:`STALL_WINDOW` iterations (one
        block stuck at a critical point of ``|Φ|²`` that is no zero, as a
        random start in a product of many loops nearly always has one).
    """
    point = _one_point(manifold, point, "project")
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    blocked = handled_by_blocks(manifold)
    value = manifold.constraint(point)
    history = []
    steps = 0
    damping = DAMPING_START if damped and not blocked else None
    for steps in range(max_iterations + 1):
        history.append(float(np.linalg.norm(value)))
        if (steps == max_iterations or history[-1] <= tolerance or not np.isfinite(history[-1])
                or (blocked and _stalled(history))):
            break  # a residual that is not finite: the iterate left Φ's domain (or overflowed)
        if damping is not None:
            accepted = _damped_step(manifold, point, value, damping, max_step)
            if accepted is None:
                break
            point, value, damping = accepted
            continue
        if blocked:
            inverse = blocks_module.pseudo_inverse(manifold, point, STEP_RCOND, sparse_columns=SPARSE_BLOCK_COLUMNS)
            step = -scales * apply_pseudo_inverse(inverse, value)
            if max_step is not None:
                blocks_module.cap_block_steps(manifold.pattern, step, max_step, scales)
        else:
            step = -scales * np.linalg.lstsq(scaled_jacobian(manifold, point), value, rcond=STEP_RCOND)[0]
            norm = np.linalg.norm(step / scales)
            if max_step is not None and norm > max_step:
                step *= max_step / norm
        point = ambient.retract(point, step)
        value = manifold.constraint(point)
    final = float(np.linalg.norm(value))
    method = "Levenberg-Marquardt" if damping is not None else "Gauss-Newton"
    if not np.isfinite(final):
        raise ProjectionError(f"{method} projection did not converge: the residual is not finite after {steps} "
                              f"iterations (an iterate left the constraint map's domain)")
    if final > tolerance:
        raise ProjectionError(
            f"{method} projection did not converge: residual {final:.3g} "
            f"> tolerance {tolerance:.3g} after {steps} iterations"
        )
    if manifold.is_solution is not None and not manifold.is_solution(point):
        raise ProjectionError(f"{method} converged to a spurious zero of the constraint map")
    return point


def _damped_step(manifold, point, value, damping, max_step):
    """One Levenberg-Marquardt step of :func:`project` that lowers ‖Φ‖: ``(point, value, damping)`` after it,
    or None where none does up to :data:`DAMPING_LARGEST` (one SVD of DΦ·diag(s) serves every damping tried)."""
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    left, singular, right_transposed = np.linalg.svd(scaled_jacobian(manifold, point), full_matrices=False)
    reference = singular[0] ** 2 if singular.size and singular[0] > 0 else 1.0
    along = left.T @ value
    residual_before = np.linalg.norm(value)
    while damping <= DAMPING_LARGEST:
        step = -scales * (right_transposed.T @ (singular / (singular ** 2 + damping * reference) * along))
        norm = np.linalg.norm(step / scales)
        if max_step is not None and norm > max_step:
            step *= max_step / norm
        candidate = ambient.retract(point, step)
        candidate_value = manifold.constraint(candidate)
        if np.linalg.norm(candidate_value) < residual_before:  # False for NaN: a step that leaves the domain
            return candidate, candidate_value, max(damping / 10, DAMPING_SMALLEST)
        damping *= 4
    return None


def settle_blocks(manifold, points, redraw, tolerance=1e-12, max_iterations=60, max_step=None,
                  patience=STALL_WINDOW):
    """Gauss-Newton projection of a stack of points onto a manifold handled block by block, each block of DΦ
    that has not settled after `patience` iterations drawn again by `redraw`: the projected points and the
    columns of the blocks that did not settle.

    The rows of a block of the pattern depend on its columns only, and no two
    blocks share a row or a column (see the module's note on sparsity): M is
    the product of the blocks' zero sets and the free columns, and
    Gauss-Newton's step is one step per block, each independent of the other
    blocks' columns: here each block that has not settled takes the step of
    its own block alone, ``−s·(J_b)⁺ Φ_b`` (``J_b`` its part of DΦ·diag(s),
    singular values at most :data:`STEP_RCOND` times its own σ₁ cut; its
    norm capped at `max_step` as :func:`project` caps each block's part), and
    a settled block does not move (nor is it decomposed). A random start in
    a product of many blocks nearly always has a block at a critical point of
    its ‖Φ_b‖² that is no zero, so a projection of the whole point fails (of
    300 blocks of random starts of RSUR loops, steps capped at 1, 25% had not
    settled after 100 iterations).
    Here a block *settles* when ‖Φ_b‖ ≤ tolerance / √B (B blocks), and a block
    that has not settled `patience` iterations after it was last drawn, or
    whose residual is not finite, is drawn again: ``redraw(points, columns)``
    returns points that differ from `points` at the `columns` (boolean,
    [n, k]: those blocks' columns) only, so the other blocks keep their
    residuals (their rows do not depend on those columns) and the settled ones
    stay settled. A point stops moving when ``|Φ| ≤ tolerance``; all stop
    after `max_iterations`, or when no block moves (every block settled or not
    finite after its draw, Φ held up by rows outside the blocks). A point returned settled is a zero of Φ to
    `tolerance`, no more: :func:`project` applies ``manifold.is_solution``.

    Parameters
    ----------
    manifold : ImplicitManifold
        Handled block by block (:func:`handled_by_blocks`); its ``constraint`` and
        ``constraint_jacobian_entries`` take stacks of points. Every block is decomposed densely (none is left
        to LSQR, :data:`SPARSE_BLOCK_COLUMNS`).
    points : array_like, shape=[n, point_size]
    redraw : callable
        ``redraw(points [j, point_size], columns [j, k]) -> points [j, point_size]``, e.g. those columns of new
        random points (:func:`manifold.sample_manifold`).
    tolerance : float
        A point stops when ``|Φ(p)| ≤ tolerance``.
    max_iterations : int
    max_step : float, optional
        Largest dimensionless norm of each block's part of a step.
    patience : int
        Iterations a block is given, after each draw, to settle.

    Returns
    -------
    projected : ndarray, shape=[n, point_size]
    unsettled : ndarray of bool, shape=[n, k]
        The columns of the blocks above the cut at `projected` (none at a point where ``|Φ| ≤ tolerance``).
    """
    points = np.array(points, dtype=float).reshape(-1, manifold.ambient.point_size)
    count, size = len(points), manifold.ambient.dim
    rows, groups = manifold.pattern.shape[0], manifold.pattern.blocks
    cut = tolerance / np.sqrt(max(1, sum(len(group.rows) for group in groups)))
    ages = [np.zeros((count, len(group.rows)), dtype=int) for group in groups]

    def constraint(chosen):
        return np.asarray(manifold.constraint(points[chosen]), dtype=float).reshape(len(chosen), rows)

    active = np.arange(count)
    values = constraint(active)
    for _ in range(max_iterations):
        active = active[~(np.linalg.norm(values[active], axis=-1) <= tolerance)]
        if not active.size:
            break
        stale = np.zeros((len(active), size), dtype=bool)
        for group, age in zip(groups, ages):
            residual = np.linalg.norm(values[active][:, group.rows], axis=-1)            # [a, b]
            drawn = ~np.isfinite(residual) | ((age[active] >= patience) & ~(residual <= cut))
            which, block = np.nonzero(drawn)
            stale[which[:, None], group.columns[block]] = True
            age[active] = np.where(drawn, 0, age[active]) + 1
        chosen = np.flatnonzero(stale.any(axis=-1))
        if chosen.size:
            points[active[chosen]] = redraw(points[active[chosen]], stale[chosen])
            values[active[chosen]] = constraint(active[chosen])
        residuals = [np.linalg.norm(values[active][:, group.rows], axis=-1) for group in groups]
        moving = [np.isfinite(residual) & (residual > cut) for residual in residuals]
        if not any(map(np.any, moving)):
            break
        steps = _settling_steps(manifold, points[active], values[active], moving, max_step)
        points[active] = manifold.ambient.retract(points[active], steps)
        values[active] = constraint(active)
    unsettled = np.zeros((count, size), dtype=bool)
    for group in groups:
        which, block = np.nonzero(~(np.linalg.norm(values[:, group.rows], axis=-1) <= cut))
        unsettled[which[:, None], group.columns[block]] = True
    unsettled[np.linalg.norm(values, axis=-1) <= tolerance] = False
    return points, unsettled


def _settling_steps(manifold, points, values, moving, max_step):
    """The steps of :func:`settle_blocks` at `points` [a, point_size] with ``Φ = values`` [a, c]: each block in
    `moving` (per block group, [a, b] of bool) Gauss-Newton's step of that block alone, capped at `max_step`,
    the other columns 0, shape=[a, k]."""
    scales = manifold.ambient.tangent_scales
    entries = np.asarray(manifold.constraint_jacobian_entries(points), dtype=float)
    padded = np.concatenate([entries, np.zeros((len(entries), 1))], axis=-1)                # [a, nnz + 1]
    steps = np.zeros((len(points), manifold.ambient.dim))
    for group, mask in zip(manifold.pattern.blocks, moving):
        which, block = np.nonzero(mask)
        if not which.size:
            continue
        columns = group.columns[block]                                                     # [p, q]
        matrices = padded[which[:, None, None], group.positions[block]] * scales[columns][:, None, :]  # [p, r, q]
        left, singular, right = np.linalg.svd(matrices, full_matrices=False)
        kept = singular > STEP_RCOND * singular[:, :1]
        reciprocal = np.divide(1.0, singular, out=np.zeros_like(singular), where=kept)
        along = (np.swapaxes(left, -1, -2) @ values[which[:, None], group.rows[block]][..., None])[..., 0]
        moves = (np.swapaxes(right, -1, -2) @ (reciprocal * along)[..., None])[..., 0]  # [p, q], dimensionless
        if max_step is not None:
            norms = np.linalg.norm(moves, axis=-1)
            moves *= np.minimum(1.0, max_step / np.maximum(norms, np.finfo(float).tiny))[:, None]
        steps[which[:, None], columns] = -scales[columns] * moves
    return steps


def _stalled(history):
    """Whether the residuals (one per iteration) fell by less than 1% over the last :data:`STALL_WINDOW`."""
    return len(history) > STALL_WINDOW and history[-1] > 0.99 * history[-1 - STALL_WINDOW]


def project_many(manifold, points, tolerance=1e-12, max_iterations=60, max_step=None, damped=False):
    """The projections of a stack of points onto M, all at once: :func:`project` point by point.

    Every point whose residual exceeds `tolerance` takes :func:`project`'s
    step with the same `max_step` and `damped`: Gauss-Newton's
    ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))`` (:func:`minimum_norm_steps`: one batched
    pseudo-inverse per iteration, of the dense Jacobians or block by block),
    or with `damped` Levenberg-Marquardt's, each point with its own damping
    (:func:`_damped_steps`: one batched SVD per iteration); until
    ``|Φ(p)| ≤ tolerance``. A point stops moving where :func:`project`
    stops: it reaches the tolerance, its residual is not finite, no damped
    step lowers it, or (handled block by block) it stalls. Unlike
    :func:`project` nothing is raised: the points that did not converge are
    reported, and ``manifold.is_solution`` (which takes one point) is not
    applied: a caller with a batched check (e.g. :func:`mechanisms.closes`)
    applies it to the stack.

    Parameters
    ----------
    manifold : ImplicitManifold
        Its ``constraint`` and ``constraint_jacobian`` must take stacks of points.
    points : array_like, shape=[..., point_size]
    tolerance : float
    max_iterations : int
    max_step : float, optional
        As :func:`project`'s, for each point.
    damped : bool
        As :func:`project`'s.

    Returns
    -------
    projected : ndarray, shape=[..., point_size]
    reached : ndarray of bool, shape=[...]
        Whether ``|Φ| ≤ tolerance`` at the projected point.

    Examples
    --------
    >>> circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p ** 2).sum(-1, keepdims=True) - 1,
    ...                           lambda p: 2 * p[..., None, :])
    >>> projected, reached = project_many(circle, [[2.0, 0.0], [0.0, 0.5]])
    >>> bool(np.allclose(projected, [[1, 0], [0, 1]])), reached.tolist()
    (True, [True, True])
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    requested = np.asarray(points, dtype=float)
    count = math.prod(requested.shape[:-1])  # not a reshape with -1: point_size may be 0
    if not count or (requested.shape == (0,) and ambient.point_size):  # an empty stack: nothing to project
        return requested.copy(), np.zeros(requested.shape[:-1], dtype=bool)
    projected = requested.reshape(count, ambient.point_size).copy()
    blocked = handled_by_blocks(manifold)

    def constraint(stack):
        return np.asarray(manifold.constraint(stack), dtype=float).reshape(len(stack), -1)

    values = constraint(projected)
    active = np.arange(len(projected))
    damping = np.full(len(projected), DAMPING_START) if damped and not blocked else None
    # block by block, the stall test (_stalled) point by point: |Φ| of the last STALL_WINDOW + 1 iterations, in turn
    history = np.full((len(projected), STALL_WINDOW + 1), np.nan) if blocked else None
    for iteration in range(max_iterations):
        norms = np.linalg.norm(values, axis=-1)
        keep = ~(norms <= tolerance) & np.isfinite(norms)
        if history is not None:
            if iteration >= STALL_WINDOW:  # the slot of iteration − STALL_WINDOW
                keep &= ~(norms > 0.99 * history[active, (iteration + 1) % (STALL_WINDOW + 1)])
            history[active, iteration % (STALL_WINDOW + 1)] = norms
        active, values = active[keep], values[keep]
        if not len(active):
            break
        if damping is not None:
            moved, values, damping[active], accepted = _damped_steps(manifold, projected[active], values,
                                                                     damping[active], max_step)
            projected[active] = moved
            active, values = active[accepted], values[accepted]  # no step lowers |Φ|: given up
            continue
        steps = -scales * minimum_norm_steps(manifold, projected[active], values)
        if max_step is not None:
            _cap_steps(manifold, steps, max_step, scales)
        projected[active] = ambient.retract(projected[active], steps)
        values = constraint(projected[active])
    norms = np.linalg.norm(constraint(projected), axis=-1)
    shape = requested.shape[:-1]
    return projected.reshape(requested.shape), (norms <= tolerance).reshape(shape)


def project_each(manifold, points, **options):
    """:func:`project` at each point of a stack, all at once where Φ and DΦ take stacks (:func:`takes_stacks`):
    :func:`project_many`, then ``manifold.is_solution`` point by point; else one point at a time.

    Parameters
    ----------
    manifold : ImplicitManifold
    points : array_like, shape=[n, point_size]
    **options
        :func:`project`'s `tolerance`, `max_iterations`, `max_step` and `damped`.

    Returns
    -------
    projected : ndarray, shape=[n, point_size]
        Each point's projection where `projected_ok` (elsewhere not a point of M: where the iterations stopped,
        or the point itself).
    projected_ok : ndarray of bool, shape=[n]
        Where :func:`project` returns a point (elsewhere it raises :class:`ProjectionError`).

    Raises
    ------
    ValueError
        If a point is not finite (as :func:`project`).
    """
    points = _finite_points(manifold, points, "project_each")
    if len(points) > 1 and takes_stacks(manifold, points[:2]):
        projected, reached = project_many(manifold, points, **options)
        if manifold.is_solution is not None:
            reached = np.array([bool(one) and bool(manifold.is_solution(point))
                                for point, one in zip(projected, reached)], dtype=bool)
        return projected, reached
    projected, reached = points.copy(), np.zeros(len(points), dtype=bool)
    for index, point in enumerate(points):
        try:
            projected[index] = project(manifold, point, **options)
        except ProjectionError:
            continue
        reached[index] = True
    return projected, reached


def _cap_steps(manifold, steps, max_step, scales):
    """Scale, in place, a stack of steps [n, k] as :func:`project` caps one: each block's part where the manifold is
    handled block by block, else the whole step, to dimensionless norm at most `max_step`."""
    if handled_by_blocks(manifold):
        blocks_module.cap_block_steps(manifold.pattern, steps, max_step, scales)
        return
    norms = np.linalg.norm(steps / scales, axis=-1)
    over = norms > max_step
    steps[over] *= (max_step / norms[over])[:, None]


def _damped_steps(manifold, points, values, damping, max_step):
    """:func:`_damped_step` at a stack of points [n, point_size] with ``Φ = values`` [n, c] and dampings [n]:
    ``(points, values, damping, accepted)`` after it, where `accepted` [n] says which points took a step that
    lowers ‖Φ‖ (the others, none up to :data:`DAMPING_LARGEST`, are returned unmoved). One batched SVD of
    DΦ·diag(s) serves every damping tried; each round tries the points not yet moved, their damping 4× larger."""
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    left, singular, right_transposed = np.linalg.svd(scaled_jacobian(manifold, points), full_matrices=False)
    largest = singular[:, 0] if singular.shape[-1] else np.zeros(len(points))
    reference = np.where(largest > 0, largest ** 2, 1.0)
    along = (np.swapaxes(left, -1, -2) @ values[..., None])[..., 0]
    residual_before = np.linalg.norm(values, axis=-1)
    points, values, damping = points.copy(), values.copy(), damping.copy()
    accepted = np.zeros(len(points), dtype=bool)
    trying = np.flatnonzero(damping <= DAMPING_LARGEST)
    while trying.size:
        weights = singular[trying] / (singular[trying] ** 2 + damping[trying, None] * reference[trying, None])
        step = -scales * (np.swapaxes(right_transposed[trying], -1, -2) @ (weights * along[trying])[..., None])[..., 0]
        if max_step is not None:
            _cap_steps(manifold, step, max_step, scales)
        candidates = ambient.retract(points[trying], step)
        candidate_values = np.asarray(manifold.constraint(candidates), dtype=float).reshape(len(trying), -1)
        lower = np.linalg.norm(candidate_values, axis=-1) < residual_before[trying]  # False for NaN
        moved = trying[lower]
        points[moved], values[moved] = candidates[lower], candidate_values[lower]
        damping[moved] = np.maximum(damping[moved] / 10, DAMPING_SMALLEST)
        accepted[moved] = True
        damping[trying[~lower]] *= 4
        trying = trying[~lower][damping[trying[~lower]] <= DAMPING_LARGEST]
    return points, values, damping, accepted


def minimum_norm_steps(manifold, points, values, columns=None, rcond=STEP_RCOND):
    """The dimensionless minimum-norm least-squares solutions u of ``DΦ(p)[:, columns]·diag(s[columns]) u = b``
    at a stack of points: Gauss-Newton's steps ``−s·u`` where ``b = Φ(p)``.

    Singular values at most ``rcond · σ₁`` count as zero, as in
    ``numpy.linalg.pinv``. Where the manifold is handled block by block
    (:data:`BLOCK_THRESHOLD`), the blocks of DΦ's `columns` are solved apart
    (:func:`manifold.blocks.minimum_norm_solutions`: memory and time grow
    with the blocks, not with c × k per point); else one batched
    pseudo-inverse of the dense Jacobians.

    Parameters
    ----------
    manifold : ImplicitManifold
        Its ``constraint_jacobian`` (or ``constraint_jacobian_entries``) must take stacks of points.
    points : array_like, shape=[n, point_size]
    values : array_like, shape=[n, c]
        The right-hand sides b.
    columns : array_like of int, shape=[r], optional
        The tangent coordinates that move (default all; the others are held).
    rcond : float

    Returns
    -------
    steps : ndarray, shape=[n, r]

    Examples
    --------
    >>> circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p ** 2).sum(-1, keepdims=True) - 1,
    ...                           lambda p: 2 * p[..., None, :])
    >>> minimum_norm_steps(circle, [[2.0, 0.0]], [[3.0]]).tolist()
    [[0.75, 0.0]]
    """
    ambient = manifold.ambient
    columns = np.arange(ambient.dim) if columns is None else np.asarray(columns, dtype=np.intp)
    scales = ambient.tangent_scales[columns]
    points, values = np.asarray(points, dtype=float), np.asarray(values, dtype=float)
    if handled_by_blocks(manifold):
        pattern, kept = manifold.pattern.restricted(columns)
        entries = np.asarray(manifold.constraint_jacobian_entries(points), dtype=float)[..., kept]
        return blocks_module.minimum_norm_solutions(pattern, entries, scales, values, rcond, SPARSE_BLOCK_COLUMNS)
    jacobian = np.asarray(manifold.constraint_jacobian(points), dtype=float)[..., columns] * scales
    return np.einsum("nkc,nc->nk", np.linalg.pinv(jacobian, rcond=rcond), values)


def scaled_singular_values(manifold, points, columns=None):
    """Singular values of ``DΦ(p)[:, columns]·diag(s[columns])`` at a stack of points, descending,
    shape=[n, min(c, r)]: block by block where the manifold is handled so (:data:`BLOCK_THRESHOLD`;
    :func:`manifold.blocks.stacked_singular_values`), else of the dense Jacobians.

    Parameters
    ----------
    manifold : ImplicitManifold
    points : array_like, shape=[n, point_size]
    columns : array_like of int, shape=[r], optional
        Default all the tangent coordinates.
    """
    ambient = manifold.ambient
    columns = np.arange(ambient.dim) if columns is None else np.asarray(columns, dtype=np.intp)
    scales = ambient.tangent_scales[columns]
    points = np.asarray(points, dtype=float)
    if handled_by_blocks(manifold):
        pattern, kept = manifold.pattern.restricted(columns)
        entries = np.asarray(manifold.constraint_jacobian_entries(points), dtype=float)[..., kept]
        return blocks_module.stacked_singular_values(pattern, entries, scales)
    jacobian = np.asarray(manifold.constraint_jacobian(points), dtype=float)[..., columns] * scales
    return np.linalg.svd(jacobian, compute_uv=False)


# --------------------------------------------------------------------------- bases

def _blocked_decision(manifold, point, rtol, atol):
    """Block SVDs (full matrices) of DΦ(point)·diag(s) and the rank decision of the whole matrix."""
    point = _one_point(manifold, point, "the block-by-block rank decision")
    decomposition = decompose(manifold, point)
    return decomposition, block_rank([entry[1] for entry in decomposition], manifold.pattern.shape, rtol, atol)


def tangent_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Basis of ker DΦ(point), orthonormal for ⟨·,·⟩_s, and the rank decision behind it.

    At a regular point this is a basis of the tangent space T_pM; at a
    singular point of M it spans the (larger) kernel of DΦ. The rank is that
    of the dimensionless Jacobian DΦ·diag(s) (:func:`scaled_jacobian`), and
    the columns are joint-rate vectors ``s·u`` with u orthonormal: the
    columns are orthonormal for the dimensionless inner product
    ``⟨v, w⟩_s = Σᵢ vᵢ wᵢ / sᵢ²`` (Euclidean where every scale is 1).
    For a large manifold with a pattern the basis is the direct sum of the
    blocks' kernels and the unit vectors of the free columns (each column
    supported on one block).

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
    point = _one_point(manifold, point, "tangent_basis")
    scales = manifold.ambient.tangent_scales
    if handled_by_blocks(manifold):
        decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
        pieces = block_vectors(decomposition, decision.tolerance, kernel=True)
        basis = blocks_module.dense_basis(pieces, manifold.ambient.dim, manifold.pattern.free_columns)
        basis *= scales[:, None]
        return basis, decision
    jacobian = scaled_jacobian(manifold, point)
    decision = numerical_rank(jacobian, rtol=rtol, atol=atol)
    _, _, vh = np.linalg.svd(jacobian, full_matrices=True)
    return scales[:, None] * vh[decision.rank:].T, decision


def sparse_tangent_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """:func:`tangent_basis` as a sparse matrix: each column supported on one block of DΦ (or one free
    column), so the basis of a ladder of loops has O(k) entries where the dense one has k·m.

    The same columns as :func:`tangent_basis` for a manifold handled block by
    block; for any other, its dense basis converted.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]

    Returns
    -------
    basis : scipy.sparse.csc_array, shape=[k, k - rank]
    decision : RankDecision
    """
    if not handled_by_blocks(manifold):
        from scipy.sparse import coo_array

        basis, decision = tangent_basis(manifold, point, rtol=rtol, atol=atol)
        return coo_array(basis).tocsc(), decision
    decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
    pieces = block_vectors(decomposition, decision.tolerance, kernel=True)
    return blocks_module.sparse_basis(pieces, manifold.ambient.tangent_scales, manifold.pattern.free_columns), \
        decision


def normal_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Orthonormal basis of the row space of DΦ(point)·diag(s) (the normal space in dimensionless
    coordinates u = v / s), shape=[k, rank]."""
    if handled_by_blocks(manifold):
        decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
        pieces = block_vectors(decomposition, decision.tolerance, kernel=False)
        return blocks_module.dense_basis(pieces, manifold.ambient.dim)
    jacobian = scaled_jacobian(manifold, point)
    decision = numerical_rank(jacobian, rtol=rtol, atol=atol)
    _, _, vh = np.linalg.svd(jacobian, full_matrices=True)
    return vh[: decision.rank].T.copy()


def constraint_curvature(manifold, point, basis, rtol=DEFAULT_RTOL, right=None):
    """Ambient accelerations of curves on M: ``x''(u, w) = −s·(DΦ·s)⁺ D²Φ(Bu, Bw)``.

    For a curve ``p ⊕ x(t)`` on M with ``x'(0) = B u``, the second-order
    term of Φ(p ⊕ x(t)) = 0 gives ``DΦ x'' + D²Φ(Bu, Bu) = 0``; this returns
    the solution of that equation of least dimensionless norm ``|x''/s|`` for
    every pair of basis vectors. For a large manifold with a pattern, D²Φ is
    contracted by :func:`hessian_form` and the pseudo-inverse applied block
    by block (same cut, relative to σ₁ of the whole DΦ·diag(s)), a few
    columns of `basis` at a time: beside the result, the work memory stays
    within a few times :data:`CHUNK_ENTRIES` floats.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    basis : array_like, shape=[k, d]
        Tangent vectors (columns), usually a tangent basis.
    rtol : float
        Relative cut of the pseudo-inverse.
    right : array_like, shape=[k, e], optional
        Second tangent vectors; default `basis` (e = d). A caller that needs
        only a summary of the accelerations (their largest entry, say) can
        pass a few columns of a basis as `basis` and the whole basis as
        `right`, chunk by chunk.

    Returns
    -------
    acceleration : ndarray, shape=[k, d, e]
        ``acceleration[:, i, j] = x''(bᵢ, rⱼ)``; symmetric in ``i, j`` when `right` is `basis`.
    """
    basis = np.asarray(basis, dtype=float)
    other = basis if right is None else np.asarray(right, dtype=float)
    scales = manifold.ambient.tangent_scales
    if handled_by_blocks(manifold):
        inverse = blocks_module.pseudo_inverse(manifold, point, rtol)
        count, size = basis.shape[1], other.shape[1]
        acceleration = np.empty((manifold.ambient.dim, count, size))
        chunk = max(1, CHUNK_ENTRIES // max(1, size * sum(manifold.pattern.shape)))
        for start in range(0, count, chunk):
            second = hessian_form(manifold, point, basis[:, start:start + chunk], other)
            acceleration[:, start:start + chunk] = apply_pseudo_inverse(inverse, second)
        acceleration *= -scales[:, None, None]
        return acceleration
    if manifold.constraint_hessian is None:
        second = hessian_form(manifold, point, basis, other)
    else:
        second = np.einsum("cab,ai,bj->cij", manifold.constraint_hessian(point), basis, other)
    pseudo_inverse = np.linalg.pinv(scaled_jacobian(manifold, point), rcond=rtol)
    return -scales[:, None, None] * np.einsum("kc,cij->kij", pseudo_inverse, second)
