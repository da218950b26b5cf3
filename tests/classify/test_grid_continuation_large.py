"""The grid continuation of ``closedchain map`` on a large mechanism: the blocks of DΦ solved apart.

Past :data:`manifold.implicit.BLOCK_THRESHOLD` coordinates the corrector's
and the predictor's minimum-norm solves (:func:`manifold.minimum_norm_steps`)
and the held coordinates' margins (:func:`manifold.scaled_singular_values`)
work block by block: the stack of dense c × k Jacobians of a 5 × 5 grid of
the RSUR stack at k = 400 took 32 s (180 s and 2 GB at k = 1000).
"""

import numpy as np

from builders import ladder
from classify.grid_continuation import assemble_grid, held_margins
from manifold import JacobianPattern, implicit
from mechanisms import from_displacements, home


def grid(mechanism, values):
    """Targets of A1 and A2 on a square grid of `values`, the other joints at home; the held coordinates."""
    targets = np.array([from_displacements(mechanism, {"A1": first, "A2": second})
                        for first in values for second in values])
    return targets, tuple(sorted(mechanism.actuated_coordinates))


def test_a_large_grid_is_continued_block_by_block_as_densely(monkeypatch):
    mechanism = ladder(22)  # 88 joints, 66 free once the 22 actuated ones are held
    targets, held = grid(mechanism, np.linspace(-0.3, 0.3, 3))
    k = len(mechanism.joints)
    stacks = []
    dense = JacobianPattern.dense

    def recorded(pattern, entries):
        if pattern.shape[1] == k:
            stacks.append(np.ndim(entries) - 1)
        return dense(pattern, entries)

    monkeypatch.setattr(JacobianPattern, "dense", recorded)
    points, reached = assemble_grid(mechanism, home(mechanism), targets, (3, 3), held)
    margins = held_margins(mechanism, points, held)
    assert reached.all() and max(stacks, default=0) == 0  # no stack of whole Jacobians
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 10 ** 9)  # the dense solves
    expected, expected_reached = assemble_grid(mechanism, home(mechanism), targets, (3, 3), held)
    assert expected_reached.all()
    np.testing.assert_allclose(points, expected, atol=1e-9)
    np.testing.assert_allclose(margins, held_margins(mechanism, expected, held), rtol=1e-9)
