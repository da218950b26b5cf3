"""AmbientSpace: retraction and its inverse, batches, random points."""

import numpy as np
import pytest

from manifold import AmbientSpace, rotation_exp, rotation_log

SPACES = [("S1",), ("R", "S1"), ("SO3",), ("S1", "R", "SO3", "SO3", "R")]


@pytest.mark.parametrize("factors", SPACES)
def test_inverse_retract_undoes_retract(factors):
    rng = np.random.default_rng(0)
    space = AmbientSpace(factors)
    for _ in range(10):
        point = space.random_point(rng)
        tangent = rng.uniform(-1.0, 1.0, space.dim)  # rotation steps below π
        moved = space.retract(point, tangent)
        np.testing.assert_allclose(space.inverse_retract(point, moved), tangent, atol=1e-12)


@pytest.mark.parametrize("factors", SPACES)
def test_batched_retract_equals_repeated_single_calls(factors):
    rng = np.random.default_rng(1)
    space = AmbientSpace(factors)
    points = space.random_point(rng, size=6).reshape(2, 3, -1)
    tangents = rng.standard_normal((2, 3, space.dim))
    batched = space.retract(points, tangents)
    inverse = space.inverse_retract(points, batched)
    for i in range(2):
        for j in range(3):
            np.testing.assert_allclose(batched[i, j], space.retract(points[i, j], tangents[i, j]))
            np.testing.assert_allclose(inverse[i, j], space.inverse_retract(points[i, j], batched[i, j]))


def test_rotations_stay_orthonormal_and_charts_have_no_gimbal_lock():
    """At the gimbal-lock attitudes of XYZ (pitch ±90°) and ZYZ (middle angle 0) Euler angles
    the recentred chart is as regular as anywhere: its derivative at 0 is the identity."""
    space = AmbientSpace(("SO3",))
    for rotation_vector in ([0, np.pi / 2, 0], [0, -np.pi / 2, 0], [0, 0, 0.7], [0, 0, 0]):
        point = rotation_exp(np.array(rotation_vector, dtype=float)).ravel()
        step = 1e-6
        columns = [space.inverse_retract(point, space.retract(point, step * e)) / step for e in np.eye(3)]
        np.testing.assert_allclose(np.array(columns), np.eye(3), atol=1e-9)
        matrix = space.retract(point, [0.3, -0.2, 0.1]).reshape(3, 3)
        np.testing.assert_allclose(matrix @ matrix.T, np.eye(3), atol=1e-12)


def test_rotation_log_inverts_exp():
    rng = np.random.default_rng(2)
    vectors = rng.uniform(-1.5, 1.5, (20, 3))
    np.testing.assert_allclose(rotation_log(rotation_exp(vectors)), vectors, atol=1e-12)


def test_circle_differences_are_wrapped():
    space = AmbientSpace(("S1",))
    assert space.inverse_retract([np.pi - 0.1], [-np.pi + 0.1])[0] == pytest.approx(0.2)


def test_unknown_factor_and_wrong_scales_are_refused():
    with pytest.raises(ValueError, match="factor"):
        AmbientSpace(("T2",))
    with pytest.raises(ValueError, match="scales"):
        AmbientSpace(("R",), scales=(1.0, 2.0))


@pytest.mark.parametrize("scale", [0.0, -1.0, float("nan"), float("inf")])
def test_a_scale_must_be_finite_and_positive(scale):
    """A zero scale erased its coordinates from every rank decision (the line x = 0 had rank 0)."""
    with pytest.raises(ValueError, match="finite positive"):
        AmbientSpace(("R", "R"), scales=(scale, 1.0))


@pytest.mark.parametrize("factors", SPACES)
def test_bracket_is_the_second_order_term_of_composed_charts(factors):
    """``p ⊕ hu ⊕ hw = p ⊕ (hu + hw + h² B(u, w) + O(h³))`` (Baker–Campbell–Hausdorff on SO(3)): the remainder
    after B falls like h³, and without B (on an SO3 factor) like h²."""
    rng = np.random.default_rng(5)
    space = AmbientSpace(factors)
    point = space.random_point(rng)
    first, second = rng.standard_normal((2, space.dim))
    bracket = space.bracket(first[:, None], second[:, None])[:, 0, 0]

    def remainder(size, with_bracket=True):
        composed = space.inverse_retract(point, space.retract(space.retract(point, size * first), size * second))
        return np.linalg.norm(composed - size * (first + second) - with_bracket * size ** 2 * bracket)

    assert remainder(1e-2) / remainder(5e-3) == pytest.approx(8.0, rel=0.05) or remainder(1e-2) < 1e-14
    if "SO3" in factors:
        assert remainder(1e-2, False) / remainder(5e-3, False) == pytest.approx(4.0, rel=0.05)
    np.testing.assert_array_equal(space.bracket(first[:, None], first[:, None])[:, 0, 0], 0.0)
