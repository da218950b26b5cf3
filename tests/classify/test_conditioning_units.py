"""Conditioning in any unit of length: the same mechanism drawn in micrometres, millimetres or kilometres has the
same condition numbers, the same characteristic length (scaled with the unit) and the same isotropic postures.

Chablat, Caro, Wenger & Angeles 2002 (eq. 7: L makes Ā homogeneous; §3.3-3.4: the isotropic postures and the
characteristic length of the 3-PRR, L = √2 r sin γ); the project's rule that no reported number depends on the
unit of length (``mechanisms.scale_lengths``).
"""

import io
import json
import math

import numpy as np
import pytest

from classify.cli import main
from mechanisms import catalogue, configuration, from_displacements, scale_lengths, to_displacements

FACTORS = (1e-6, 1e-3, 1e3, 1e6)
ROOT_TWO_R = math.sqrt(2.0) * 100.0


def _at_home(mechanism):
    return configuration(mechanism, {}).point[None]


@pytest.mark.parametrize("name", ["3-prr", "eclipse", "five-bar"])
def test_condition_numbers_do_not_depend_on_the_unit_of_length(name):
    """κ(A), κ(B) (derived relation), κ(J̄), κ(K̄) and λ₁/λₙ at home, L the characteristic length, are the same
    in every unit. The Eclipse actuates a revolute joint (the carriage on its track) and a prismatic one (the
    slider on its column) per leg: J̄ had columns of two units and its κ grew like the unit (17.8 in the
    catalogue's unit, 1.7e7 in micrometres, 1.7e6 in kilometres); the actuated angles' rates are now multiplied
    by L as in the derived relation, and κ(A) κ(B) = κ(J̄) holds there as on the others."""
    from classify.conditioning import mechanism_condition_numbers

    mechanism = catalogue.entry(name).mechanism()
    reference = mechanism_condition_numbers(mechanism, _at_home(mechanism)).values
    assert reference["A"][0] * reference["B"][0] == pytest.approx(reference["A-1B"][0], rel=1e-9)
    assert reference["lambda"][0] == pytest.approx(reference["A-1B"][0] ** 2, rel=1e-9)
    for factor in FACTORS:
        scaled = scale_lengths(mechanism, factor)
        values = mechanism_condition_numbers(scaled, _at_home(scaled)).values
        for matrix, value in reference.items():
            assert np.isfinite(values[matrix][0]), (factor, matrix)
            assert values[matrix][0] == pytest.approx(value[0], rel=1e-9), (factor, matrix)


def test_map_of_a_mixed_actuation_does_not_depend_on_the_unit_of_length():
    """The maps' 1/κ(J̄) and λₙ/λ₁ (:func:`classify.isoconditioning.mechanism_map`) of the Eclipse, in mm and in
    m: λ was the batched classification's, whose actuator metric weighs the rates as given (1/λ = 3e-9 in
    thousandths of the unit, 3e-3 in the unit); it is now (1/κ(J̄))², J̄ on rates of length."""
    from classify.isoconditioning import mechanism_map

    mechanism = catalogue.entry("eclipse").mechanism()
    maps = [mechanism_map(variant, _at_home(variant), [True], [[0.0]], ["t"])
            for variant in (mechanism, scale_lengths(mechanism, 1e-3), scale_lengths(mechanism, 1e3))]
    for matrix in ("A-1B", "lambda"):
        for conditioning_map in maps[1:]:
            assert conditioning_map.inverse[matrix][0] == pytest.approx(maps[0].inverse[matrix][0], rel=1e-9)
    assert maps[0].inverse["lambda"][0] == pytest.approx(maps[0].inverse["A-1B"][0] ** 2, rel=1e-12)


def test_small_actuator_weights_in_a_small_unit_do_not_unmake_the_actuation():
    """Whether the actuators parametrise M is decided on the unit actuator rows (dimensionless: neither the
    weights nor the unit decide). The Eclipse in micrometres with its slides weighted 1e-12 had raw actuator rows
    1e-13 apart and its J̄ was called undefined (every κ null); in the catalogue's unit with the same weights
    it is regular, and κ is the same in both units."""
    import dataclasses

    from classify.conditioning import mechanism_condition_numbers
    from mechanisms import Mechanism

    original = catalogue.entry("eclipse").mechanism()
    joints = [dataclasses.replace(joint, weight=1e-12) if joint.actuated and joint.type == "P" else joint
              for joint in original.joints]
    weighted = Mechanism(original.name, original.space, joints, original.ground, original.end_effector)
    small = scale_lengths(weighted, 1e-6)
    reference = mechanism_condition_numbers(weighted, _at_home(weighted)).values["A-1B"][0]
    assert np.isfinite(reference)
    assert mechanism_condition_numbers(small, _at_home(small)).values["A-1B"][0] == pytest.approx(reference,
                                                                                                 rel=1e-9)


def test_length_auto_of_the_three_prr_in_any_unit_of_length():
    """``--length auto`` on the catalogue 3-PRR as a general mechanism (2002 §3.4: the largest isotropic L,
    √2 r): the same L (scaled) and one isotropic posture in every unit. In kilometres-scale units it refused
    the file (J̄ evaluated at L = 1, a factor 2e8 from the mechanism's size); at ×1e3 it counted the isotropic
    posture twice (two minima 3e-8 apart in units of L, but 3e-5 apart in the file's unit, compared with an
    absolute 1e-6); L differed by 7e-8 from unit to unit (a bounded search on log L stops within √ε ‖log L‖)."""
    from classify.characteristic_length import mechanism_optimal_length

    mechanism = catalogue.entry("3-prr").mechanism()
    results = {}
    for factor in (1e-3, 1.0, 1e3, 1e6):
        scaled = scale_lengths(mechanism, factor)
        found, isotropic = mechanism_optimal_length(scaled, _at_home(scaled)[0], restarts=0, max_evaluations=250)
        results[factor] = found.value / factor
        assert len(isotropic) == 1, factor
        assert found.kappa - 1.0 <= 1e-9 and isotropic[0][1] <= 1e-9, factor
    for factor, value in results.items():
        assert value == pytest.approx(results[1.0], rel=1e-12), factor
        assert value == pytest.approx(ROOT_TWO_R, rel=1e-10), factor


def test_general_conditioning_of_a_three_prr_file_in_kilometres(tmp_path):
    """``conditioning FILE`` on a 3-PRR drawn 1e6 times larger (a characteristic length of 2e8): it exited with
    "Expected a length scale within a factor 1e+06 … got 1" (whether an output is an orientation was tried at
    L = 1 and 2); now it reports the κ's of the file in the catalogue's unit, L given in the file's unit."""
    from mechanisms.io import save

    mechanism = catalogue.entry("3-prr").assemble({"x": 30.0, "y": -20.0, "phi": 1.3, "working_mode": 2})
    results = []
    for factor in (1.0, 1e6):
        path = tmp_path / f"three_prr_{factor:g}.yaml"
        save(scale_lengths(mechanism, factor), str(path))
        out = io.StringIO()
        assert main(["conditioning", str(path), "--length", repr(ROOT_TWO_R * factor)], out=out) == 0
        results.append(json.loads(out.getvalue()))
    assert results[1]["characteristic_length"]["value"] == pytest.approx(ROOT_TWO_R * 1e6, rel=1e-12)
    for matrix, value in results[0]["kappa"].items():
        assert results[1]["kappa"][matrix] == pytest.approx(value, rel=1e-9), matrix


def _displacements(mechanism, flat):
    """The joint displacements of a flat tuple (one per coordinate, as ``CharacteristicLength.posture``)."""
    home = to_displacements(mechanism, configuration(mechanism, {}).point)
    result, start = {}, 0
    for name, value in home.items():
        size = np.size(value)
        result[name] = flat[start] if np.ndim(value) == 0 else list(flat[start:start + size])
        start += size
    return result


def test_optimal_length_of_a_mixed_actuation_is_that_of_its_condition_numbers():
    """κ(J̄) minimised over L and the posture on the Eclipse (revolute and prismatic joints actuated): at
    L = ρ L₀ the actuated angles' rates scale with L as the output's rotations, J̄(L) = D(ρ) J̄(L₀) C(ρ); the κ
    reported is :func:`mechanism_condition_numbers`' at the L and posture reported, and both are the same in
    thousandths and in thousands of the unit (L scaled; a smooth minimum over L: L itself to √ε)."""
    from classify.characteristic_length import mechanism_optimal_length
    from classify.conditioning import mechanism_condition_numbers

    mechanism = catalogue.entry("eclipse").mechanism()
    found = {}
    for factor in (1e-3, 1e3):
        scaled = scale_lengths(mechanism, factor)
        result, _ = mechanism_optimal_length(scaled, _at_home(scaled)[0], restarts=0, max_evaluations=60)
        point = from_displacements(scaled, _displacements(scaled, result.posture))
        kappa = mechanism_condition_numbers(scaled, point[None], result.value).values["A-1B"][0]
        assert result.kappa == pytest.approx(kappa, rel=1e-9)
        found[factor] = result
    assert found[1e3].kappa == pytest.approx(found[1e-3].kappa, rel=1e-9)
    assert found[1e3].value / 1e3 == pytest.approx(found[1e-3].value / 1e-3, rel=1e-7)


def test_length_window_when_length_also_divides_actuated_rates():
    """J̄(L') = D(ρ) J̄(L) C(ρ), D = diag(ρ on rotation rows, 1), C = diag(1/ρ on angular actuated rates, 1):
    κ changes by up to max(ρ, 1/ρ)² (not max(ρ, 1/ρ) as with D alone), and ``length_window(…, exponent=2)``
    excludes only lengths where no posture can be isotropic."""
    from classify.characteristic_length import length_window
    from classify.conditioning import singular_value_ratio

    rng = np.random.default_rng(3)
    rows, columns = np.array([True, False, False]), np.array([True, True, False])

    def kappa(jacobian, ratio):
        return float(singular_value_ratio(np.where(rows, ratio, 1.0)[:, None] * jacobian
                                          * np.where(columns, 1.0 / ratio, 1.0)[None, :]))

    exceeded = False
    for _ in range(200):
        jacobian = rng.standard_normal((3, 3))
        value = kappa(jacobian, 1.0)
        for ratio in (0.5, 0.9, 1.1, 2.0):
            assert kappa(jacobian, ratio) >= value / max(ratio, 1 / ratio) ** 2 * (1 - 1e-12)
            exceeded |= kappa(jacobian, ratio) < value / max(ratio, 1 / ratio) * (1 - 1e-9)
    assert exceeded   # the window of exponent 1 would exclude lengths it must not
    low, high = length_window(10.0, 4.0, 0.0, exponent=2)
    assert (low, high) == pytest.approx((5.0, 20.0), rel=1e-15)


def test_isotropic_postures_of_the_three_prr_in_any_unit_of_length():
    """The 3-PRR's isotropic postures at L = √2 r (2002 Fig. 4a), searched on (x/l, y/l, φ): the same postures
    (scaled) and as many in m, mm and μm. On raw (x, y, φ) the search's first steps (and the comparison of two
    postures, relative to their size + 1) were in the file's unit."""
    from classify.characteristic_length import isotropic_postures, three_prr_kappa

    starts = np.array([[10.0, 5.0, 1.0], [0.0, 0.0, math.pi / 3], [0.0, 0.0, -math.pi / 3], [40.0, -30.0, 0.2]])
    found = {}
    for factor in (1e-3, 1.0, 1e3):
        def kappa(posture, factor=factor):
            return three_prr_kappa(ROOT_TWO_R * factor, posture, (1, 1, 1), "B-1A", 100.0 * factor,
                                   200.0 * factor, 200.0 * factor)
        found[factor] = isotropic_postures(kappa, starts * [factor, factor, 1.0],
                                           scales=(200.0 * factor, 200.0 * factor, 1.0))
    assert found[1.0]
    for factor, postures in found.items():
        assert len(postures) == len(found[1.0]), factor
        for (posture, margin), (expected, _) in zip(postures, found[1.0]):
            assert margin <= 1e-6
            np.testing.assert_allclose(posture / [factor, factor, 1.0], expected, rtol=0, atol=1e-5)
