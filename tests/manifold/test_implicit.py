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


# ------------------------------------------------------------------------------------------------ an audit

def test_an_iterate_that_leaves_the_domain_ends_in_a_projection_error():
    """Φ = eˣ − 1 from x = −10: Newton's first step overflows (and √x − 1 from 9 steps to x < 0, NaN); the
    next least-squares solve raised LinAlgError, which the callers of project do not catch."""
    overflow = ImplicitManifold(AmbientSpace(("R",)), lambda p: np.exp(p[:1]) - 1.0,
                                lambda p: np.exp(p[:1])[None])
    with np.errstate(over="ignore"), pytest.raises(ProjectionError, match="not finite"):
        project(overflow, [-10.0])
    root = ImplicitManifold(AmbientSpace(("R",)), lambda p: np.sqrt(p[:1]) - 1.0,
                            lambda p: (0.5 / np.sqrt(p[:1]))[None])
    with np.errstate(invalid="ignore"), pytest.raises(ProjectionError, match="not finite"):
        project(root, [9.0])
    with np.errstate(invalid="ignore"):
        samples = sample_manifold(root, np.random.default_rng(3), [[1.0]], random_count=4, walk_count=8)
    assert np.allclose(samples, 1.0)


def scaled_curve(length):
    """Φ(θ, x) = x/L − 2 sin 3θ − 0.5 on S¹ × ℝ: one curve, its length x in units where L is `length`."""
    return ImplicitManifold(AmbientSpace(("S1", "R"), scales=(1.0, length)),
                            lambda p: np.array([p[1] / length - 2 * np.sin(3 * p[0]) - 0.5]),
                            lambda p: np.array([[-6 * np.cos(3 * p[0]), 1.0 / length]]))


def test_a_capped_projection_and_the_samples_do_not_depend_on_the_unit_of_length():
    """The cap is on the dimensionless step ‖v / s‖; it was on ‖v‖, radians and lengths added, so that in mm
    an angle's step was uncapped where in m it was capped (and sample_manifold's samples differed)."""
    results = []
    for length in (1.0, 1000.0):
        manifold = scaled_curve(length)
        point = project(manifold, [0.3, 5.0 * length], max_step=0.5)
        samples = sample_manifold(manifold, np.random.default_rng(3), [[np.arcsin(-0.25) / 3, 0.0]],
                                  random_count=6, walk_count=6)
        results.append((point / [1.0, length], samples / [1.0, length]))
    np.testing.assert_allclose(results[0][0], results[1][0], atol=1e-9)
    np.testing.assert_allclose(results[0][1], results[1][1], atol=1e-9)


@pytest.mark.parametrize("small", [1e-4, 1e-7, 1e-8])
def test_damped_projection_converges_on_an_ill_conditioned_linear_map(small):
    """Φ = diag(1, ε)(p − 1): Gauss-Newton's one step; the damping's floor 1e-12 σ₁² froze the ε direction."""
    matrix = np.diag([1.0, small])
    level = ImplicitManifold(AmbientSpace(("R", "R")), lambda p: matrix @ (p - 1.0), lambda p: matrix)
    point = project(level, [0.0, 0.0], damped=True)
    assert np.linalg.norm(matrix @ (point - 1.0)) <= 1e-12


def test_continuation_does_not_certify_a_jump_from_an_isolated_point_to_a_nearby_branch():
    """(x² + y²)(x − y − 0.012) = 0: the origin is isolated, a line passes 0.0085 away. The first corrector
    landed on the line and the walk along it was certified as a curve through the origin (a false
    'degenerate' for the second-order test); the midpoint of that first secant is far from M."""
    level = ImplicitManifold(
        AmbientSpace(("R", "R")),
        lambda p: np.array([(p[0] ** 2 + p[1] ** 2) * (p[0] - p[1] - 0.012)]),
        lambda p: np.array([[2 * p[0] * (p[0] - p[1] - 0.012) + p[0] ** 2 + p[1] ** 2,
                             2 * p[1] * (p[0] - p[1] - 0.012) - p[0] ** 2 - p[1] ** 2]]))
    for direction in ([1.0, 0.0], [1.0, 0.5], [1.0, 1.0], [0.5, 1.0]):
        assert not continue_curve(level, np.zeros(2), np.array(direction), length=0.1, step=0.01).reached
    certificate = continue_curve(circle(), np.array([2.0, 0.0]), np.array([0.0, 1.0]), length=0.5, step=0.05)
    assert certificate.reached
