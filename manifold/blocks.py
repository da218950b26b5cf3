"""The block structure of a sparse constraint Jacobian DΦ, and linear algebra block by block.

A manifold may declare where DΦ can be nonzero (:class:`JacobianPattern`,
with ``constraint_jacobian_entries`` giving the entries there). Its rows and
columns split into *blocks*, the connected components of the pattern (for a
mechanism, groups of loops that share joints), and columns no row touches.
After permuting rows and columns DΦ is block diagonal, so its singular values
are the union of the blocks', its kernel the direct sum of theirs, and a
minimum-norm solve is one per block. Blocks of one shape are stacked and
decomposed by one batched SVD.

Everything here works on the dimensionless Jacobian DΦ·diag(s)
(:attr:`AmbientSpace.tangent_scales`); :mod:`manifold.implicit` decides when
to take this path and keeps the public functions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .rank import numerical_rank, rank_of_values

__all__ = [
    "BlockGroup", "JacobianPattern", "PseudoInverse", "scaled_blocks", "decompose", "block_rank",
    "block_vectors", "dense_basis", "sparse_basis", "pseudo_inverse", "apply_pseudo_inverse", "cap_block_steps",
    "minimum_norm_solutions", "stacked_singular_values", "union_of_values", "labelled_block_singular_values",
]


@dataclass(frozen=True, eq=False)
class BlockGroup:
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
    blocks : tuple of BlockGroup
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

    def dense(self, entries):
        """The matrices with `entries` (shape=[..., nnz], in the pattern's order) at the pattern and zeros
        elsewhere, shape=[..., c, k].

        >>> JacobianPattern((2, 3), [0, 1], [2, 0]).dense([5.0, 7.0]).tolist()
        [[0.0, 0.0, 5.0], [7.0, 0.0, 0.0]]
        """
        entries = np.asarray(entries, dtype=float)
        matrices = np.zeros(entries.shape[:-1] + self.shape)
        matrices[..., self.rows, self.columns] = entries
        return matrices

    def restricted(self, columns):
        """The pattern of the columns `columns` of DΦ (in that order), and which of this pattern's entries it
        keeps, in its order: ``(JacobianPattern of shape (c, len(columns)), indices [nnz'])``.

        >>> pattern, kept = JacobianPattern((2, 3), [0, 0, 1], [0, 1, 2]).restricted([2, 1])
        >>> pattern.rows.tolist(), pattern.columns.tolist(), kept.tolist()
        ([0, 1], [1, 0], [1, 2])
        """
        columns = np.asarray(columns, dtype=np.intp)
        place = np.full(self.shape[1], -1, dtype=np.intp)
        place[columns] = np.arange(len(columns))
        kept = np.flatnonzero(place[self.columns] >= 0)
        return JacobianPattern((self.shape[0], len(columns)), self.rows[kept], place[self.columns[kept]]), kept

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
            groups.append(BlockGroup(np.array([rows_of[label] for label in labels], dtype=np.intp),
                                     np.array([columns_of[label] for label in labels], dtype=np.intp),
                                     positions))
        return tuple(groups)

    @cached_property
    def column_components(self):
        """The component of the pattern each column belongs to, shape=[k]: its block's number (the blocks
        numbered group by group, in the order of :attr:`blocks`), or a number of its own for a free column."""
        labels = np.empty(self.shape[1], dtype=np.intp)
        start = 0
        for group in self.blocks:
            labels[group.columns] = start + np.arange(len(group.columns))[:, None]
            start += len(group.columns)
        labels[self.free_columns] = start + np.arange(len(self.free_columns))
        return labels

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


# --------------------------------------------------------------------------- decompositions and ranks

def _stacked_blocks(pattern, entries, scales):
    """The blocks of a stack of ``DΦ·diag(s)`` given by their entries [..., nnz] at `pattern`: ``(group, blocks
    [..., b, r, q])`` per block group."""
    padded = np.concatenate([entries, np.zeros(entries.shape[:-1] + (1,))], axis=-1)
    return [(group, padded[..., group.positions] * scales[group.columns][:, None, :]) for group in pattern.blocks]


def scaled_blocks(manifold, point=None, *, jacobian=None, entries=None):
    """The blocks of DΦ(point)·diag(s), or of the given `jacobian` or `entries`, one array per block group of
    ``manifold.pattern``, shape=[..., b, r, q] (``DΦ·diag(s)[..., rows[i][:, None], columns[i]]`` for block i).

    Parameters
    ----------
    manifold : ImplicitManifold
        With a pattern and ``constraint_jacobian_entries``.
    point : array_like, shape=[..., point_size], optional
        Points (or one point) where DΦ is taken, from its entries at the pattern.
    jacobian : array_like, shape=[..., c, k], optional
        Instead of `point`: DΦ·diag(s) itself, zero off the pattern (e.g. a stack already evaluated densely).
    entries : array_like, shape=[..., nnz], optional
        Instead of `point`: DΦ's entries at the pattern (unscaled, as ``constraint_jacobian_entries`` gives
        them), already evaluated.

    Returns
    -------
    list of ndarray
        Shape=[..., b, r, q] per block group.
    """
    if sum(given is not None for given in (point, jacobian, entries)) != 1:
        raise ValueError("Expected exactly one of point, jacobian and entries")
    if jacobian is not None:
        jacobian = np.asarray(jacobian, dtype=float)
        return [jacobian[..., group.rows[:, :, None], group.columns[:, None, :]] for group in manifold.pattern.blocks]
    if entries is None:
        entries = manifold.constraint_jacobian_entries(point)
    entries = np.asarray(entries, dtype=float)
    return [blocks for _, blocks in _stacked_blocks(manifold.pattern, entries, manifold.ambient.tangent_scales)]


def decompose(manifold, point=None, *, jacobian=None, entries=None):
    """SVD (full matrices) of every block of DΦ(point)·diag(s) (or of `jacobian`, :func:`scaled_blocks`), the
    blocks of one shape of every matrix of the stack in one batched call.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[..., point_size], optional
    jacobian : array_like, shape=[..., c, k], optional
        DΦ·diag(s) itself instead of `point`.
    entries : array_like, shape=[..., nnz], optional
        DΦ's entries at the pattern instead of `point` (unscaled).

    Returns
    -------
    list of tuple
        ``(block group, singular values [..., b, min(r, q)], Vᴴ [..., b, q, q])`` per block group.
    """
    decomposed = []
    for group, blocks in zip(manifold.pattern.blocks, scaled_blocks(manifold, point, jacobian=jacobian,
                                                                    entries=entries)):
        _, values, right = np.linalg.svd(blocks, full_matrices=True)
        decomposed.append((group, values, right))
    return decomposed


def block_rank(values, shape, rtol, atol):
    """The rank decision of the whole DΦ·diag(s) of `shape` ``(c, k)`` from its blocks' singular values.

    Every singular value of the whole is a block's, or an exact zero (rows no
    entry touches, blocks with more rows than columns); the cut is relative
    to σ₁ of the whole, as for the dense matrix (:func:`manifold.rank_of_values`).

    Parameters
    ----------
    values : list of ndarray
        Each block group's singular values, shape=[b, min(r, q)].
    shape : tuple of int
    rtol, atol : float

    Returns
    -------
    decision : RankDecision
    """
    if min(shape) == 0:
        return numerical_rank(np.zeros(shape), rtol=rtol, atol=atol)
    values = np.concatenate([entry.ravel() for entry in values]) if values else np.zeros(0)
    values = np.concatenate([values, np.zeros(max(min(shape) - len(values), 0))])
    return rank_of_values(values, rtol=rtol, atol=atol)


def block_vectors(decomposition, tolerance, kernel):
    """Right singular vectors of the blocks (dimensionless): the kernel ones (σ ≤ `tolerance`, each block's
    right singular vectors beyond its count of values above the cut) or the row-space ones.

    Parameters
    ----------
    decomposition : list of tuple
        From :func:`decompose`: ``(block group, values [..., b, s], Vᴴ [..., b, q, q])`` of one matrix or of a
        stack of them.
    tolerance : float or ndarray, shape=[...]
        The cut of the whole matrix's rank decision (one per matrix of a stack).
    kernel : bool

    Returns
    -------
    list of tuple
        Per block group, ``(*stack, columns [n, q], vectors [n, q])``: the index of each vector's matrix
        along each stack axis (none for one matrix), its block's columns and the vector, in the order of
        the matrices, their blocks and the singular values.
    """
    pieces = []
    for group, values, right in decomposition:
        cut = np.asarray(tolerance)[..., None, None]
        ranks = np.count_nonzero(values > cut, axis=-1)                           # [..., b]
        beyond = np.arange(right.shape[-2]) >= ranks[..., None]                   # [..., b, q]
        *stack, block, row = np.nonzero(beyond if kernel else ~beyond)
        pieces.append((*stack, group.columns[block], right[(*stack, block, row)]))
    return pieces


def dense_basis(pieces, size, extra_columns=()):
    """The [size, count] matrix whose columns are the pieces' vectors (and unit vectors at `extra_columns`)."""
    count = sum(len(vectors) for _, vectors in pieces) + len(extra_columns)
    matrix = np.zeros((size, count))
    start = 0
    for columns, vectors in pieces:
        number = np.arange(start, start + len(vectors))
        matrix[columns, number[:, None]] = vectors
        start += len(vectors)
    matrix[np.asarray(extra_columns, dtype=np.intp), np.arange(start, count)] = 1.0
    return matrix


def sparse_basis(pieces, scales, free_columns):
    """:func:`dense_basis` of the pieces times the scales, as a sparse matrix (each column on one block),
    followed by the scaled unit vectors of the free columns.

    Returns
    -------
    basis : scipy.sparse.csc_array, shape=[k, count]
    """
    from scipy.sparse import coo_array

    rows, columns, values, start = [], [], [], 0
    for block_columns, vectors in pieces:
        rows.append(block_columns.ravel())
        columns.append(np.repeat(np.arange(start, start + len(vectors)), block_columns.shape[-1]))
        values.append((vectors * scales[block_columns]).ravel())
        start += len(vectors)
    rows.append(free_columns)
    columns.append(np.arange(start, start + len(free_columns)))
    values.append(scales[free_columns])
    basis = coo_array((np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
                      shape=(len(scales), start + len(free_columns)))
    return basis.tocsc()


# --------------------------------------------------------------------------- least-squares solves

@dataclass(frozen=True, eq=False)
class PseudoInverse:
    """``(DΦ(point)·diag(s))⁺`` block by block (see :func:`pseudo_inverse`).

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


def pseudo_inverse(manifold, point, rcond, sparse_columns=None):
    """The pseudo-inverse of DΦ(point)·diag(s), block by block.

    Singular values at most ``rcond · σ₁`` (σ₁ of the whole matrix) count as
    zero, as in ``numpy.linalg.lstsq`` and ``numpy.linalg.pinv``. Blocks with
    more than `sparse_columns` columns (if given) are left to LSQR (its
    iterates from zero converge to the minimum-norm solution), each on its
    own: σ₁ counts the blocks decomposed densely only, and LSQR's
    ``conlim`` 1/rcond is relative to its block.

    Returns
    -------
    PseudoInverse
    """
    pattern = manifold.pattern
    decomposed, iterative, largest = [], [], 0.0
    for group, blocks in zip(pattern.blocks, scaled_blocks(manifold, point)):
        if sparse_columns is not None and group.columns.shape[1] > sparse_columns:
            iterative.append((group, blocks))
            continue
        left, values, right = np.linalg.svd(blocks, full_matrices=False)
        decomposed.append((group, left, values, right))
        largest = max(largest, float(values.max(initial=0.0)))
    factors = tuple((group, left, np.divide(1.0, values, out=np.zeros_like(values), where=values > rcond * largest),
                     right) for group, left, values, right in decomposed)
    return PseudoInverse(pattern.shape, factors, tuple(iterative), rcond)


def apply_pseudo_inverse(inverse, right_hand_side):
    """The minimum-norm least-squares solutions u of ``DΦ·diag(s) u = b``.

    Parameters
    ----------
    inverse : PseudoInverse
    right_hand_side : array_like, shape=[c, ...]

    Returns
    -------
    solution : ndarray, shape=[k, ...]
    """
    from_rows = np.asarray(right_hand_side, dtype=float)
    trailing = from_rows.shape[1:]
    flat = from_rows.reshape(inverse.shape[0], -1)
    solution = np.zeros((inverse.shape[1], flat.shape[1]))
    for group, left, reciprocal, right in inverse.factors:
        projected = np.swapaxes(left, -1, -2) @ flat[group.rows]                    # [b, s, n]
        solution[group.columns] = np.swapaxes(right, -1, -2) @ (reciprocal[..., None] * projected)
    if inverse.iterative:
        from scipy.sparse import csr_array
        from scipy.sparse.linalg import lsqr

        for group, blocks in inverse.iterative:
            for rows, columns, block in zip(group.rows, group.columns, blocks):
                matrix = csr_array(block)
                for index in range(flat.shape[1]):
                    solution[columns, index] = lsqr(matrix, flat[rows, index], atol=1e-14, btol=1e-14,
                                                    conlim=1.0 / inverse.rcond, iter_lim=20 * len(columns))[0]
    return solution.reshape((inverse.shape[1],) + trailing)


def cap_block_steps(pattern, step, max_step, scales):
    """Scale, in place, each block's part of `step` (shape=[..., k]: one step or a stack) down to dimensionless
    norm ‖step/s‖ at most `max_step` (`scales`: s, shape=[k])."""
    for group in pattern.blocks:
        norms = np.linalg.norm(step[..., group.columns] / scales[group.columns], axis=-1)  # [..., b]
        factors = np.minimum(1.0, max_step / np.maximum(norms, np.finfo(float).tiny))
        step[..., group.columns] *= factors[..., None]


def stacked_singular_values(pattern, entries, scales):
    """Singular values of a stack of ``J = DΦ·diag(s)`` given by their entries at `pattern`, descending, zeros
    up to ``min(c, k)`` as a dense SVD gives them: the union of the blocks', shape=[n, min(c, k)].

    Parameters
    ----------
    pattern : JacobianPattern
    entries : array_like, shape=[n, nnz]
    scales : array_like, shape=[k]
    """
    entries = np.asarray(entries, dtype=float)
    values = [np.linalg.svd(blocks, compute_uv=False) for _, blocks in
              _stacked_blocks(pattern, entries, np.asarray(scales, dtype=float))]
    return union_of_values(values, len(entries), min(pattern.shape))


def union_of_values(values, count, size):
    """The singular values of a stack of `count` matrices from those of their blocks (one array [n, b, s] per
    block group), descending, with the zeros up to `size` (``min(c, k)``: rows no entry touches, blocks with
    more rows than columns) that a dense SVD gives, shape=[n, size]."""
    values = [value.reshape(count, value.shape[1] * value.shape[2]) for value in values]
    values = np.concatenate(values + [np.zeros((count, size))], axis=1)
    return -np.sort(-values, axis=1)[:, :size]


def minimum_norm_solutions(pattern, entries, scales, right_hand_side, rcond, sparse_columns=None):
    """The minimum-norm least-squares solutions u of ``J u = b`` for a stack of ``J = DΦ·diag(s)`` given by their
    entries at `pattern`, block by block (:func:`pseudo_inverse` and :func:`apply_pseudo_inverse` for each
    matrix, blocks of one shape of every matrix in one batched SVD).

    Singular values at most ``rcond · σ₁`` (σ₁ of each whole matrix) count as zero, as in
    ``numpy.linalg.pinv``: the solutions are ``J⁺ b`` of the dense matrices, to rounding. Blocks with more
    than `sparse_columns` columns (if given) are left to LSQR, one matrix at a time, as in
    :func:`apply_pseudo_inverse`: such a block is solved on its own (LSQR's ``conlim`` 1/rcond is relative to
    the block), so σ₁ counts the blocks decomposed densely only, and a block far below the others is not cut.

    Parameters
    ----------
    pattern : JacobianPattern
        Of shape ``(c, k)``.
    entries : array_like, shape=[n, nnz]
    scales : array_like, shape=[k]
    right_hand_side : array_like, shape=[n, c]
    rcond : float
    sparse_columns : int, optional

    Returns
    -------
    solutions : ndarray, shape=[n, k]
    """
    entries = np.asarray(entries, dtype=float)
    right_hand_side = np.asarray(right_hand_side, dtype=float)
    scales = np.asarray(scales, dtype=float)
    count = len(entries)
    dense, iterative, largest = [], [], np.zeros(count)
    for group, blocks in _stacked_blocks(pattern, entries, scales):     # blocks [n, b, r, q]
        if sparse_columns is not None and group.columns.shape[1] > sparse_columns:
            iterative.append((group, blocks))
            continue
        left, values, right = np.linalg.svd(blocks, full_matrices=False)
        dense.append((group, left, values, right))
        largest = np.maximum(largest, values.max(axis=(1, 2), initial=0.0))
    solutions = np.zeros((count, pattern.shape[1]))
    for group, left, values, right in dense:
        reciprocal = np.divide(1.0, values, out=np.zeros_like(values), where=values > rcond * largest[:, None, None])
        projected = np.swapaxes(left, -1, -2) @ right_hand_side[:, group.rows][..., None]    # [n, b, s, 1]
        solutions[:, group.columns] = (np.swapaxes(right, -1, -2) @ (reciprocal[..., None] * projected))[..., 0]
    for group, blocks in iterative:
        for index in range(count):
            inverse = PseudoInverse(pattern.shape, (), ((group, blocks[index]),), rcond)
            solutions[index] += apply_pseudo_inverse(inverse, right_hand_side[index])
    return solutions


def labelled_block_singular_values(matrices, row_labels, column_labels, singular_values=None):
    """Singular values of a stack of matrices that are block diagonal after permuting rows and columns, the
    blocks given by labels, descending, with the zeros up to ``min(a, m)`` that a dense SVD gives.

    Entry ``(i, j)`` of matrix ``l`` must be zero unless ``row_labels[i] == column_labels[l, j]`` (not
    checked). The rows and columns of one label form a block; with ``P``, ``Q`` the permutations that
    gather them, ``P M Q`` is block diagonal, so the singular values of M are the union of the blocks' and
    the zeros of the rows or columns beyond each block's smaller side (as for DΦ itself,
    :func:`union_of_values`). The blocks of one shape of every matrix go in one call of
    `singular_values`. A label with rows and no column (or columns and no row) in a matrix gives zeros only.

    For instance ``G = Dπ·T`` with coordinate rows Dπ (row i picks joint coordinate ``jᵢ``) and a tangent
    basis T whose every column lies on one component of DΦ's pattern (:func:`manifold.tangent_basis` on the
    block path): the labels are :attr:`JacobianPattern.column_components` of the ``jᵢ`` and of the columns'
    supports.

    Parameters
    ----------
    matrices : array_like, shape=[g, a, m]
    row_labels : array_like of int, shape=[a]
        Non-negative.
    column_labels : array_like of int, shape=[g, m] or [m]
        Non-negative; [m] for the same labels in every matrix.
    singular_values : callable, optional
        Singular values of a stack [t, p, q] of blocks, shape=[t, min(p, q)], descending; default
        ``numpy.linalg.svd(·, compute_uv=False)``, and the norm for blocks of one row or one column.

    Returns
    -------
    values : ndarray, shape=[g, min(a, m)]

    Examples
    --------
    >>> import numpy as np
    >>> from manifold.blocks import labelled_block_singular_values
    >>> matrix = np.array([[[0.0, 3.0, 0.0], [4.0, 0.0, 0.0]]])
    >>> labelled_block_singular_values(matrix, [1, 0], [0, 1, 2]).tolist()
    [[4.0, 3.0]]
    """
    matrices = np.asarray(matrices, dtype=float)
    count, rows, columns = matrices.shape
    row_labels = np.asarray(row_labels, dtype=np.intp).reshape(rows)
    column_labels = np.broadcast_to(np.asarray(column_labels, dtype=np.intp), (count, columns))
    size = min(rows, columns)
    values = np.zeros((count, size))
    if size == 0 or count == 0:
        return values
    label_count = int(max(row_labels.max(), column_labels.max())) + 1
    row_order = np.argsort(row_labels, kind="stable")
    row_counts = np.bincount(row_labels, minlength=label_count)
    row_starts = np.cumsum(row_counts) - row_counts
    column_order = np.argsort(column_labels, axis=1, kind="stable")                   # [g, m]
    sorted_labels = np.take_along_axis(column_labels, column_order, axis=1)
    keys = (np.arange(count)[:, None] * label_count + sorted_labels).ravel()           # ascending
    pairs, pair_starts, column_counts = np.unique(keys, return_index=True, return_counts=True)
    matrix_of, label_of = np.divmod(pairs, label_count)
    pair_starts = pair_starts - matrix_of * columns  # where each pair's columns start in its matrix's order
    shapes = np.stack([row_counts[label_of], column_counts], axis=1)                  # of each pair's block
    found_matrix, found_values = [], []
    for row_count, column_count in np.unique(shapes[shapes[:, 0] > 0], axis=0).tolist():
        chosen = np.flatnonzero(np.all(shapes == (row_count, column_count), axis=1))
        row_index = row_order[row_starts[label_of[chosen]][:, None] + np.arange(row_count)]       # [t, p]
        column_index = column_order[matrix_of[chosen][:, None],
                                    pair_starts[chosen][:, None] + np.arange(column_count)]      # [t, q]
        blocks = matrices[matrix_of[chosen][:, None, None], row_index[:, :, None], column_index[:, None, :]]
        found_values.append(_block_values(blocks, singular_values).ravel())
        found_matrix.append(np.repeat(matrix_of[chosen], min(row_count, column_count)))
    if found_values:
        matrix_of, found = np.concatenate(found_matrix), np.concatenate(found_values)
        order = np.argsort(matrix_of, kind="stable")
        matrix_of, found = matrix_of[order], found[order]
        counts = np.bincount(matrix_of, minlength=count)
        place = np.arange(len(matrix_of)) - (np.cumsum(counts) - counts)[matrix_of]
        values[matrix_of, place] = found
    return -np.sort(-values, axis=1)


def _block_values(blocks, singular_values):
    """Singular values of a stack of blocks [t, p, q]: `singular_values` if given, else a block of one row or
    column has its norm and others LAPACK's."""
    if singular_values is not None:
        return singular_values(blocks)
    if blocks.shape[-2] == 1 or blocks.shape[-1] == 1:
        return np.linalg.norm(blocks.reshape(len(blocks), -1), axis=-1)[:, None]
    return np.linalg.svd(blocks, compute_uv=False)
