"""Φ, the half-turn test and DΦ from one expansion equal the three separate functions."""

import numpy as np
import pytest

from builders import bennett, five_bar, five_bar_positions, rsur, spherical_four_bar
from mechanisms import closes, closure_and_jacobian, constraint, constraint_jacobian, home, kinematics_of

MECHANISMS = {
    "five-bar": lambda: five_bar(five_bar_positions(1.2, 2.0)),
    "bennett": bennett,
    "rsur": rsur,
    "spherical-four-bar": spherical_four_bar,
}


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_one_expansion_equals_the_separate_functions(name):
    mechanism = MECHANISMS[name]()
    space = kinematics_of(mechanism).ambient
    rng = np.random.default_rng(21)
    points = space.retract(home(mechanism), 0.7 * rng.standard_normal((6, space.dim)))
    half_turn = space.retract(home(mechanism), np.pi * np.eye(space.dim)[0])  # the first joint turned by π
    points = np.concatenate([points, half_turn[None], home(mechanism)[None]]).reshape(2, 4, -1)
    rows, turns, jacobian = closure_and_jacobian(mechanism, points)
    np.testing.assert_allclose(rows, constraint(mechanism, points), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(turns, closes(mechanism, points, tolerance=np.inf))
    np.testing.assert_allclose(jacobian, constraint_jacobian(mechanism, points), rtol=0, atol=1e-15)
    assert turns.reshape(-1)[-1] and not turns.reshape(-1)[-2]  # the home closes; the half-turn is seen


@pytest.mark.parametrize("name", sorted(MECHANISMS))
@pytest.mark.parametrize("batch", [(0,), (2, 0)])
def test_an_empty_stack_gives_empty_arrays_of_the_right_shapes(name, batch):
    """A stack of no configurations (e.g. a map none of whose points is reachable) was a reshape error."""
    mechanism = MECHANISMS[name]()
    point_size, (rows_count, columns) = home(mechanism).size, kinematics_of(mechanism).pattern.shape
    points = np.zeros(batch + (point_size,))
    rows, turns, jacobian = closure_and_jacobian(mechanism, points)
    assert rows.shape == constraint(mechanism, points).shape == batch + (rows_count,)
    assert turns.shape == closes(mechanism, points).shape == batch
    assert jacobian.shape == constraint_jacobian(mechanism, points).shape == batch + (rows_count, columns)
