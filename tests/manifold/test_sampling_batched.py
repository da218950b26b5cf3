"""sample_manifold projects its random starts all at once (manifold.project_many with project's cap, damping and
stall test) and keeps what project, one start at a time, would keep.

The random starts' damped projections onto the closing map and then onto Φ were a loop of single projections,
about half of every survey of M (a third of the test suite's time)."""

import dataclasses

import numpy as np
import pytest

from builders import five_bar, five_bar_positions, ladder, rsur, spherical_four_bar
from manifold import AmbientSpace, ImplicitManifold, ProjectionError, project, project_many, sample_manifold
from manifold.implicit import BLOCK_THRESHOLD, STALL_WINDOW
from manifold.sampling import CLOSING_ITERATIONS, CLOSING_TOLERANCE
from mechanisms import configuration_space, home

MECHANISMS = {
    "five-bar": lambda: five_bar(five_bar_positions(1.2, 2.0)),
    "spherical four-bar": spherical_four_bar,
    "RSUR pose": rsur,
}


def one_at_a_time(manifold, points, **options):
    """What sample_manifold kept before: each point projected by project, those it raised on left out."""
    kept = []
    for point in points:
        try:
            kept.append(project(manifold, point, **options))
        except ProjectionError:
            continue
    return np.reshape(kept, (-1, manifold.ambient.point_size))


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_damped_capped_projections_of_far_starts_are_project_point_by_point(name):
    """Levenberg-Marquardt from random points of K (each point its own damping), steps capped at 1: the same
    points reach the closing map, at the same places."""
    mechanism = MECHANISMS[name]()
    closing = configuration_space(mechanism).closing
    starts = closing.ambient.random_point(np.random.default_rng(5), center=home(mechanism), size=16)
    options = dict(tolerance=1e-6, max_step=1.0, max_iterations=100, damped=True)
    projected, reached = project_many(closing, starts, **options)
    for start, point, one in zip(starts, projected, reached):
        try:
            single = project(closing, start, **options)
        except ProjectionError:
            assert not one
            continue
        assert one
        np.testing.assert_allclose(point, single, rtol=0, atol=1e-9)
    assert reached.sum() >= 8


def test_project_each_is_project_point_by_point_spurious_zeros_included():
    """Near half-turns (zeros of Φ that project refuses, ``is_solution``) and near M: project_each says where
    project returns a point, and returns that point. The starts are 1e-3 (dimensionless) from those zeros, where
    Gauss-Newton converges in a few steps: from far away its path is chaotic, and the batch's rounding (pinv of a
    stack) and project's (lstsq) may end at different zeros."""
    from manifold import project_each

    mechanism = MECHANISMS["five-bar"]()
    manifold = configuration_space(mechanism)
    rng = np.random.default_rng(6)
    far = manifold.ambient.random_point(rng, center=home(mechanism), size=12)
    ends, reached = project_many(manifold, far, max_step=0.05, max_iterations=200)
    solutions = np.array([bool(manifold.is_solution(point)) for point in ends])
    zeros = np.concatenate([ends[reached & ~solutions][:2], ends[reached & solutions][:2]])
    assert len(zeros) == 4  # two half-turns, two points of M
    scales = manifold.ambient.tangent_scales
    starts = manifold.ambient.retract(zeros, 1e-3 * scales * rng.standard_normal((len(zeros), len(scales))))
    projected, projected_ok = project_each(manifold, starts, max_step=0.05)
    assert projected_ok.tolist() == [False, False, True, True]
    for start, point, ok in zip(starts, projected, projected_ok):
        try:
            single = project(manifold, start, max_step=0.05)
        except ProjectionError:
            assert not ok
            continue
        assert ok
        np.testing.assert_allclose(point, single, rtol=0, atol=1e-12)


def test_a_point_that_stalls_block_by_block_stops_after_the_stall_window():
    """project gives up, block by block, once the residual fell by less than 1% over STALL_WINDOW iterations;
    so does the batch (steps capped at 1e-3 from a random start: no progress is possible), where it ran on to
    max_iterations."""
    mechanism = ladder(20, tail=1)
    manifold = configuration_space(mechanism)
    assert manifold.ambient.dim >= BLOCK_THRESHOLD
    start = manifold.ambient.random_point(np.random.default_rng(28), center=home(mechanism))
    with pytest.raises(ProjectionError, match=f"after {STALL_WINDOW} iterations"):
        project(manifold, start, max_step=1e-3)
    calls = []

    def counted(points):
        calls.append(len(points))
        return manifold.constraint(points)

    _, reached = project_many(dataclasses.replace(manifold, constraint=counted), start[None], max_step=1e-3)
    assert not reached[0]
    assert len(calls) == STALL_WINDOW + 2  # the start, one per step, the final check


@pytest.mark.parametrize("name", sorted(MECHANISMS))
def test_the_random_samples_are_the_single_projections(name):
    """The random starts of sample_manifold (no walk): onto the closing map (damped), then onto Φ, as one
    projection at a time would give them, in the same order."""
    mechanism = MECHANISMS[name]()
    manifold = configuration_space(mechanism)
    start = home(mechanism)
    samples = sample_manifold(manifold, np.random.default_rng(9), start[None], random_count=12, walk_count=0)
    guesses = manifold.ambient.random_point(np.random.default_rng(9), center=start, size=12)
    closed = one_at_a_time(manifold.closing, guesses, tolerance=CLOSING_TOLERANCE, max_step=1.0,
                           max_iterations=CLOSING_ITERATIONS, damped=True)
    expected = np.concatenate([start[None], one_at_a_time(manifold, closed, max_step=1.0)])
    assert samples.shape == expected.shape
    np.testing.assert_allclose(samples, expected, rtol=0, atol=1e-9)


def test_a_map_written_for_one_point_is_sampled_one_point_at_a_time():
    """Φ(p) = [p[0]² + p[1]² − 4] takes one point: on a stack of two it returns a wrong array of the right size,
    no error. The samples are the single projections, all on the circle."""
    circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: np.array([p[0] ** 2 + p[1] ** 2 - 4.0]),
                              lambda p: np.array([[2 * p[0], 2 * p[1]]]))
    start = np.array([[2.0, 0.0]])
    samples = sample_manifold(circle, np.random.default_rng(3), start, random_count=2, walk_count=0)
    guesses = circle.ambient.random_point(np.random.default_rng(3), center=start[0], size=2)
    expected = np.concatenate([start, one_at_a_time(circle, guesses, max_step=1.0)])
    np.testing.assert_allclose(samples, expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.hypot(samples[:, 0], samples[:, 1]), 2.0, atol=1e-10)


@pytest.mark.parametrize("name", sorted(MECHANISMS) + ["ladder of 20 loops"])
def test_the_rank_decisions_of_a_stack_are_jacobian_rank_point_by_point(name):
    """The survey decides DΦ's rank at all its samples at once (manifold.jacobian_ranks): densely, and block by
    block past BLOCK_THRESHOLD, the decisions of jacobian_rank, with the singular values to rounding."""
    from manifold import jacobian_rank, jacobian_ranks

    mechanism = ladder(20, tail=1) if name.startswith("ladder") else MECHANISMS[name]()
    manifold = configuration_space(mechanism)
    points = sample_manifold(manifold, np.random.default_rng(2), home(mechanism)[None], random_count=0,
                             walk_count=5)
    for batched, point in zip(jacobian_ranks(manifold, points), points):
        single = jacobian_rank(manifold, point)
        assert (batched.rank, batched.tolerance) == pytest.approx((single.rank, single.tolerance), rel=1e-13)
        np.testing.assert_allclose(batched.singular_values, single.singular_values, rtol=0,
                                   atol=1e-13 * single.singular_values[0])


def test_a_map_written_for_one_point_is_decided_one_point_at_a_time():
    from manifold import jacobian_rank, jacobian_ranks, takes_stacks

    circle = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: np.array([p[0] ** 2 + p[1] ** 2 - 4.0]),
                              lambda p: np.array([[2 * p[0], 2 * p[1]]]))
    points = np.array([[2.0, 0.0], [0.0, 0.0], [0.0, -2.0]])  # DΦ = 0 at the origin: rank 0 there only
    assert not takes_stacks(circle, points[:2])
    assert [decision.rank for decision in jacobian_ranks(circle, points)] == [1, 0, 1]
    assert [decision.rank for decision in jacobian_ranks(circle, points)] == \
        [jacobian_rank(circle, point).rank for point in points]


def test_a_large_manifold_is_checked_for_stacks_without_its_dense_jacobian():
    from manifold import takes_stacks

    mechanism = ladder(20, tail=1)
    manifold = configuration_space(mechanism)

    def dense(point):
        raise AssertionError("the dense Jacobian was formed")

    points = sample_manifold(manifold, np.random.default_rng(2), home(mechanism)[None], random_count=0,
                             walk_count=2)
    assert takes_stacks(dataclasses.replace(manifold, constraint_jacobian=dense), points)


def test_a_space_of_dimension_zero_is_still_sampled():
    """A point of a zero-dimensional space has no coordinate: a stack of them is [n, 0], which a reshape with -1
    cannot rebuild (project_each and jacobian_ranks raised); one sample per start, random point and walk step."""
    from manifold import jacobian_ranks

    point = ImplicitManifold(AmbientSpace(()), lambda p: np.zeros(np.shape(p)[:-1] + (1,)),
                             lambda p: np.zeros(np.shape(p)[:-1] + (1, 0)))
    samples = sample_manifold(point, np.random.default_rng(0), np.zeros((1, 0)), random_count=3, walk_count=2)
    assert samples.shape == (6, 0)
    assert [decision.rank for decision in jacobian_ranks(point, samples)] == [0] * 6


def test_a_point_that_is_not_finite_is_refused_wherever_it_is_in_the_stack():
    """As project refuses one (ValueError), not ``reached = False`` after the first two points and a ValueError
    among them."""
    from manifold import jacobian_ranks, project_each

    manifold = configuration_space(MECHANISMS["five-bar"]())
    points = np.repeat(home(MECHANISMS["five-bar"]())[None], 4, axis=0)
    for row in (0, 3):
        spoiled = points.copy()
        spoiled[row, 1] = np.nan
        with pytest.raises(ValueError, match="non-finite"):
            project_each(manifold, spoiled)
        with pytest.raises(ValueError, match="non-finite"):
            jacobian_ranks(manifold, spoiled)


def test_no_seeds_are_no_points():
    """An empty list of seeds (the loci's seeds of a kind that has none) is an empty stack, as the loop over it was."""
    from manifold import project_each

    manifold = configuration_space(MECHANISMS["five-bar"]())
    projected, projected_ok = project_each(manifold, [])
    assert projected.shape == (0, manifold.ambient.point_size) and projected_ok.shape == (0,)


def test_tangent_extent_block_by_block_is_the_dense_one(monkeypatch):
    """tangent_extent's secants on a manifold handled block by block come from project_each (steps capped, NaN
    where project would raise): the same extent and secant singular values as the dense path's, on a structure
    that only flexes, a stretched four-bar and Bennett's linkage (BLOCK_THRESHOLD lowered to put them on it)."""
    from builders import bennett, flat_triangle, stretched_four_bar
    from manifold import handled_by_blocks, implicit, tangent_basis, tangent_extent

    for mechanism in (flat_triangle(), stretched_four_bar(), bennett()):
        manifold, point = configuration_space(mechanism), home(mechanism)
        basis = tangent_basis(manifold, point)[0] * manifold.ambient.tangent_scales[:, None]
        dense = tangent_extent(manifold, point, basis)
        with monkeypatch.context() as patch:
            patch.setattr(implicit, "BLOCK_THRESHOLD", 1)
            assert handled_by_blocks(manifold)
            blocked = tangent_extent(manifold, point, basis)
        assert blocked.extent == dense.extent
        np.testing.assert_allclose(blocked.singular_values, dense.singular_values, rtol=1e-9, atol=1e-12)
