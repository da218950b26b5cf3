"""Fixes of the conditioning audit: the five-bar's unequal legs on the paper's maps, a canonical characteristic
length, and condition numbers of the derived relation that do not depend on the unit of length.

Chablat, Wenger & Angeles 1998 (eqs. 3b-c: the five-bar, legs L1, L2 and L3, L4); Chablat, Caro, Wenger &
Angeles 2002 (§3.3-3.4, eqs. 9a-f: the 3-PRR's isotropy conditions and characteristic length).
"""

import io
import json
import math

import numpy as np
import pytest

from classify.cli import main


def run(*arguments):
    out = io.StringIO()
    status = main(list(arguments), out=out)
    return status, out.getvalue()


# ------------------------------------------------------------------------------------------------ five-bar, D1

def _five_bar_reach(points, base, left, right):
    """Independent reach test: P within the annuli of both legs (|Lp − Ld| ≤ ‖P − pivot‖ ≤ Lp + Ld)."""
    reach = np.ones(points.shape[:-1], dtype=bool)
    for pivot, (proximal, distal) in (((0.0, 0.0), left), ((base, 0.0), right)):
        distance = np.linalg.norm(points - np.array(pivot), axis=-1)
        reach &= (distance >= abs(proximal - distal)) & (distance <= proximal + distal)
    return reach


def test_five_bar_named_configuration_with_unequal_legs_is_mapped_with_its_own_right_leg(tmp_path):
    """1998 eqs. 3b-c with L3 ≠ L1: ``fig13_combined`` (L0 = √13, L1 = L2 = L4 = 1, L3 = 2) maps the points both
    of *its* legs reach, and 1/κ(K̄) there is eq. 3b-c's with L3 = 2 (not the symmetric design L3 = L1)."""
    path = tmp_path / "map.npz"
    status, out = run("conditioning", "five-bar", "--configuration", "fig13_combined", "--mode", "+-",
                      "--grid", "X=-1:4:26", "Y=-3:3:31", "--out", str(path))
    assert status == 0
    values = np.load(path)
    points = np.stack(np.meshgrid(values["x"], values["y"], indexing="ij"), axis=-1)
    base = math.sqrt(13.0)
    expected = _five_bar_reach(points, base, (1.0, 1.0), (2.0, 1.0))
    boundary = _five_bar_reach(points, base, (1.0, 1.0 - 1e-9), (2.0, 1.0 - 1e-9)) != _five_bar_reach(
        points, base, (1.0, 1.0 + 1e-9), (2.0, 1.0 + 1e-9))   # points on an annulus' edge: either way
    reachable = values["reachable_+-"]
    assert np.array_equal(reachable[~boundary], expected[~boundary])
    assert json.loads(out)["modes"][0]["unreachable_share"] == pytest.approx(1.0 - reachable.mean(), abs=1e-15)
    # one reachable point by hand: θ's from the legs' geometry, K̄ = B⁻¹A (eqs. 3b-c)
    index = tuple(np.argwhere(reachable & ~boundary)[0])
    point = points[index]
    inverse_kappa = values["inverse_kappa_B-1A_+-"][index]
    hand = []
    for pivot, proximal, distal, sign in (((0.0, 0.0), 1.0, 1.0, 1), ((base, 0.0), 2.0, 1.0, -1)):
        offset = point - np.array(pivot)
        distance = np.linalg.norm(offset)
        first = math.atan2(offset[1], offset[0]) - sign * math.acos(
            (proximal ** 2 + distance ** 2 - distal ** 2) / (2 * proximal * distance))
        elbow = np.array(pivot) + proximal * np.array([math.cos(first), math.sin(first)])
        crank, coupler = elbow - np.array(pivot), point - elbow
        hand.append(coupler / (crank[0] * coupler[1] - crank[1] * coupler[0]))   # row (p − c)ᵀ / (L1 L2 sin(θ3 − θ1))
    singular_values = np.linalg.svd(np.array(hand), compute_uv=False)
    assert inverse_kappa == pytest.approx(singular_values[-1] / singular_values[0], rel=1e-12)


# ------------------------------------------------------------------------------------------------ 3-PRR, D2

#: a 3-PRR on which γ = π/2 is out of reach (r² + l² < R²/4), but other isotropic postures exist
NARROW = {"platform_radius": 50.0, "base_radius": 300.0, "leg_length": 110.0}


def _three_prr_parameters(design, scale=1.0):
    """``--param`` words of a 3-PRR design posed at P = O, φ = 1.2807 (lengths multiplied by `scale`)."""
    values = {**{name: value * scale for name, value in design.items()}, "x": 0.0, "y": 0.0,
              "phi": 1.2806988363794756}
    return [word for name, value in values.items() for word in ("--param", f"{name}={value!r}")]


@pytest.mark.parametrize("scale", [1.0, 1e-3])
def test_three_prr_length_is_the_largest_isotropic_one_when_gamma_right_is_out_of_reach(scale):
    """2002 §3.4: L = √2 r sin γ at an isotropic posture; the paper's √2 r (γ = π/2, Fig. 4a) is out of reach on
    this design, so the length reported must be that of an isotropic posture which exists, the one with γ
    closest to π/2 (the largest L), and scale with the unit of length."""
    from classify.characteristic_length import isotropy_residuals, three_prr_kappa, three_prr_leg_angles
    from classify.conditioning_matrices import three_prr_matrices

    status, out = run("conditioning", "3-prr", *_three_prr_parameters(NARROW, scale))
    assert status == 0
    found = json.loads(out)["characteristic_length"]
    radius, base, leg = (NARROW[name] * scale for name in ("platform_radius", "base_radius", "leg_length"))
    length, posture = found["value"], np.array(found["posture"])
    assert length < math.sqrt(2.0) * radius * (1 - 1e-3)          # not the unreachable closed form at γ = π/2
    signs = (1, 1, 1)
    assert three_prr_kappa(length, posture, signs, "B-1A", radius, base, leg) == pytest.approx(1.0, abs=1e-12)
    gamma = three_prr_leg_angles(posture, signs, radius, base, leg)
    assert length == pytest.approx(math.sqrt(2.0) * radius * math.sin(gamma[0]), rel=1e-12)
    # no isotropic posture (P = O, eqs. 10a-d) of any orientation has a larger √2 r sin γ
    orientations = np.linspace(-math.pi, math.pi, 7201)
    poses = np.stack([0 * orientations, 0 * orientations, orientations], axis=-1)
    direct, inverse, reachable = three_prr_matrices(poses, signs, radius, base, leg)
    direct, inverse = direct[reachable], inverse[reachable]
    angles = three_prr_leg_angles(poses[reachable], signs, radius, base, leg)
    lengths = math.sqrt(2.0) * radius * np.sin(angles[:, 0])
    isotropic = np.max(np.abs(isotropy_residuals(direct, inverse, np.abs(lengths))), axis=(1, 2))
    assert np.count_nonzero(isotropic < 1e-9) > 100
    assert np.max(lengths[isotropic < 1e-9]) <= length * (1 + 1e-12)
    assert length / scale == pytest.approx(49.204414234551, rel=1e-9)   # the same in m as in mm


def test_three_prr_length_of_the_papers_design_is_root_two_r():
    """2002 §3.4 (Fig. 4a): where γ = π/2 is reachable the largest isotropic L is the paper's √2 r."""
    from classify.characteristic_length import three_prr_characteristic_length

    found = three_prr_characteristic_length(100.0, 200.0, 200.0)
    assert found.value == pytest.approx(math.sqrt(2.0) * 100.0, rel=1e-12)
    assert found.kappa == pytest.approx(1.0, abs=1e-12)


# ------------------------------------------------------------------------------------------------ any file, D3

def test_length_auto_does_not_depend_on_axis_sign_nor_unit():
    """2002 §3.4: κ(J̄) = 1 along the family L = √2 r sin γ; ``--length auto`` on the 3-PRR as a general
    mechanism returns the family's largest L, √2 r, whatever the chart, an axis sign or the unit."""
    from classify.characteristic_length import mechanism_optimal_length
    from mechanisms import catalogue, configuration, flip_axis, scale_lengths

    mechanism = catalogue.entry("3-prr").assemble({"x": 30.0, "y": -20.0, "phi": 1.3, "working_mode": 2})
    variants = {"original": (mechanism, 1.0), "rail 1 flipped": (flip_axis(mechanism, "rail1"), 1.0),
                "in metres": (scale_lengths(mechanism, 1e-3), 1e-3)}
    for name, (variant, scale) in variants.items():
        found, isotropic = mechanism_optimal_length(variant, configuration(variant, {}).point, restarts=0,
                                                    max_evaluations=250)
        assert found.value / scale == pytest.approx(math.sqrt(2.0) * 100.0, rel=1e-7), name
        assert found.kappa - 1.0 <= 1e-6 and isotropic and isotropic[0][1] <= 1e-6, name


# ------------------------------------------------------------------------------------------------ derived A, B: D4

@pytest.mark.parametrize("name, parameters, length", [
    ("3-prr", {"x": 30.0, "y": -20.0, "phi": 1.3, "working_mode": 2}, 141.42135623730951),   # prismatic inputs
    ("five-bar", {}, None),                                      # revolute inputs (L: the characteristic length)
])
def test_derived_kappa_of_a_and_b_do_not_depend_on_the_unit_of_length(name, parameters, length):
    """κ(A), κ(B) of the derived relation are dimensionless: the same in mm and in m (with L scaled), and their
    product is κ(J̄) (rows [B A] orthonormal in coordinates of one unit, 2002 eq. 7's homogenisation)."""
    from classify.conditioning import mechanism_condition_numbers
    from mechanisms import catalogue, configuration, scale_lengths

    mechanism = catalogue.entry(name).assemble(parameters)
    scaled = scale_lengths(mechanism, 1e-3)
    original = mechanism_condition_numbers(mechanism, configuration(mechanism, {}).point[None], length)
    metres = mechanism_condition_numbers(scaled, configuration(scaled, {}).point[None],
                                         None if length is None else length * 1e-3)
    for matrix in ("A", "B", "B-1A"):
        assert metres.values[matrix][0] == pytest.approx(original.values[matrix][0], rel=1e-9), matrix
    assert original.values["A"][0] * original.values["B"][0] == pytest.approx(original.values["B-1A"][0],
                                                                             rel=1e-9)
    assert original.values["A"][0] > 1 + 1e-3   # the derived A is not orthogonal (it was, to 1e-6, in mm)
