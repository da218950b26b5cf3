"""The Gosselin–Angeles matrices (1990, eqs. 1–5): relations from SymPy and
callables, Taylor tests of their derivatives, the normalised rank decisions, and the derived
matrices (the annihilator of {(Dπ T u, J u)}) with their independence of the description."""

import numpy as np
import pytest
import sympy
from scipy.stats import ortho_group

from classify import (
    derived_gosselin_angeles, gosselin_angeles, joint_output_model, kinds_of_matrices, model_of,
    relation_from_callables, relation_from_sympy, sample_configurations,
)
from manifold import tangent_basis
from mechanisms import flip_axis, home, kinematics_of, move_base, rehome
from mechanisms.catalogue import entry

THETA, X = sympy.symbols("theta x")
R, L = sympy.symbols("R l", positive=True)


def eq9(branch, crank=1.0, coupler=2.0):
    """G–A eq. 9: x = R cos θ ± l √(1 − r² sin² θ), as F(θ, x) = 0."""
    return relation_from_sympy(
        [THETA], [X], equations=[X - R * sympy.cos(THETA) - branch * L * sympy.sqrt(1 - (R / L) ** 2 * sympy.sin(THETA) ** 2)],
        parameters={R: crank, L: coupler}, name=f"eq9{'+' if branch > 0 else '-'}")


def test_taylor_of_a_two_dimensional_relation():
    """F(θ + hδ, x + hε) − F(θ, x) − h(Bδ + Aε) = O(h²): the symbolic Jacobians are F's derivatives."""
    t1, t2, x1, x2 = sympy.symbols("t1 t2 x1 x2")
    relation = relation_from_sympy([t1, t2], [x1, x2], equations=[
        x1 ** 2 + sympy.sin(t1) * x2 - 1, sympy.exp(t2) * x1 - sympy.cos(x2 * t1)])
    rng = np.random.default_rng(0)
    theta, x, delta, epsilon = rng.normal(size=(4, 2))
    b, a = relation.jacobians(theta, x)
    errors = []
    for h in (1e-3, 1e-4):
        change = relation.residual(theta + h * delta, x + h * epsilon) - relation.residual(theta, x)
        errors.append(np.linalg.norm(change - h * (b @ delta + a @ epsilon)))
    assert errors[1] < errors[0] / 50  # second order: ×100 smaller for h ÷ 10


def test_eq9_kinds_at_the_dead_centre_and_regular():
    """θ = 0 is kind I for both branches (eq. 12: B = R sin θ (…) = 0); θ = 0.3 is regular."""
    for branch in (1, -1):
        relation = eq9(branch)
        x0 = 1.0 + branch * 2.0
        assert gosselin_angeles(relation, [0.0], [x0]).kinds == ("I",)
        theta = 0.3
        x = np.cos(theta) + branch * 2.0 * np.sqrt(1 - 0.25 * np.sin(theta) ** 2)
        result = gosselin_angeles(relation, [theta], [x])
        assert result.kinds == () and result.rank_A == result.rank_B == 1


def test_eq9_is_not_differentiable_at_its_branch_point():
    """With R > l, at sin θ = l/R the root of eq. 9 vanishes and ∂F/∂θ is infinite: undefined."""
    relation = eq9(1, crank=2.0, coupler=1.0)
    theta = np.arcsin(0.5)
    result = gosselin_angeles(relation, [theta], [2.0 * np.cos(theta)])
    assert not result.defined and result.undefined == "not_finite" and result.kinds == ()


def test_a_callable_relation_equals_the_sympy_one():
    relation = eq9(1)
    b_function = lambda theta, x: relation.jacobians(theta, x)[0]  # noqa: E731
    a_function = lambda theta, x: relation.jacobians(theta, x)[1]  # noqa: E731
    copy = relation_from_callables(["theta"], ["x"], b_function, a_function, residual=relation.residual)
    for theta in (0.0, 0.4, 2.0):
        x = np.cos(theta) + 2.0 * np.sqrt(1 - 0.25 * np.sin(theta) ** 2)
        first, second = gosselin_angeles(relation, [theta], [x]), gosselin_angeles(copy, [theta], [x])
        assert first.kinds == second.kinds
        np.testing.assert_allclose(first.output_decision.singular_values, second.output_decision.singular_values)


def test_unknown_symbols_and_bad_shapes_are_named():
    with pytest.raises(ValueError, match=r"\['l'\]"):
        relation_from_sympy([THETA], [X], equations=[X - L * sympy.cos(THETA)])
    with pytest.raises(ValueError, match="not both"):
        relation_from_sympy([THETA], [X], equations=[X], input_jacobian=[[1]], output_jacobian=[[1]])
    with pytest.raises(ValueError, match="output_jacobian"):
        relation_from_sympy([THETA], [X], input_jacobian=[[1]], output_jacobian=[[1, 2]])
    with pytest.raises(ValueError, match="2 inputs but 1 outputs"):
        relation_from_callables(["a", "b"], ["x"], np.eye, np.eye)


def test_kinds_do_not_depend_on_how_the_rows_of_f_are_scaled_or_combined():
    """det A = 0, det B = 0 and the normalised singular values are unchanged by [B A] → L [B A]."""
    rng = np.random.default_rng(1)
    for _ in range(20):
        b, a = rng.normal(size=(2, 3, 3))
        a[:, 2] = a[:, 0] - 2 * a[:, 1]  # det A = 0
        combination = rng.normal(size=(3, 3)) * np.exp(rng.uniform(-4, 4, size=(3, 1)))
        first, second = kinds_of_matrices(b, a), kinds_of_matrices(combination @ b, combination @ a)
        assert first.kinds == second.kinds == ("II",)
        np.testing.assert_allclose(first.output_decision.singular_values,
                                   second.output_decision.singular_values, atol=1e-9)
        np.testing.assert_allclose(first.input_decision.singular_values,
                                   second.input_decision.singular_values, atol=1e-9)


def test_a_degenerate_differential_is_kind_three():
    result = kinds_of_matrices([[0.0, 1.0], [0.0, 2.0]], [[1.0, 0.0], [2.0, 0.0]])
    assert result.relation_decision.rank == 1 and result.kinds == ("I", "II", "III")


def _derived(model, point, basis=None):
    basis = tangent_basis(model.manifold, point)[0] if basis is None else basis
    return derived_gosselin_angeles(model, point, basis)


def five_bar_points(count=4):
    mechanism = entry("five-bar").mechanism()
    model = model_of(mechanism)
    points = np.concatenate([home(mechanism)[None],
                             sample_configurations(model, count, np.random.default_rng(2))])
    return mechanism, model, points


def test_derived_matrices_annihilate_the_velocities():
    """Rows of [B A] annihilate (Dπ T u, J u) for every u, in the mechanism's coordinates."""
    mechanism, model, points = five_bar_points()
    for point in points:
        basis = tangent_basis(model.manifold, point)[0]
        result = _derived(model, point, basis)
        velocities = np.vstack([model.actuators @ basis, model.end_effector_jacobian(point) @ basis])
        rows = np.hstack([result.input_jacobian, result.output_jacobian])
        assert np.linalg.norm(rows @ velocities) < 1e-10 * np.linalg.norm(rows) * np.linalg.norm(velocities)


def test_derived_matrices_do_not_depend_on_the_tangent_basis():
    """Property: T → T Q (Q orthogonal, random) leaves V, so the ranks and normalised singular values."""
    rng = np.random.default_rng(3)
    for name, outputs in (("five-bar", None), ("planar-3rrr", None), ("slider-crank", ["slide"])):
        mechanism = entry(name).mechanism()
        model = model_of(mechanism) if outputs is None else joint_output_model(mechanism, outputs)
        for point in np.concatenate([home(mechanism)[None], sample_configurations(model, 3, rng)]):
            basis = tangent_basis(model.manifold, point)[0]
            rotation = ortho_group.rvs(basis.shape[1], random_state=rng) if basis.shape[1] > 1 else -np.eye(1)
            first, second = _derived(model, point, basis), _derived(model, point, basis @ rotation)
            assert (first.rank_A, first.rank_B) == (second.rank_A, second.rank_B)
            np.testing.assert_allclose(first.output_decision.singular_values,
                                       second.output_decision.singular_values, atol=1e-9)
            np.testing.assert_allclose(first.input_decision.singular_values,
                                       second.input_decision.singular_values, atol=1e-9)


@pytest.mark.parametrize("configuration", [None, "fig6a_distal_aligned", "fig6b_elbows_coincide"])
def test_derived_ranks_do_not_depend_on_joint_zeros_axis_signs_or_base_frame(configuration):
    """Property: another home, a reversed axis, a moved base give the same ranks of A and B."""
    mechanism = entry("five-bar").mechanism(configuration)
    rng = np.random.default_rng(4)
    model = model_of(mechanism)
    points = np.concatenate([home(mechanism)[None], sample_configurations(model, 2, rng)])
    for point in points:
        reference = _derived(model, point)
        ranks = (reference.rank_A, reference.rank_B)
        moved = rehome(mechanism, point)
        assert ranks == _ranks(moved, home(moved))
        for joint in mechanism.joints:
            flipped = flip_axis(mechanism, joint.name)
            mirrored = point.copy()
            for part in kinematics_of(mechanism).point_parts[joint.name]:
                mirrored[part] *= -1.0
            assert ranks == _ranks(flipped, mirrored)
        angle = rng.uniform(-np.pi, np.pi)
        motion = np.array([[np.cos(angle), -np.sin(angle), rng.normal()],
                           [np.sin(angle), np.cos(angle), rng.normal()], [0.0, 0.0, 1.0]])
        assert ranks == _ranks(move_base(mechanism, motion), point)


def _ranks(mechanism, point):
    result = _derived(model_of(mechanism), point)
    return result.rank_A, result.rank_B
