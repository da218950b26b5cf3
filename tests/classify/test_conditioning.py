"""Condition numbers, characteristic length and working modes (Chablat, Caro, Wenger & Angeles 2002;
Chablat, Wenger & Angeles 1998; Park & Kim 1999 eq. 3)."""

import math

import numpy as np
import pytest

from builders import catalogue_mechanism
from classify.characteristic_length import (
    isotropic_postures, isotropy_length, isotropy_residuals, optimal_characteristic_length, three_prr_kappa,
    three_prr_leg_angles, three_prr_length,
)
from classify.conditioning import (
    condition_numbers, inverse_condition, mechanism_condition_numbers, singular_value_ratio, square_root_ratio,
)
from classify.conditioning_matrices import (
    five_bar_direct_kinematics, five_bar_matrices, hybrid_matrices, three_prr_matrices, three_prr_pose_of,
)
from classify.working_modes import (
    sign_pattern, five_bar_working_modes, three_prr_mode_pairs, three_prr_rotation_classes,
    three_prr_working_modes,
)
from manifold import project
from mechanisms import configuration_space, flip_axis, home, move_base, rehome

ROOT_TWO_R = math.sqrt(2.0) * 100.0          # L = √2 r sin γ at γ = π/2 (Chablat et al. 2002 §3.4)
FIG4A = np.array([0.0, 0.0, math.pi / 3])    # the catalogue's isotropic pose (Chablat et al. 2002 Fig. 4a)


def random_poses(rng, count, signs=(1, 1, 1)):
    """Reachable 3-PRR poses of the 2002 design, away from the singularities."""
    poses = rng.uniform([-120.0, -120.0, -math.pi], [120.0, 120.0, math.pi], (8 * count, 3))
    direct, inverse, reachable = three_prr_matrices(poses, signs)
    direct = np.where(reachable[:, None, None], direct, np.eye(3))
    inverse = np.where(reachable[:, None, None], inverse, np.eye(3))
    inverses = condition_numbers(direct, inverse, ROOT_TWO_R, (2,))
    keep = reachable & (inverses.inverse("B-1A") > 0.05)
    return poses[keep][:count]


# --------------------------------------------------------------------------- definitions

def test_definitions_on_a_diagonal_matrix():
    matrix = np.diag([4.0, 1.0])
    assert singular_value_ratio(matrix) == pytest.approx(4.0)
    assert square_root_ratio(matrix) == pytest.approx(2.0)
    assert inverse_condition(matrix) == pytest.approx(0.25)
    assert singular_value_ratio(np.diag([1.0, 0.0])) == math.inf
    assert inverse_condition(np.zeros((2, 2))) == 0.0
    assert np.isnan(inverse_condition(np.array([[np.nan, 0.0], [0.0, 1.0]])))


def test_batched_equals_single(rng=np.random.default_rng(3)):
    poses = random_poses(rng, 12)
    direct, inverse, _ = three_prr_matrices(poses, (1, -1, 1))
    batched = condition_numbers(direct, inverse, ROOT_TWO_R, (2,))
    for index in range(len(poses)):
        single = condition_numbers(direct[index], inverse[index], ROOT_TWO_R, (2,))
        for matrix, value in single.values.items():
            assert batched.values[matrix][index] == pytest.approx(float(value), rel=1e-12)


def test_jacobian_condition_does_not_depend_on_how_rows_of_F_are_written(rng=np.random.default_rng(4)):
    """κ(Ā⁻¹B) and λ are unchanged when the rows of [B A] are scaled and reordered; κ(A), κ(B) are not."""
    poses = random_poses(rng, 8)
    direct, inverse, _ = three_prr_matrices(poses, (1, 1, 1))
    scales = np.diag([3.0, 0.2, 7.0])[[2, 0, 1]]          # scale then permute the rows
    first = condition_numbers(direct, inverse, ROOT_TWO_R, (2,))
    second = condition_numbers(scales @ direct, scales @ inverse, ROOT_TWO_R, (2,))
    for matrix in ("A-1B", "B-1A", "lambda"):
        np.testing.assert_allclose(first.values[matrix], second.values[matrix], rtol=1e-10)
    assert not np.allclose(first.values["B"], second.values["B"])
    np.testing.assert_allclose(first.values["A-1B"], first.values["B-1A"], rtol=1e-12)   # K̄ = J̄⁻¹
    np.testing.assert_allclose(first.values["lambda"], first.values["A-1B"] ** 2, rtol=1e-10)


# --------------------------------------------------------------------------- Chablat, Wenger & Angeles 1998

def five_bar_samples(rng, count=40):
    inputs = rng.uniform(-math.pi, math.pi, (count, 2))
    angles, reachable = five_bar_direct_kinematics(inputs, 1)
    return angles[reachable]


def test_five_bar_kappa_A_is_eq9(rng=np.random.default_rng(5)):
    """Chablat, Wenger & Angeles 1998 eqs. (5)-(9): κ(A) = 1/|tan((θ3 − θ4)/2)|, the difference taken modulo
    π into [−π/2, π/2] (eq. 9 as printed holds where cos(θ3 − θ4) ≥ 0; elsewhere κ = |tan((θ3 − θ4)/2)|)."""
    angles = five_bar_samples(rng)
    direct, _ = five_bar_matrices(angles)
    product = direct @ np.swapaxes(direct, -1, -2)
    cosine = np.cos(angles[:, 2] - angles[:, 3])
    np.testing.assert_allclose(product, 25.0 * np.stack([np.stack([np.ones_like(cosine), cosine], -1),
                                                         np.stack([cosine, np.ones_like(cosine)], -1)], -2),
                               atol=1e-12)                                                   # eq. 5
    difference = np.angle(np.exp(2j * (angles[:, 2] - angles[:, 3]))) / 2                    # modulo π
    np.testing.assert_allclose(singular_value_ratio(direct), 1 / np.abs(np.tan(difference / 2)), rtol=1e-9)
    literal = 1 / np.abs(np.tan((angles[:, 2] - angles[:, 3]) / 2))
    near = cosine >= 0
    np.testing.assert_allclose(singular_value_ratio(direct)[near], literal[near], rtol=1e-9)
    assert not np.allclose(singular_value_ratio(direct)[~near], literal[~near])


def test_five_bar_A_isotropic_at_right_angle():
    """Eq. 9: κ(A) = 1 at |θ3 − θ4| = π/2 whatever θ1, θ2."""
    angles = np.array([[1.8, 1.3, 0.4, 0.4 - math.pi / 2], [0.2, -2.0, 2.5, 2.5 + math.pi / 2]])
    direct, _ = five_bar_matrices(angles)
    np.testing.assert_allclose(singular_value_ratio(direct), 1.0, rtol=1e-12)


def test_five_bar_kappa_B_is_eq11(rng=np.random.default_rng(6)):
    """Eqs. (10)-(13): β = |sin(θ3 − θ1)|, |sin(θ4 − θ2)|, κ(B) = √(β_max/β_min) (the paper's definition);
    σ_l/σ_s is its square."""
    angles = five_bar_samples(rng)
    _, inverse = five_bar_matrices(angles)
    beta = np.abs(np.stack([np.sin(angles[:, 2] - angles[:, 0]), np.sin(angles[:, 3] - angles[:, 1])], -1))
    expected = np.sqrt(beta.max(-1) / beta.min(-1))
    np.testing.assert_allclose(square_root_ratio(inverse), expected, rtol=1e-12)
    np.testing.assert_allclose(singular_value_ratio(inverse), expected ** 2, rtol=1e-12)


def test_five_bar_four_working_modes():
    """Chablat, Wenger & Angeles 1998 §3.3, Fig. 2: four modes at a pose, each reaching it with its signs."""
    modes = five_bar_working_modes((3.0, 7.0))
    assert [mode.label for mode in modes] == ["++", "+-", "-+", "--"]
    for mode in modes:
        assert mode.reachable
        signs, margin = sign_pattern(np.diag(mode.diagonal))
        assert tuple(signs) == mode.signs and margin > 1e-3


def test_five_bar_paper_matrices_agree_with_catalogue_mechanism():
    """κ(A⁻¹B) of the catalogue five-bar (derived, any chart) equals that of eqs. 3b-c."""
    for mode in ("pp", "pm", "mp", "mm"):
        mechanism = catalogue_mechanism("five-bar", f"fig2_working_mode_{mode}")
        point = home(mechanism)
        joints = {name: mechanism.joint(name).point for name in "ACPDB"}
        c, p, d, b = (np.array(joints[name]) for name in "CPDB")
        angles = np.array([np.arctan2(c[1], c[0]), np.arctan2(*(d - b)[::-1]), np.arctan2(*(p - c)[::-1]),
                           np.arctan2(*(p - d)[::-1])])
        direct, inverse = five_bar_matrices(angles)
        paper = condition_numbers(direct, inverse)
        derived = mechanism_condition_numbers(mechanism, point[None])
        assert derived.values["A-1B"][0] == pytest.approx(float(paper.values["A-1B"]), rel=1e-8)
        assert derived.values["lambda"][0] == pytest.approx(float(paper.values["lambda"]), rel=1e-8)


def test_hybrid_eq24_eq25_from_the_catalogue_geometry(rng=np.random.default_rng(7)):
    """Chablat, Wenger & Angeles 1998 eqs. (22a), (24), (25): AAᵀ = L2²[[1, 0, 0], [0, 1, c], [0, c, 1]],
    c = cos(θ4 − θ5), from the catalogue hybrid's joint centres in the world frame (any θ1)."""
    for theta1 in rng.uniform(-math.pi, math.pi, 3):
        mechanism = catalogue_mechanism("hybrid", theta1=float(theta1))
        joints = {name: np.array(mechanism.joint(name).point) for name in "ACPDB"}
        normal = np.array(mechanism.joint("A").axis)
        direct = np.stack([5.0 * normal, joints["P"] - joints["C"], joints["P"] - joints["D"]])
        cosine = np.dot(joints["P"] - joints["C"], joints["P"] - joints["D"]) / 25.0
        expected = 25.0 * np.array([[1, 0, 0], [0, 1, cosine], [0, cosine, 1]])
        np.testing.assert_allclose(direct @ direct.T, expected, atol=1e-10)
        difference = math.acos(np.clip(cosine, -1, 1))
        assert singular_value_ratio(direct) == pytest.approx(
            max(1 / abs(math.tan(difference / 2)), abs(math.tan(difference / 2))), rel=1e-9)


@pytest.mark.parametrize("configuration,entry", [("eq30_on_the_axis", 0), ("eq30_left_leg_stretched", 1),
                                                 ("eq30_left_leg_folded", 1), ("eq30_right_leg_stretched", 2),
                                                 ("eq30_right_leg_folded", 2)])
def test_hybrid_eq30_singularities(configuration, entry):
    """Eq. (30): B (eq. 22b) singular where d1 = 0, θ2 = θ4 + kπ or θ3 = θ5 + kπ; the catalogue's named
    configurations make exactly the expected diagonal entry vanish."""
    mechanism = catalogue_mechanism("hybrid", configuration)
    joints = {name: np.array(mechanism.joint(name).point) for name in "ACPDB"}
    along = np.array([0.0, 1.0, 0.0])
    def angle(vector):   # from AB (j) towards the plane's across direction
        across = vector - np.dot(vector, along) * along
        return math.atan2(np.linalg.norm(across) * np.sign(np.dot(across, joints["P"] - np.dot(joints["P"], along)
                                                                   * along) or 1.0), np.dot(vector, along))
    angles = np.array([angle(joints["C"] - joints["A"]), angle(joints["D"] - joints["B"]),
                       angle(joints["P"] - joints["C"]), angle(joints["P"] - joints["D"])])
    _, inverse = hybrid_matrices(angles)
    diagonal = np.abs(np.diagonal(inverse)) / 40.0
    assert diagonal[entry] < 1e-6
    assert all(diagonal[other] > 1e-3 for other in range(3) if other != entry)


def test_hybrid_conditioning_is_a_surface_of_revolution():
    """§5.1: θ1 (the turn about AB) changes neither κ(A⁻¹B) nor λ, computed in the world frame."""
    values = []
    for theta1 in (0.0, 0.9, -2.3):
        mechanism = catalogue_mechanism("hybrid", theta1=theta1)
        values.append(mechanism_condition_numbers(mechanism, home(mechanism)[None]).values)
    for other in values[1:]:
        for matrix in ("A-1B", "lambda"):
            assert other[matrix][0] == pytest.approx(values[0][matrix][0], rel=1e-9)


# --------------------------------------------------------------------------- Chablat, Caro, Wenger & Angeles 2002

def test_three_prr_isotropy_conditions_at_fig4a():
    """Eqs. (9a-f) and (10a-d) at the isotropic posture of Fig. 4a (γ = π/2) with L = √2 r."""
    direct, inverse, reachable = three_prr_matrices(FIG4A, (1, 1, 1))
    assert reachable
    legs = direct[:, :2]
    np.testing.assert_allclose(np.linalg.norm(legs, axis=1), 200.0, rtol=1e-12)                  # (10a)
    gram = legs @ legs.T
    np.testing.assert_allclose(gram[[0, 1, 0], [1, 2, 2]], gram[0, 1], rtol=1e-12)                # (10c)
    diagonal = np.diagonal(inverse)
    products = np.array([diagonal[0] * diagonal[1], diagonal[1] * diagonal[2], diagonal[0] * diagonal[2]])
    np.testing.assert_allclose(products, products[0], rtol=1e-12)                                  # (10d)
    assert np.abs(isotropy_residuals(direct, inverse, ROOT_TWO_R)).max() < 1e-12                   # (9a-f)
    assert float(isotropy_length(direct)) == pytest.approx(ROOT_TWO_R, rel=1e-12)                  # §3.4
    np.testing.assert_allclose(three_prr_leg_angles(FIG4A, (1, 1, 1)), math.pi / 2, atol=1e-12)
    numbers = condition_numbers(direct, inverse, ROOT_TWO_R, (2,))
    for matrix in ("A", "B", "A-1B", "B-1A", "lambda"):
        assert float(numbers.values[matrix]) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("gamma", [math.pi / 2, 2.2, 1.0])
def test_three_prr_length_is_root_two_r_sin_gamma(gamma):
    """§3.4: at an isotropic posture L = √(−k₁k₂ / l₁ᵀl₂) = √2 r sin γ. The posture is P = O with the
    platform turned so that every γᵢ = γ (the legs then form an equilateral triangle, eqs. 10a-d)."""
    from scipy.optimize import brentq

    def gap(phi):
        return float(three_prr_leg_angles([0.0, 0.0, phi], (1, 1, 1))[0]) - gamma
    grid = np.linspace(-math.pi, math.pi, 721)
    values = np.array([gap(phi) for phi in grid])
    index = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
    phi = brentq(gap, grid[index], grid[index + 1], xtol=1e-14)
    direct, inverse, _ = three_prr_matrices([0.0, 0.0, phi], (1, 1, 1))
    length = float(isotropy_length(direct))
    assert length == pytest.approx(three_prr_length(100.0, gamma), rel=1e-9)
    assert np.abs(isotropy_residuals(direct, inverse, length)).max() < 1e-8


def test_optimised_length_is_isotropic_and_obeys_the_closed_form():
    """§3.2: minimising κ(K̄) over L and the posture reaches κ = 1, and there L = √2 r sin γ (§3.4)."""
    result = optimal_characteristic_length(lambda length, pose: three_prr_kappa(length, pose, (1, 1, 1)),
                                           120.0, [10.0, 5.0, 1.0], restarts=0)
    assert result.kappa == pytest.approx(1.0, abs=1e-7)
    gamma = three_prr_leg_angles(result.posture, (1, 1, 1))
    np.testing.assert_allclose(gamma, gamma[0], atol=1e-5)
    assert result.value == pytest.approx(three_prr_length(100.0, gamma[0]), rel=1e-5)


def test_isotropic_postures_at_root_two_r_include_fig4a():
    found = isotropic_postures(lambda pose: three_prr_kappa(ROOT_TWO_R, pose, (1, 1, 1)), [[10.0, 5.0, 1.0]])
    assert len(found) == 1
    posture, margin = found[0]
    np.testing.assert_allclose(posture, FIG4A, atol=1e-6)
    assert 0 <= margin < 1e-6


def test_three_prr_eight_working_modes_and_pairs():
    """§3.5, Fig. 5: eight modes at a pose; pairs 1-5, 2-6, 3-7, 4-8 of opposite signs; 2, 3, 4 (and 6, 7, 8) by
    turns of 120°. B's diagonal has the same magnitudes in all eight (only its signs change, so κ(B) is the
    same, §3.6)."""
    modes = three_prr_working_modes([20.0, -10.0, 1.1])
    assert [mode.label for mode in modes] == [str(number) for number in range(1, 9)]
    assert all(mode.reachable for mode in modes)
    assert len({mode.signs for mode in modes}) == 8
    for mode in modes:
        assert tuple(np.sign(mode.diagonal).astype(int)) == mode.signs
    assert three_prr_mode_pairs() == [(1, 5), (2, 6), (3, 7), (4, 8)]
    assert three_prr_rotation_classes() == [[1], [2, 3, 4], [6, 7, 8], [5]]
    by_label = {mode.label: mode for mode in modes}
    for first, second in three_prr_mode_pairs():
        assert by_label[str(first)].signs == tuple(-sign for sign in by_label[str(second)].signs)
    for mode in modes:
        np.testing.assert_allclose(np.abs(mode.diagonal), np.abs(modes[0].diagonal), rtol=1e-12)


def test_three_prr_paper_matrices_match_catalogue_mechanism():
    """The mechanism's own J̄ (any chart) has the κ of eq. 4's K̄ = B⁻¹Ā; λ = κ²; the catalogue pose is read back."""
    parameters = {"x": 30.0, "y": -20.0, "phi": 1.3, "working_mode": 2}
    mechanism = catalogue_mechanism("3-prr", **parameters)
    pose, signs = three_prr_pose_of(mechanism, home(mechanism))
    np.testing.assert_allclose(pose, [30.0, -20.0, 1.3], atol=1e-9)
    assert tuple(signs) == (-1, 1, 1)
    direct, inverse, _ = three_prr_matrices(pose, signs)
    paper = condition_numbers(direct, inverse, ROOT_TWO_R, (2,))
    derived = mechanism_condition_numbers(mechanism, home(mechanism)[None], length=ROOT_TWO_R)
    assert derived.values["A-1B"][0] == pytest.approx(float(paper.values["B-1A"]), rel=1e-8)
    assert derived.values["lambda"][0] == pytest.approx(float(paper.values["lambda"]), rel=1e-8)


def test_conditioning_invariant_under_joint_zero_axis_sign_and_base_frame():
    """Property: κ(J̄) and λ do not change with another home (joint zeros), a reversed axis or a moved base."""
    mechanism = catalogue_mechanism("3-prr", x=30.0, y=-20.0, phi=1.3, working_mode=2)
    reference = mechanism_condition_numbers(mechanism, home(mechanism)[None], length=ROOT_TWO_R).values
    turn = 0.7
    base = np.array([[math.cos(turn), -math.sin(turn), 5.0], [math.sin(turn), math.cos(turn), -3.0], [0, 0, 1]])
    for variant in (flip_axis(mechanism, "rail1"), flip_axis(mechanism, "B2"), move_base(mechanism, base)):
        values = mechanism_condition_numbers(variant, home(variant)[None], length=ROOT_TWO_R).values
        for matrix in ("A-1B", "lambda"):
            assert values[matrix][0] == pytest.approx(reference[matrix][0], rel=1e-8)
    # another home: the mechanism drawn at a nearby configuration p, its joint zeros there, classified at p
    manifold = configuration_space(mechanism)
    step = 0.05 * np.random.default_rng(8).standard_normal(manifold.ambient.dim)
    point = project(manifold, manifold.ambient.retract(home(mechanism), step))
    assert not np.allclose(point, home(mechanism), atol=1e-3)
    at_point = mechanism_condition_numbers(mechanism, point[None], length=ROOT_TWO_R).values
    rehomed = rehome(mechanism, point)
    values = mechanism_condition_numbers(rehomed, home(rehomed)[None], length=ROOT_TWO_R).values
    for matrix in ("A-1B", "lambda"):
        assert values[matrix][0] == pytest.approx(at_point[matrix][0], rel=1e-8)
        assert values[matrix][0] != pytest.approx(reference[matrix][0], rel=1e-4)  # p is another configuration
