"""Projection of far points block by block, the blocks that do not settle drawn again (manifold.settle_blocks)."""

import numpy as np
import pytest

from manifold import AmbientSpace, ImplicitManifold, JacobianPattern, ProjectionError, project, settle_blocks

BLOCKS = 70  # k ≥ BLOCK_THRESHOLD: handled block by block


def parabolas(count=BLOCKS):
    """Φ_b(x) = x_b² − 1, one block per coordinate: x_b = 0 is a critical point of Φ_b² that is no zero
    (Gauss-Newton's step there is 0), any other start reaches ±1."""
    pattern = JacobianPattern((count, count), np.arange(count), np.arange(count))
    return ImplicitManifold(AmbientSpace(("R",) * count), lambda p: np.asarray(p) ** 2 - 1.0,
                            lambda p: pattern.dense(2.0 * np.asarray(p)), pattern=pattern,
                            constraint_jacobian_entries=lambda p: 2.0 * np.asarray(p))


def test_the_stuck_blocks_alone_are_drawn_again_and_the_others_keep_their_columns():
    manifold = parabolas()
    stuck = np.arange(BLOCKS) % 7 == 0
    start = np.where(stuck, 0.0, 3.0)
    with pytest.raises(ProjectionError):  # projected whole, the stuck blocks hold the residual up
        project(manifold, start)
    drawn_columns = []

    def redraw(points, columns):
        drawn_columns.append(columns.copy())
        return np.where(columns, 0.5, points)

    settled, unsettled = settle_blocks(manifold, [start, np.full(BLOCKS, 2.0)], redraw, patience=8)
    assert not unsettled.any()
    np.testing.assert_allclose(settled, 1.0, atol=1e-12)
    assert len(drawn_columns) == 1 and drawn_columns[0].tolist() == [stuck.tolist()]  # once, the first point only


def test_blocks_that_never_settle_are_reported():
    manifold = parabolas()
    start = np.where(np.arange(BLOCKS) < 3, 0.0, 3.0)
    settled, unsettled = settle_blocks(manifold, [start], lambda points, columns: points, max_iterations=30)
    assert unsettled[0].tolist() == (np.arange(BLOCKS) < 3).tolist()
    np.testing.assert_allclose(settled[0, 3:], 1.0, atol=1e-12)


def test_an_empty_stack_settles_at_once():
    settled, unsettled = settle_blocks(parabolas(), np.zeros((0, BLOCKS)), redraw=None)
    assert settled.shape == unsettled.shape == (0, BLOCKS)
