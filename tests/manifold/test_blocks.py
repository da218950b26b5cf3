"""manifold.blocks: block decompositions of a sparse DΦ agree with the dense linear algebra.

A linear manifold Φ(x) = A x whose A has blocks of two shapes (one with more
rows than columns), an empty row and a free column: ranks, kernels, row
spaces, minimum-norm solves (dense and by LSQR) and capped steps computed
block by block equal their dense counterparts.
"""

import numpy as np
import pytest

from manifold import implicit

from manifold import (
    AmbientSpace, ImplicitManifold, JacobianPattern, jacobian_rank, normal_basis, numerical_rank, sparse_tangent_basis,
    tangent_basis,
)
from manifold.blocks import (
    apply_pseudo_inverse, block_rank, block_vectors, cap_block_steps, decompose, dense_basis,
    labelled_block_singular_values, minimum_norm_solutions, pseudo_inverse, scaled_blocks, sparse_basis,
    stacked_singular_values,
)


def linear_manifold(rng, singular=False):
    """Φ(x) = A x in ℝ⁹ with A of a fixed pattern (8 × 9: row 3 empty, column 7 free); `singular` makes the
    first block rank-deficient."""
    matrix = np.zeros((8, 9))
    matrix[np.ix_([0, 1], [0, 3, 5])] = rng.standard_normal((2, 3))
    matrix[np.ix_([2, 4], [1, 2, 8])] = rng.standard_normal((2, 3))
    matrix[np.ix_([5, 6, 7], [4, 6])] = rng.standard_normal((3, 2))
    if singular:
        matrix[1, [0, 3, 5]] = 2.0 * matrix[0, [0, 3, 5]]
    rows, columns = np.nonzero(matrix)
    manifold = ImplicitManifold(
        AmbientSpace(("R",) * 9, tuple(rng.uniform(0.5, 2.0, 9))), lambda x: x @ matrix.T,
        lambda x: np.broadcast_to(matrix, np.shape(x)[:-1] + matrix.shape),
        pattern=JacobianPattern((8, 9), rows, columns),
        constraint_jacobian_entries=lambda x: np.broadcast_to(matrix[rows, columns], np.shape(x)[:-1] + (len(rows),)))
    return manifold, matrix * manifold.ambient.tangent_scales


def projector(columns):
    return columns @ np.linalg.pinv(columns)


@pytest.mark.parametrize("singular", [False, True])
def test_blocks_rank_kernel_and_row_space_equal_the_dense_ones(singular):
    rng = np.random.default_rng(30)
    manifold, dense = linear_manifold(rng, singular)
    point = np.zeros(9)
    blocks = scaled_blocks(manifold, point)
    assert sorted(block.shape for block in blocks) == [(1, 3, 2), (2, 2, 3)]  # blocks of two shapes
    decomposition = decompose(manifold, point)
    decision = block_rank([values for _, values, _ in decomposition], dense.shape, 1e-6, 1e-12)
    reference = numerical_rank(dense)
    assert decision.rank == reference.rank == 6 - singular
    assert decision.tolerance == pytest.approx(reference.tolerance, rel=1e-12)
    np.testing.assert_allclose(decision.singular_values, reference.singular_values, atol=1e-12)
    kernel = dense_basis(block_vectors(decomposition, decision.tolerance, kernel=True), 9,
                         manifold.pattern.free_columns)
    rows = dense_basis(block_vectors(decomposition, decision.tolerance, kernel=False), 9)
    assert kernel.shape == (9, 9 - decision.rank) and rows.shape == (9, decision.rank)
    np.testing.assert_allclose(np.hstack([kernel, rows]).T @ np.hstack([kernel, rows]), np.eye(9), atol=1e-12)
    np.testing.assert_allclose(dense @ kernel, 0.0, atol=1e-12)
    np.testing.assert_allclose(projector(rows), projector(dense.T), atol=1e-12)
    scales = manifold.ambient.tangent_scales
    sparse = sparse_basis(block_vectors(decomposition, decision.tolerance, kernel=True), scales,
                          manifold.pattern.free_columns)
    np.testing.assert_array_equal(sparse.toarray(), kernel * scales[:, None])


def test_a_stack_of_points_or_of_jacobians_decomposes_as_each_point():
    """decompose of points [2, 3, 9] or of dense DΦ·diag(s) [2, 8, 9] (exactly one of the two): each item's
    blocks, values and vectors, are the single point's, to the bit."""
    rng = np.random.default_rng(35)
    manifold, dense = linear_manifold(rng, singular=True)
    single = decompose(manifold, np.zeros(9))
    for stacked, shape in ((decompose(manifold, rng.standard_normal((2, 3, 9))), (2, 3)),
                           (decompose(manifold, jacobian=np.stack([dense, dense])), (2,))):
        for (group, values, right), (stacked_group, stacked_values, stacked_right) in zip(single, stacked):
            assert stacked_group is group and stacked_values.shape == shape + values.shape
            for index in np.ndindex(shape):
                np.testing.assert_array_equal(stacked_values[index], values)
                np.testing.assert_array_equal(stacked_right[index], right)
    for arguments in ({}, {"point": np.zeros(9), "jacobian": dense}):
        with pytest.raises(ValueError, match="exactly one"):
            decompose(manifold, **arguments)


@pytest.mark.parametrize("sparse_columns", [None, 0])
@pytest.mark.parametrize("singular", [False, True])
def test_block_pseudo_inverse_solves_as_the_dense_one(singular, sparse_columns):
    rng = np.random.default_rng(31)
    manifold, dense = linear_manifold(rng, singular)
    right_hand_side = rng.standard_normal((8, 2, 3))
    inverse = pseudo_inverse(manifold, np.zeros(9), 1e-12, sparse_columns=sparse_columns)
    solution = apply_pseudo_inverse(inverse, right_hand_side)
    expected = np.einsum("kc,cij->kij", np.linalg.pinv(dense, rcond=1e-12), right_hand_side)
    assert solution.shape == (9, 2, 3)
    np.testing.assert_allclose(solution, expected, atol=1e-12 if sparse_columns is None else 1e-9)


@pytest.mark.parametrize("sparse_columns", [None, 0])
@pytest.mark.parametrize("singular", [False, True])
def test_stacked_minimum_norm_solutions_are_the_dense_pseudo_inverses(singular, sparse_columns):
    """Of a stack of matrices (each its own cut rcond·σ₁: one block of one matrix lies below it) and of some
    columns only (the others held): ``J⁺ b`` of each dense matrix."""
    rng = np.random.default_rng(33)
    manifold, dense = linear_manifold(rng, singular)
    pattern, scales = manifold.pattern, manifold.ambient.tangent_scales
    entries = dense[pattern.rows, pattern.columns] / scales[pattern.columns]
    stack = entries * rng.uniform(0.1, 10.0, (4, 1))  # four multiples of A
    if sparse_columns is None:  # LSQR solves a block whatever its size: no cut relative to the whole matrix
        stack[1, np.isin(pattern.rows, [0, 1])] *= 1e-13  # the first block of matrix 1 below its cut: ignored
    right_hand_side = rng.standard_normal((4, 8))
    for columns in (np.arange(9), np.array([8, 0, 4, 3, 7, 1])):
        restricted, kept = pattern.restricted(columns)
        solutions = minimum_norm_solutions(restricted, stack[:, kept], scales[columns], right_hand_side, 1e-12,
                                           sparse_columns)
        matrices = pattern.dense(stack)[..., columns] * scales[columns]
        expected = np.einsum("nkc,nc->nk", np.linalg.pinv(matrices, rcond=1e-12), right_hand_side)
        assert solutions.shape == (4, len(columns))
        np.testing.assert_allclose(solutions, expected, atol=1e-12 if sparse_columns is None else 1e-9)


@pytest.mark.parametrize("singular", [False, True])
def test_stacked_singular_values_are_the_dense_ones(singular):
    """Of a stack, of all columns and of some (the others held; an empty stack too): the union of the blocks'
    values, descending, with zeros up to min(c, k) as LAPACK gives them (row 3 is empty)."""
    rng = np.random.default_rng(34)
    manifold, dense = linear_manifold(rng, singular)
    pattern, scales = manifold.pattern, manifold.ambient.tangent_scales
    entries = dense[pattern.rows, pattern.columns] / scales[pattern.columns]
    stack = entries * rng.uniform(0.1, 10.0, (3, len(entries)))
    for columns in (np.arange(9), np.array([8, 0, 4, 3, 7, 1]), np.array([2])):
        restricted, kept = pattern.restricted(columns)
        for count in (3, 0):
            values = stacked_singular_values(restricted, stack[:count, kept], scales[columns])
            matrices = pattern.dense(stack[:count])[..., columns] * scales[columns]
            np.testing.assert_allclose(values, np.linalg.svd(matrices, compute_uv=False), atol=1e-12)
            assert values.shape == (count, min(8, len(columns)))


def test_capped_steps_keep_each_block_within_the_cap():
    """The cap is on each block's dimensionless norm ‖step / s‖ (radians and lengths over their scale)."""
    rng = np.random.default_rng(32)
    manifold, _ = linear_manifold(rng)
    step = rng.standard_normal(9)
    step[[1, 2, 8]] *= 1e-3  # a block already within the cap is left as it is
    scales = rng.uniform(0.5, 20.0, 9)
    capped = step.copy()
    cap_block_steps(manifold.pattern, capped, 0.5, scales)
    for group in manifold.pattern.blocks:
        for columns in group.columns:
            norm = np.linalg.norm(step[columns] / scales[columns])
            expected = step[columns] * min(1.0, 0.5 / norm)
            np.testing.assert_allclose(capped[columns], expected, rtol=1e-15)
    assert capped[7] == step[7]  # the free column belongs to no block


@pytest.mark.parametrize("function", [jacobian_rank, normal_basis, sparse_tangent_basis, tangent_basis])
def test_a_point_that_is_not_finite_is_refused_on_the_block_path_as_on_the_dense_one(function):
    """40 independent circles (k = 80 ≥ BLOCK_THRESHOLD): NaN ended in LAPACK's 'SVD did not converge'."""
    count = 40
    rows, columns = np.repeat(np.arange(count), 2), np.arange(2 * count)
    manifold = ImplicitManifold(
        AmbientSpace(("R",) * (2 * count)),
        lambda p: p[..., 0::2] ** 2 + p[..., 1::2] ** 2 - 1.0,
        lambda p: JacobianPattern((count, 2 * count), rows, columns).dense(2 * np.asarray(p, dtype=float)),
        pattern=JacobianPattern((count, 2 * count), rows, columns),
        constraint_jacobian_entries=lambda p: 2 * np.asarray(p, dtype=float))
    point = np.ones(2 * count)
    point[3] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        function(manifold, point)


@pytest.mark.parametrize("kernel", [True, False])
def test_block_vectors_of_a_stack_are_each_matrix_s_to_the_bit(kernel):
    """block_vectors of the blocks of a stack [4] of DΦ·diag(s) with a cut per matrix: per group, the vectors of
    matrix i are those of block_vectors of matrix i alone, to the bit, with i as their stack index."""
    rng = np.random.default_rng(36)
    manifold, dense = linear_manifold(rng)
    stack = dense * np.array([1.0, 1e-9, 3.0, 1.0])[:, None, None]
    stack[3, 0] *= 1e-10  # a row of the first block below the cut in the last matrix only
    decomposition = decompose(manifold, jacobian=stack)
    tolerance = np.array([numerical_rank(matrix).tolerance for matrix in stack])
    stacked = block_vectors(decomposition, tolerance, kernel)
    for index in range(len(stack)):
        alone = block_vectors([(group, values[index], right[index]) for group, values, right in decomposition],
                              tolerance[index], kernel)
        for (configurations, columns, vectors), (columns_alone, vectors_alone) in zip(stacked, alone):
            np.testing.assert_array_equal(columns[configurations == index], columns_alone)
            np.testing.assert_array_equal(vectors[configurations == index], vectors_alone)
    counts = sum(np.bincount(configurations, minlength=len(stack)) for configurations, _, _ in stacked)
    assert counts[3] != counts[0]  # the cuts differ: the last matrix's first block has one value less above it


@pytest.mark.parametrize("shared_columns", [False, True], ids=["labels per matrix", "one set of labels"])
def test_labelled_block_singular_values_are_the_dense_ones(shared_columns):
    """Stacks of matrices block diagonal after permuting rows and columns by random labels (blocks of several
    shapes, wide and tall, 1 × 1 ones; labels with rows and no column and the reverse; no rows or no columns;
    a block 1e-9 of the others): the union of the blocks' values with the dense SVD's zeros, to 1e-12 of σ₁."""
    rng = np.random.default_rng(41)
    for trial in range(120):
        count, rows, columns = int(rng.integers(0, 4)), int(rng.integers(0, 10)), int(rng.integers(0, 10))
        labels = int(rng.integers(1, 6))
        row_labels = rng.integers(0, labels, rows)
        column_labels = rng.integers(0, labels + 1, columns if shared_columns else (count, columns))
        mask = row_labels[:, None] == np.broadcast_to(column_labels, (count, columns))[:, None, :]
        matrices = rng.standard_normal((count, rows, columns)) * mask
        if rows and trial % 2:
            matrices[:, row_labels == row_labels[0]] *= 1e-9
        values = labelled_block_singular_values(matrices, row_labels, column_labels)
        dense = np.linalg.svd(matrices, compute_uv=False) if count else np.zeros((0, min(rows, columns)))
        assert values.shape == dense.shape == (count, min(rows, columns)), trial
        if dense.size:
            assert np.all(np.abs(values - dense) <= 1e-12 * dense[:, :1]), trial


def test_labelled_block_singular_values_of_coordinate_rows_on_one_block_basis(monkeypatch):
    """Coordinate rows (one nonzero each, two on one column) times a basis whose columns each lie on one
    component of a pattern (the labels of :attr:`JacobianPattern.column_components`): the blocks' values are the
    dense ones; a given `singular_values` is the one called."""
    rng = np.random.default_rng(42)
    manifold, _ = linear_manifold(rng)
    pattern = manifold.pattern
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 0)  # the block path's basis: one block per column
    basis = tangent_basis(manifold, np.zeros(9))[0]                              # [9, m]
    components = pattern.column_components
    assert sorted(set(components.tolist())) == list(range(len(set(components.tolist()))))
    columns, factors = np.array([0, 4, 7, 0, 8]), rng.uniform(0.5, 2.0, 5)
    block = factors[:, None] * basis[columns]
    column_labels = components[np.argmax(basis != 0.0, axis=0)]
    assert np.all((basis == 0.0) | (components[:, None] == column_labels))
    called = []
    values = labelled_block_singular_values(block[None], components[columns], column_labels,
                                            lambda blocks: called.append(blocks.shape) or
                                            np.linalg.svd(blocks, compute_uv=False))
    dense = np.linalg.svd(block, compute_uv=False)
    assert called and np.all(np.abs(values[0] - dense) <= 1e-12 * dense[0])
