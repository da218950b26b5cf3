"""Implicit manifolds: projection, rank decisions, local rank, continuation."""

import numpy as np
import pytest

from manifold import (
    AmbientSpace, ImplicitManifold, ProjectionError, constraint_curvature, continue_curve,
    local_rank, numerical_rank, project, sample_manifold, tangent_basis,
)


def circle(radius=2.0):
    """x² + y² = r² in ℝ²."""
    return ImplicitManifold(
        AmbientSpace(("R", "R")),
        lambda p: np.array([p[0] ** 2 + p[1] ** 2 - radius ** 2]),
        lambda p: np.array([[2 * p[0], 2 * p[1]]]),
        lambda p: np.array([2 * np.eye(2)]),
    )


def crossing_lines():
    """xy = 0 in ℝ²: two lines crossing at the origin (a singular point of the level set)."""
    return ImplicitManifold(
        AmbientSpace(("R", "R")),
        lambda p: np.array([p[0] * p[1]]),
        lambda p: np.array([[p[1], p[0]]]),
        lambda p: np.array([[[0.0, 1.0], [1.0, 0.0]]]),
    )


def test_projection_lands_on_the_manifold():
    point = project(circle(), [3.0, 1.0])
    assert np.hypot(*point) == pytest.approx(2.0, abs=1e-12)


def test_projection_failure_is_reported():
    level = ImplicitManifold(AmbientSpace(("R",)), lambda p: np.array([p[0] ** 2 + 1.0]),
                             lambda p: np.array([[2 * p[0]]]))
    with pytest.raises(ProjectionError, match="did not converge"):
        project(level, [0.5])


def test_damped_projection_reaches_a_zero_gauss_newton_overshoots():
    """Φ = arctan x: Newton's steps from x = 1.5 overshoot and grow; Levenberg-Marquardt keeps only steps that
    lower |Φ| (Nocedal & Wright §10.3) and reaches the zero."""
    level = ImplicitManifold(AmbientSpace(("R",)), lambda p: np.arctan(p[:1]),
                             lambda p: np.array([[1 / (1 + p[0] ** 2)]]))
    with pytest.raises(ProjectionError, match="did not converge: residual 1.57 "):  # x: 1.5, -1.7, 2.3, -5.1, 32, ...
        project(level, [1.5], max_iterations=5)
    assert abs(project(level, [1.5], damped=True)[0]) < 1e-12
    assert project(level, [1.5], damped=True, max_step=0.1)[0] == pytest.approx(0.0, abs=1e-12)


def test_damped_projection_gives_up_at_a_critical_point_that_is_no_zero():
    """Φ = x² + 1 has no zero and |Φ|² its minimum at 0: no step lowers |Φ| there, and the search stops."""
    level = ImplicitManifold(AmbientSpace(("R",)), lambda p: np.array([p[0] ** 2 + 1.0]),
                             lambda p: np.array([[2 * p[0]]]))
    with pytest.raises(ProjectionError, match="did not converge: residual 1 "):
        project(level, [0.5], damped=True, max_iterations=1000)


def test_rank_decision_reports_its_margin():
    decision = numerical_rank(np.diag([3.0, 1.0, 1e-9]))
    assert decision.rank == 2
    assert decision.margin == (1.0, 1e-9)
    assert decision.tolerance == pytest.approx(3e-6)
    scaled = numerical_rank(np.diag([1e-9]), scale=1.0)
    assert scaled.rank == 0 and numerical_rank(np.diag([1e-9])).rank == 1


def test_rank_cut_does_not_depend_on_units():
    matrix = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0 + 1e-3]])
    assert numerical_rank(matrix).rank == numerical_rank(1e6 * matrix).rank == 2


def test_local_rank_sees_the_regular_neighbours_of_a_singular_point():
    rng = np.random.default_rng(0)
    lines = crossing_lines()
    origin = np.zeros(2)
    assert numerical_rank(lines.constraint_jacobian(origin)).rank == 0
    near = local_rank(lines, origin, rng)
    assert near.rank == 1 and near.dimension == 1
    regular = local_rank(circle(), np.array([2.0, 0.0]), rng)
    assert regular.rank == 1 and regular.dimension == 1


def test_tangent_basis_is_orthonormal_and_in_the_kernel():
    basis, decision = tangent_basis(circle(), np.array([np.sqrt(2), np.sqrt(2)]))
    assert decision.rank == 1 and basis.shape == (2, 1)
    np.testing.assert_allclose(basis.T @ basis, np.eye(1), atol=1e-12)
    np.testing.assert_allclose(circle().constraint_jacobian(np.array([np.sqrt(2), np.sqrt(2)])) @ basis, 0,
                               atol=1e-12)


def test_constraint_curvature_is_the_circle_curvature():
    """A unit-speed curve on a circle of radius r has acceleration of length 1/r toward the centre."""
    radius = 2.0
    point = np.array([radius, 0.0])
    basis = np.array([[0.0], [1.0]])
    acceleration = constraint_curvature(circle(radius), point, basis)[:, 0, 0]
    np.testing.assert_allclose(acceleration, [-1.0 / radius, 0.0], atol=1e-12)


def test_continuation_follows_a_curve_and_stops_at_an_isolated_point():
    certificate = continue_curve(circle(), np.array([2.0, 0.0]), np.array([0.0, 1.0]), length=0.5, step=0.05)
    assert certificate.reached and certificate.distance >= 0.5
    assert certificate.largest_residual < 1e-10
    isolated = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: np.array([p[0] ** 2 + p[1] ** 2]),
                                lambda p: np.array([[2 * p[0], 2 * p[1]]]))
    assert not continue_curve(isolated, np.zeros(2), np.array([1.0, 0.0]), length=0.1).reached


def test_sampling_reaches_points_of_the_manifold():
    rng = np.random.default_rng(3)
    samples = sample_manifold(circle(), rng, np.array([[2.0, 0.0]]), random_count=5, walk_count=5)
    np.testing.assert_allclose(np.hypot(samples[:, 0], samples[:, 1]), 2.0, atol=1e-10)
    assert len(samples) > 5
