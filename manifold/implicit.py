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
entries there). Its rows and columns split into *blocks*, the connected
components of the pattern (for a mechanism, groups of loops that share
joints), and columns no row touches. After permuting rows and columns DΦ is
block diagonal, so its singular values are the union of the blocks', its
kernel the direct sum of theirs, and a minimum-norm solve is one per block.
From :data:`BLOCK_THRESHOLD` coordinates on, :func:`project`,
:func:`jacobian_rank`, :func:`tangent_basis`, :func:`normal_basis` and
:func:`constraint_curvature` work block by block (blocks of one shape in one
batched SVD): the same decisions (every cut is relative to σ₁ of the whole
DΦ, as for the dense matrix) at a cost that grows with the blocks, not with
k². Below the threshold everything is dense, as for any manifold without a
pattern. D²Φ is contracted by ``constraint_hessian_form`` where the manifold
gives one (:func:`hessian_form`), never formed as a c×k×k array.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Optional

import numpy as np

from .ambient import AmbientSpace
from .errors import ProjectionError
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, numerical_rank, rank_of_values

__all__ = [
    "BLOCK_THRESHOLD",
    "SPARSE_BLOCK_COLUMNS",
    "CHUNK_ENTRIES",
    "JacobianPattern",
    "ImplicitManifold",
    "residual",
    "scaled_jacobian",
    "jacobian_rank",
    "hessian_form",
    "project",
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
#: floats of work memory :func:`constraint_curvature` uses per chunk of basis columns on the block path
CHUNK_ENTRIES = 2 ** 20
#: a projection handled block by block stops when the residual fell by less than 1% over this many iterations
STALL_WINDOW = 10


@dataclass(frozen=True, eq=False)
class _BlockGroup:
    """Blocks of DΦ of one shape: ``DΦ[rows[b][:, None], columns[b]] = padded_entries[positions[b]]``.

    Attributes
    ----------
    rows : ndarray, shape=[blocks, r]
    columns : ndarray, shape=[blocks, q]
    positions : ndarray, shape=[blocks, r, q]
        Index of each entry in the pattern's entry list, or ``nnz`` (a zero) off the pattern.
    """

    rows: np.ndarray
    columns: np.ndarray
    positions: np.ndarray


@dataclass(frozen=True, eq=False)
class JacobianPattern:
    """Where DΦ can be nonzero: entry e at ``(rows[e], columns[e])``, no two entries at one place.

    Parameters
    ----------
    shape : tuple of int
        ``(c, k)``.
    rows, columns : array_like of int, shape=[nnz]

    Attributes
    ----------
    blocks : tuple of _BlockGroup
        The connected components of the pattern (rows and columns linked by
        an entry), grouped by shape; computed on first use.
    free_columns : ndarray of int
        Columns no entry touches (directions along which Φ is constant).

    Examples
    --------
    >>> pattern = JacobianPattern((2, 3), [0, 0, 1], [0, 1, 2])
    >>> [group.columns.tolist() for group in pattern.blocks], pattern.free_columns.tolist()
    ([[[0, 1]], [[2]]], [])
    """

    shape: tuple
    rows: np.ndarray
    columns: np.ndarray
    nnz: int = field(init=False)

    def __post_init__(self):
        rows = np.asarray(self.rows, dtype=np.intp).ravel()
        columns = np.asarray(self.columns, dtype=np.intp).ravel()
        if rows.shape != columns.shape:
            raise ValueError(f"Expected as many rows as columns in the pattern, got {rows.shape} and {columns.shape}")
        object.__setattr__(self, "shape", (int(self.shape[0]), int(self.shape[1])))
        object.__setattr__(self, "rows", rows)
        object.__setattr__(self, "columns", columns)
        object.__setattr__(self, "nnz", int(rows.size))

    @cached_property
    def _components(self):
        from scipy.sparse import coo_array
        from scipy.sparse.csgraph import connected_components

        c, k = self.shape
        graph = coo_array((np.ones(self.nnz), (self.rows, c + self.columns)), shape=(c + k, c + k))
        _, labels = connected_components(graph, directed=False)
        return labels[:c], labels[c:]

    @cached_property
    def blocks(self):
        row_labels, column_labels = self._components
        rows_of, columns_of = _members(row_labels), _members(column_labels)
        shapes = {}
        for label in columns_of:
            if label in rows_of:
                shapes.setdefault((len(rows_of[label]), len(columns_of[label])), []).append(label)
        local_row, local_column = _local_positions(row_labels), _local_positions(column_labels)
        entry_labels = column_labels[self.columns]
        place = np.full(int(column_labels.max(initial=-1)) + 1, -1, dtype=np.intp)
        groups = []
        for (row_count, column_count), labels in shapes.items():
            place[labels] = np.arange(len(labels))
            chosen = np.flatnonzero(place[entry_labels] >= 0)
            positions = np.full((len(labels), row_count, column_count), self.nnz, dtype=np.intp)
            positions[place[entry_labels[chosen]], local_row[self.rows[chosen]],
                      local_column[self.columns[chosen]]] = chosen
            place[labels] = -1
            groups.append(_BlockGroup(np.array([rows_of[label] for label in labels], dtype=np.intp),
                                      np.array([columns_of[label] for label in labels], dtype=np.intp),
                                      positions))
        return tuple(groups)

    @cached_property
    def free_columns(self):
        touched = np.zeros(self.shape[1], dtype=bool)
        touched[self.columns] = True
        return np.flatnonzero(~touched)


def _members(labels):
    """label -> sorted indices carrying it."""
    order = np.argsort(labels, kind="stable")
    boundaries = np.flatnonzero(np.diff(labels[order])) + 1
    return {int(labels[part[0]]): part for part in np.split(order, boundaries) if len(part)}


def _local_positions(labels):
    """Position of each index among the indices of its label, in increasing order."""
    order = np.argsort(labels, kind="stable")
    sorted_labels = labels[order]
    starts = np.flatnonzero(np.r_[True, sorted_labels[1:] != sorted_labels[:-1]]) if len(labels) else np.zeros(0, int)
    first = np.repeat(starts, np.diff(np.r_[starts, len(labels)]))
    positions = np.empty(len(labels), dtype=np.intp)
    positions[order] = np.arange(len(labels)) - first
    return positions


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
    """

    ambient: AmbientSpace
    constraint: Callable
    constraint_jacobian: Callable
    constraint_hessian: Optional[Callable] = None
    is_solution: Optional[Callable] = None
    pattern: Optional[JacobianPattern] = None
    constraint_jacobian_entries: Optional[Callable] = None
    constraint_hessian_form: Optional[Callable] = None


_SCALES = weakref.WeakKeyDictionary()


def _tangent_scales(ambient):
    """:attr:`AmbientSpace.tangent_scales`, computed once per ambient space (read-only)."""
    scales = _SCALES.get(ambient)
    if scales is None:
        scales = np.array(ambient.tangent_scales, dtype=float)
        scales.setflags(write=False)
        _SCALES[ambient] = scales
    return scales


def _blocked(manifold):
    """Whether `manifold` is handled block by block (a pattern, its entries, and k ≥ :data:`BLOCK_THRESHOLD`)."""
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
    return np.asarray(manifold.constraint_jacobian(point), dtype=float) * _tangent_scales(manifold.ambient)


# --------------------------------------------------------------------------- blocks

def _block_values(manifold, point):
    """The blocks of DΦ(point)·diag(s): one array [b, r, q] per block group."""
    pattern = manifold.pattern
    entries = np.asarray(manifold.constraint_jacobian_entries(point), dtype=float)
    padded = np.concatenate([entries, np.zeros(1)])
    scales = _tangent_scales(manifold.ambient)
    return [padded[group.positions] * scales[group.columns][:, None, :] for group in pattern.blocks]


def _decomposition(manifold, point):
    """SVD (full matrices) of every block of DΦ(point)·diag(s), blocks of one shape in one batched call:
    ``[(block group, singular values [b, min(r, q)], Vᴴ [b, q, q])]``."""
    decomposed = []
    for group, blocks in zip(manifold.pattern.blocks, _block_values(manifold, point)):
        _, values, right = np.linalg.svd(blocks, full_matrices=True)
        decomposed.append((group, values, right))
    return decomposed


def _all_values(values, shape):
    """Every singular value of DΦ·diag(s) from the blocks', shape=[min(c, k)]: the blocks' values, and
    exact zeros for rows no entry touches and for blocks with more rows than columns."""
    values = np.concatenate([entry.ravel() for entry in values]) if values else np.zeros(0)
    return np.concatenate([values, np.zeros(max(min(shape) - len(values), 0))])


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
    if not _blocked(manifold):
        return numerical_rank(scaled_jacobian(manifold, point), rtol=rtol, atol=atol)
    shape = manifold.pattern.shape
    if min(shape) == 0:
        return numerical_rank(np.zeros(shape), rtol=rtol, atol=atol)
    values = [np.linalg.svd(blocks, compute_uv=False) for blocks in _block_values(manifold, point)]
    return rank_of_values(_all_values(values, shape), rtol=rtol, atol=atol)


def _block_vectors(decomposition, tolerance, kernel):
    """Right singular vectors of the blocks (dimensionless): the kernel ones (σ ≤ `tolerance`) or the
    row-space ones, as ``[(columns [n, q], vectors [n, q])]``."""
    pieces = []
    for group, values, right in decomposition:
        ranks = np.count_nonzero(values > tolerance, axis=-1)                     # [b]
        beyond = np.arange(right.shape[-2]) >= ranks[:, None]                     # [b, q]
        block, row = np.nonzero(beyond if kernel else ~beyond)
        pieces.append((group.columns[block], right[block, row]))
    return pieces


def _assemble(pieces, size, extra_columns=()):
    """The [k, count] matrix whose columns are the pieces' vectors (and unit vectors at `extra_columns`)."""
    count = sum(len(vectors) for _, vectors in pieces) + len(extra_columns)
    matrix = np.zeros((size, count))
    start = 0
    for columns, vectors in pieces:
        number = np.arange(start, start + len(vectors))
        matrix[columns, number[:, None]] = vectors
        start += len(vectors)
    matrix[np.asarray(extra_columns, dtype=np.intp), np.arange(start, count)] = 1.0
    return matrix


@dataclass(frozen=True, eq=False)
class _PseudoInverse:
    """``(DΦ(point)·diag(s))⁺`` block by block (see :func:`_pseudo_inverse`).

    Attributes
    ----------
    shape : tuple
        ``(c, k)``.
    factors : tuple
        ``(block group, U [b, r, s], 1/σ or 0 [b, s], Vᴴ [b, s, q])`` of the blocks solved densely.
    iterative : tuple
        ``(block group, blocks [b, r, q])`` of the blocks solved by LSQR.
    rcond : float
    """

    shape: tuple
    factors: tuple
    iterative: tuple
    rcond: float


def _pseudo_inverse(manifold, point, rcond, sparse=True):
    """The pseudo-inverse of DΦ(point)·diag(s), block by block.

    Singular values at most ``rcond · σ₁`` (σ₁ of the whole matrix) count as
    zero, as in ``numpy.linalg.lstsq`` and ``numpy.linalg.pinv``. Blocks with
    more than :data:`SPARSE_BLOCK_COLUMNS` columns are left to LSQR when
    `sparse` (its iterates from zero converge to the minimum-norm solution).
    """
    pattern = manifold.pattern
    decomposed, iterative, largest = [], [], 0.0
    for group, blocks in zip(pattern.blocks, _block_values(manifold, point)):
        if sparse and group.columns.shape[1] > SPARSE_BLOCK_COLUMNS:
            iterative.append((group, blocks))
            continue
        left, values, right = np.linalg.svd(blocks, full_matrices=False)
        decomposed.append((group, left, values, right))
        largest = max(largest, float(values.max(initial=0.0)))
    factors = tuple((group, left, np.divide(1.0, values, out=np.zeros_like(values), where=values > rcond * largest),
                     right) for group, left, values, right in decomposed)
    return _PseudoInverse(pattern.shape, factors, tuple(iterative), rcond)


def _apply(pseudo_inverse, right_hand_side):
    """The minimum-norm least-squares solutions u of ``DΦ·diag(s) u = b``, shape=[k, ...], for b of
    shape=[c, ...]."""
    from_rows = np.asarray(right_hand_side, dtype=float)
    trailing = from_rows.shape[1:]
    flat = from_rows.reshape(pseudo_inverse.shape[0], -1)
    solution = np.zeros((pseudo_inverse.shape[1], flat.shape[1]))
    for group, left, inverse, right in pseudo_inverse.factors:
        projected = np.swapaxes(left, -1, -2) @ flat[group.rows]                    # [b, s, n]
        solution[group.columns] = np.swapaxes(right, -1, -2) @ (inverse[..., None] * projected)
    if pseudo_inverse.iterative:
        from scipy.sparse import csr_array
        from scipy.sparse.linalg import lsqr

        for group, blocks in pseudo_inverse.iterative:
            for rows, columns, block in zip(group.rows, group.columns, blocks):
                matrix = csr_array(block)
                for index in range(flat.shape[1]):
                    solution[columns, index] = lsqr(matrix, flat[rows, index], atol=1e-14, btol=1e-14,
                                                    conlim=1.0 / pseudo_inverse.rcond,
                                                    iter_lim=20 * len(columns))[0]
    return solution.reshape((pseudo_inverse.shape[1],) + trailing)


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


# --------------------------------------------------------------------------- projection and bases

def project(manifold, point, tolerance=1e-12, max_iterations=60, max_step=None):
    """Gauss-Newton projection of one point onto M.

    Iterates ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))``: the step of least
    dimensionless length (see the module's note on units; block by block for
    a large manifold with a pattern, see the note on sparsity).

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    tolerance : float
        Stop when ``|Φ(p)| ≤ tolerance``.
    max_iterations : int
    max_step : float, optional
        Largest allowed norm of one step (a damped iteration); default
        unlimited. For a manifold handled block by block, the largest norm
        of each block's part of the step: the blocks are independent
        problems, and one cap on the whole step would slow each block down
        by the number of the others.

    Returns
    -------
    projected : ndarray, shape=[point_size]

    Raises
    ------
    ProjectionError
        If the residual does not fall below `tolerance`, or the limit is a
        spurious zero of Φ rejected by ``manifold.is_solution``. A manifold
        handled block by block also gives up as soon as the residual has
        fallen by less than 1% over :data:`STALL_WINDOW` iterations (one
        block stuck at a critical point of ``|Φ|²`` that is no zero, as a
        random start in a product of many loops nearly always has one).
    """
    point = np.array(point, dtype=float)
    ambient = manifold.ambient
    scales = _tangent_scales(ambient)
    blocked = _blocked(manifold)
    value = manifold.constraint(point)
    history = []
    steps = 0
    for steps in range(max_iterations + 1):
        history.append(float(np.linalg.norm(value)))
        if steps == max_iterations or history[-1] <= tolerance or (blocked and _stalled(history)):
            break
        if blocked:
            step = -scales * _apply(_pseudo_inverse(manifold, point, STEP_RCOND), value)
            if max_step is not None:
                _cap_blocks(manifold.pattern, step, max_step)
        else:
            step = -scales * np.linalg.lstsq(scaled_jacobian(manifold, point), value, rcond=STEP_RCOND)[0]
            norm = np.linalg.norm(step)
            if max_step is not None and norm > max_step:
                step *= max_step / norm
        point = ambient.retract(point, step)
        value = manifold.constraint(point)
    final = float(np.linalg.norm(value))
    if not np.isfinite(final) or final > tolerance:
        raise ProjectionError(
            f"Gauss-Newton projection did not converge: residual {final:.3g} "
            f"> tolerance {tolerance:.3g} after {steps} iterations"
        )
    if manifold.is_solution is not None and not manifold.is_solution(point):
        raise ProjectionError("Gauss-Newton converged to a spurious zero of the constraint map")
    return point


def _stalled(history):
    """Whether the residuals (one per iteration) fell by less than 1% over the last :data:`STALL_WINDOW`."""
    return len(history) > STALL_WINDOW and history[-1] > 0.99 * history[-1 - STALL_WINDOW]


def _cap_blocks(pattern, step, max_step):
    """Scale, in place, each block's part of `step` down to norm at most `max_step`."""
    for group in pattern.blocks:
        norms = np.linalg.norm(step[group.columns], axis=-1)                      # [b]
        factors = np.minimum(1.0, max_step / np.maximum(norms, np.finfo(float).tiny))
        step[group.columns] *= factors[:, None]


def _blocked_decision(manifold, point, rtol, atol):
    """Block SVDs (full matrices) of DΦ(point)·diag(s) and the rank decision of the whole matrix."""
    decomposition = _decomposition(manifold, point)
    shape = manifold.pattern.shape
    if min(shape) == 0:
        return decomposition, numerical_rank(np.zeros(shape), rtol=rtol, atol=atol)
    return decomposition, rank_of_values(_all_values([entry[1] for entry in decomposition], shape), rtol=rtol,
                                         atol=atol)


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
    scales = _tangent_scales(manifold.ambient)
    if _blocked(manifold):
        decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
        pieces = _block_vectors(decomposition, decision.tolerance, kernel=True)
        basis = _assemble(pieces, manifold.ambient.dim, manifold.pattern.free_columns)
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
    from scipy.sparse import coo_array

    if not _blocked(manifold):
        basis, decision = tangent_basis(manifold, point, rtol=rtol, atol=atol)
        return coo_array(basis).tocsc(), decision
    scales = _tangent_scales(manifold.ambient)
    decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
    rows, columns, values, start = [], [], [], 0
    for block_columns, vectors in _block_vectors(decomposition, decision.tolerance, kernel=True):
        rows.append(block_columns.ravel())
        columns.append(np.repeat(np.arange(start, start + len(vectors)), block_columns.shape[-1]))
        values.append((vectors * scales[block_columns]).ravel())
        start += len(vectors)
    free = manifold.pattern.free_columns
    rows.append(free)
    columns.append(np.arange(start, start + len(free)))
    values.append(scales[free])
    basis = coo_array((np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
                      shape=(manifold.ambient.dim, start + len(free)))
    return basis.tocsc(), decision


def normal_basis(manifold, point, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Orthonormal basis of the row space of DΦ(point)·diag(s) (the normal space in dimensionless
    coordinates u = v / s), shape=[k, rank]."""
    if _blocked(manifold):
        decomposition, decision = _blocked_decision(manifold, point, rtol, atol)
        return _assemble(_block_vectors(decomposition, decision.tolerance, kernel=False), manifold.ambient.dim)
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
    scales = _tangent_scales(manifold.ambient)
    if _blocked(manifold):
        inverse = _pseudo_inverse(manifold, point, rtol, sparse=False)
        count, size = basis.shape[1], other.shape[1]
        acceleration = np.empty((manifold.ambient.dim, count, size))
        chunk = max(1, CHUNK_ENTRIES // max(1, size * sum(manifold.pattern.shape)))
        for start in range(0, count, chunk):
            second = hessian_form(manifold, point, basis[:, start:start + chunk], other)
            acceleration[:, start:start + chunk] = _apply(inverse, second)
        acceleration *= -scales[:, None, None]
        return acceleration
    if manifold.constraint_hessian is None:
        second = hessian_form(manifold, point, basis, other)
    else:
        second = np.einsum("cab,ai,bj->cij", manifold.constraint_hessian(point), basis, other)
    pseudo_inverse = np.linalg.pinv(scaled_jacobian(manifold, point), rcond=rtol)
    return -scales[:, None, None] * np.einsum("kc,cij->kij", pseudo_inverse, second)
