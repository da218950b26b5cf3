"""A given relation F's Gosselin–Angeles verdict does not depend on the unit of length, nor sees a kink near by.

Gosselin & Angeles (1990) write F(θ, x) = 0 in the units of its variables: the columns of ``[B A]`` (eq. 3)
carry the units of F's rows over those of θ and x (a leg length cᵢ, a position x, an angle r). An audit found
the paper's own relations decided on raw rows: the slider-crank at its fold sin θ = l/R (eq. 14, relation
eq. 12) kind II in metres but regular in millimetres; the planar 3-RRR at its regular home (eq. 44) kinds
I, II, III in millimetres; the Gough–Stewart (eqs. 75, 81) not differentiable in millimetres and kind II in
micrometres. The probe that sizes the rows and looks for kinks moved each variable by 10⁻²·(1 + |value|),
more than a millimetre-sized mechanism, and took a leg of length 10⁻³ (F = c − ‖w‖, smooth there) for the
kink at ‖w‖ = 0. The columns are now taken in the variables' own scales (each relation declares its
variables' kinds: :func:`classify.gosselin_angeles.variable_scales`) and a kink must persist down to a fine step.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from builders import shared_mechanism
from classify import compare, joint_output_model, kinds_of_matrices
from classify.comparison import REASONS
from classify.gosselin_angeles_examples import RELATIONS, eq12_relation, eq75_relation
from mechanisms import catalogue, home, scale_lengths

FACTORS = (1e-6, 1e-3, 1e6)
#: (entry, parameters, relation, outputs): the slider-crank at its fold sin θ = l/R (eq. 14), the others at home
CASES = [
    ("slider-crank", {"crank": 2.7, "coupler": 1.3, "theta": math.asin(1.3 / 2.7)}, "eq12", ("slide",)),
    ("planar-3rrr", {}, "eq44", None),
    ("gough-stewart", {}, "eq75", None),
    ("gough-stewart", {}, "eq81", None),
]


def _row(mechanism, relation_name, outputs):
    """The comparison row at home with the paper's relation (eq. 12 on its '+' branch: at the exact fold
    x − R cos θ = l cos ψ is 0 to rounding, so :func:`slider_crank_branch` may pick either sign)."""
    mechanism = shared_mechanism(mechanism)
    point = home(mechanism)
    if relation_name == "eq12":
        relation, coordinates = eq12_relation(mechanism, branch=1)
    else:
        relation, coordinates = RELATIONS[mechanism.name][relation_name](mechanism, point)
    model = mechanism if outputs is None else joint_output_model(mechanism, list(outputs))
    return compare(model, [point], relation=relation, coordinates=coordinates,
                   rng=np.random.default_rng(0)).rows[0]


def _assert_same_verdict(first, second):
    a, b = first.gosselin_angeles, second.gosselin_angeles
    assert (a.defined, a.undefined, a.kinds, a.rank_A, a.rank_B) == (b.defined, b.undefined, b.kinds, b.rank_A,
                                                                     b.rank_B)
    assert (first.agree, first.reason) == (second.agree, second.reason)
    for decision in ("input_decision", "output_decision", "relation_decision"):
        one, other = getattr(a, decision), getattr(b, decision)
        assert (one is None) == (other is None)
        if one is not None:
            np.testing.assert_allclose(one.singular_values, other.singular_values, rtol=1e-6, atol=1e-9)


#: every unit for the planar cases; for the Gough–Stewart (a survey per unit, ~2 s) the unit each relation was
#: wrong in (eq. 75 undefined at ×1e-3, eq. 81 kind II at ×1e-6) and one larger
UNIT_CASES = [(*case, factor) for case in CASES[:2] for factor in FACTORS] + [
    (*CASES[2], 1e-3), (*CASES[3], 1e-6), (*CASES[3], 1e6)]


@pytest.mark.parametrize("name, parameters, relation_name, outputs, factor", UNIT_CASES)
def test_a_change_of_length_unit_changes_no_verdict_of_a_given_relation(name, parameters, relation_name, outputs,
                                                                         factor):
    mechanism = catalogue.entry(name).mechanism(**parameters)
    first = _row(mechanism, relation_name, outputs)
    second = _row(scale_lengths(mechanism, factor), relation_name, outputs)
    _assert_same_verdict(first, second)


def test_the_papers_verdicts_in_the_catalogues_unit():
    """Eq. 12 at the fold is kind II (eq. 14) and agrees; eqs. 44, 75 and 81 at the regular homes are regular."""
    expected = {"eq12": ("II",), "eq44": (), "eq75": (), "eq81": ()}
    for name, parameters, relation_name, outputs in CASES:
        row = _row(catalogue.entry(name).mechanism(**parameters), relation_name, outputs)
        assert row.gosselin_angeles.kinds == expected[relation_name] and row.agree, (relation_name, row.note)


def _short_leg(length):
    """The Gough–Stewart with leg 1 of the given length (platform pose turned by (0.2, −0.1, 0.3))."""
    entry = catalogue.entry("gough-stewart")
    default = entry.mechanism()
    base = np.array(default.joint("U1").point)
    platform = np.array(default.joint("S1").point) - np.array([0.0, 0.0, 1.0])
    turn = (0.2, -0.1, 0.3)
    x = base - Rotation.from_rotvec(turn).apply(platform) + np.array([0.0, 0.0, length])
    return entry.mechanism(x=x[0], y=x[1], z=x[2], rotation_x=turn[0], rotation_y=turn[1], rotation_z=turn[2])


@pytest.mark.parametrize("length", (1e-3, 1e-2, 3e-2))
def test_a_short_leg_is_no_kink_of_eq75(length):
    """F₁ = c₁ − ‖w₁‖ (eq. 75) is smooth wherever ‖w₁‖ = c₁ > 0: regular, as Park–Kim and the derived G–A
    say (the kink at c₁ = 0, eq. 84, is 10⁻³ away: within the old probe's step)."""
    mechanism = shared_mechanism(_short_leg(length))
    relation, coordinates = eq75_relation(mechanism)
    row = compare(mechanism, [home(mechanism)], relation=relation, coordinates=coordinates,
                  rng=np.random.default_rng(0)).rows[0]
    assert row.park_kim.kinds == () and row.gosselin_angeles.defined, row.gosselin_angeles.detail
    assert row.gosselin_angeles.kinds == () and row.agree


def test_a_short_leg_in_millimetres():
    mechanism = scale_lengths(_short_leg(1e-3), 1e-3)
    row = _row(mechanism, "eq75", None)
    assert row.gosselin_angeles.defined and row.gosselin_angeles.kinds == () and row.agree


def test_a_change_of_a_variables_unit_changes_no_decision():
    """Column j of [B A] over c, its variable's scale times c (a unit c times smaller): the same decisions."""
    rng = np.random.default_rng(3)
    b, a = rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    a[:, 2] = 1e-3 * a[:, 0]  # nearly singular A, so that the column scales matter
    scales = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 1.0])
    first = kinds_of_matrices(b, a, variable_scales=scales)
    units = np.array([1.0, 1e3, 1.0, 1e-3, 1e-3, 1.0])
    second = kinds_of_matrices(b / units[:3], a / units[3:], variable_scales=scales * units)
    for decision in ("input_decision", "output_decision", "relation_decision"):
        np.testing.assert_allclose(getattr(first, decision).singular_values,
                                   getattr(second, decision).singular_values, rtol=1e-12)


def test_the_reason_names_both_causes():
    """A kink of F (A and B finite) is ``not_differentiable`` too: the reason says so."""
    text = REASONS["not_differentiable"]
    assert "kink" in text and "not finite" in text


def test_every_paper_relation_declares_its_units():
    """Each of the paper's relations says which of its variables are lengths (the slider-crank's x, the
    Gough–Stewart's leg lengths and position, the 3-RRR's x, y), so σ is the characteristic length there and 1
    for an angle; a relation without units is taken in the caller's units."""
    from classify.gosselin_angeles import InputOutputRelation, variable_scales

    expected = {"slider-crank": ("angle", "length"), "watt-six-bar": ("angle", "angle"),
                "planar-3rrr": ("angle",) * 3 + ("length", "length", "angle"),
                "spherical-3rrr": ("angle",) * 6, "gough-stewart": ("length",) * 9 + ("angle",) * 3}
    for name, relations in RELATIONS.items():
        mechanism = catalogue.entry(name).mechanism()
        for label, build in relations.items():
            relation, _ = build(mechanism, home(mechanism))
            assert relation.units == expected[name], (name, label)
            scales = variable_scales(relation, mechanism.characteristic_length)
            assert scales.tolist() == [mechanism.characteristic_length if unit == "length" else 1.0
                                       for unit in expected[name]]
    bare = InputOutputRelation("F", ("t",), ("x",), lambda theta, x: (np.eye(1), np.eye(1)))
    assert variable_scales(bare, 7.0) is None
    with pytest.raises(ValueError, match="units must be 2 of 'length' or 'angle'"):
        InputOutputRelation("F", ("t",), ("x",), lambda theta, x: (np.eye(1), np.eye(1)), units=("metre", "angle"))
