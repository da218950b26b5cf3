"""project_many: the batched Gauss-Newton projection equals project point by point.

Point by point to rounding where DΦ has full row rank; with redundant loop
rows (a singular value of DΦ of the order of |Φ| off M, which amplifies
rounding) both reach M at nearby points of the same fibre.
"""

import numpy as np
import pytest

from builders import five_bar, five_bar_positions, rsur, spatial_mix, spherical_four_bar
from manifold import AmbientSpace, ImplicitManifold, ProjectionError, jacobian_rank, project, project_many
from mechanisms import configuration_space, home
from mechanisms.catalogue.slider_crank import slider_crank

#: mechanisms whose DΦ has full row rank
MECHANISMS = {
    "five-bar": lambda: five_bar(five_bar_positions(1.2, 2.0)),
    "slider-crank": lambda: slider_crank(crank=2.0, coupler=1.0, theta=0.3),
    "spherical four-bar": spherical_four_bar,
    "RSUR pose": rsur,
}


def starts_near_home(mechanism, rng, shape, size=0.05):
    """Points of K at random chart steps of dimensionless size ~`size` from the home, shape=[*shape, point_size]."""
    space = configuration_space(mechanism).ambient
    steps = size * space.tangent_scales * rng.standard_normal(shape + (space.dim,))
    return space.retract(home(mechanism), steps)


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_batched_projection_equals_projection_point_by_point(name):
    rng = np.random.default_rng(40)
    mechanism = MECHANISMS[name]()
    manifold = configuration_space(mechanism)
    assert jacobian_rank(manifold, home(mechanism)).rank == manifold.pattern.shape[0]
    starts = starts_near_home(mechanism, rng, (2, 3))
    projected, reached = project_many(manifold, starts)
    assert projected.shape == starts.shape and reached.shape == (2, 3) and reached.all()
    for index in np.ndindex(2, 3):
        single = project(manifold, starts[index])
        np.testing.assert_allclose(projected[index], single, rtol=0, atol=1e-12)
        assert np.linalg.norm(manifold.constraint(projected[index])) <= 1e-12


def test_with_redundant_rows_the_batch_reaches_the_manifold_near_the_single_projections():
    rng = np.random.default_rng(42)
    mechanism = spatial_mix()
    manifold = configuration_space(mechanism)
    assert jacobian_rank(manifold, home(mechanism)).rank < manifold.pattern.shape[0]
    starts = starts_near_home(mechanism, rng, (4,))
    projected, reached = project_many(manifold, starts)
    assert reached.all()
    for start, found in zip(starts, projected):
        single = project(manifold, start)
        assert np.linalg.norm(manifold.constraint(found)) <= 1e-12
        assert np.linalg.norm(found - single) < 1e-3 * np.linalg.norm(start - single)


def test_points_on_the_manifold_are_kept_bit_for_bit():
    rng = np.random.default_rng(41)
    mechanism = MECHANISMS["five-bar"]()
    manifold = configuration_space(mechanism)
    on_manifold = np.array([project(manifold, start) for start in starts_near_home(mechanism, rng, (3,))])
    mixed = np.concatenate([on_manifold, starts_near_home(mechanism, rng, (2,))])
    projected, reached = project_many(manifold, mixed)
    assert reached.all()
    np.testing.assert_array_equal(projected[:3], on_manifold)
    assert not np.array_equal(projected[3:], mixed[3:])


def test_a_point_that_cannot_be_projected_is_reported_where_project_raises():
    circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p ** 2).sum(-1, keepdims=True) - 4.0,
                              lambda p: 2.0 * p[..., None, :])
    starts = np.array([[3.0, 1.0], [0.0, 0.0], [-1.0, 0.5]])  # the origin: DΦ = 0, no step
    projected, reached = project_many(circle, starts, max_iterations=20)
    assert reached.tolist() == [True, False, True]
    for start, found, ok in zip(starts, projected, reached):
        if ok:
            np.testing.assert_allclose(found, project(circle, start), rtol=0, atol=1e-12)
        else:
            with pytest.raises(ProjectionError):
                project(circle, start, max_iterations=20)


def test_an_empty_stack_is_projected_to_an_empty_stack():
    circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: (p ** 2).sum(-1, keepdims=True) - 1,
                              lambda p: 2 * p[..., None, :])
    projected, reached = project_many(circle, np.zeros((0, 2)))
    assert projected.shape == (0, 2) and reached.shape == (0,)


def test_a_large_mechanism_is_projected_block_by_block_as_point_by_point():
    """Past BLOCK_THRESHOLD coordinates the batch solves DΦ's blocks apart (manifold.minimum_norm_steps): it
    never forms the dense c × k Jacobians of the stack (at k = 1000, 25 points took 660 MB that way), and
    reaches the points the single projection reaches."""
    import dataclasses

    from builders import ladder
    from manifold.implicit import BLOCK_THRESHOLD

    rng = np.random.default_rng(41)
    mechanism = ladder(20, tail=1)
    manifold = configuration_space(mechanism)
    assert manifold.ambient.dim >= BLOCK_THRESHOLD

    def dense(point):
        raise AssertionError("the dense Jacobian of a stack was formed")

    starts = starts_near_home(mechanism, rng, (5,))
    projected, reached = project_many(dataclasses.replace(manifold, constraint_jacobian=dense), starts)
    assert reached.all()
    for start, point in zip(starts, projected):
        np.testing.assert_allclose(point, project(manifold, start), atol=1e-10)
