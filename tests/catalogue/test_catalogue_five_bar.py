"""Five-bar: Chablat, Wenger & Angeles (1998) Fig. 1, eqs. (1)-(13), Fig. 2;
Park & Kim (1999) eq. (8), Figs. 1, 6, 13.

The Chablat, Wenger & Angeles 1998 conditions are evaluated from the joint centres of the built mechanism, independently of
the classifier: A (eq. 3b) is singular iff θ3 − θ4 = kπ, B (eq. 3c) iff θ3 − θ1 = kπ or
θ4 − θ2 = kπ. Park-Kim/Gosselin-Angeles: singular A ↔ actuator, singular B ↔ end_effector.
"""

import math
from functools import lru_cache

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.five_bar import (
    ENTRIES, WORKING_MODES, circle_intersection, five_bar, five_bar_inputs, five_bar_points,
)

(ENTRY,) = ENTRIES
DESIGN = {"base": 6.0, "proximal": 8.0, "distal": 5.0}  # Chablat, Wenger & Angeles 1998, Sec. 3.4
#: The kinds of each named configuration (the tests below say why).
EXPECTED_KINDS = {
    "fig1a_collinear": ("cspace", "end_effector"),
    "fig1b_collinear": ("cspace", "end_effector"),
    "fig1c_collinear": ("cspace", "end_effector"),
    "fig1d_collinear": ("cspace", "end_effector"),
    "fig6a_distal_aligned": ("actuator",),
    "fig6b_elbows_coincide": ("actuator",),
    "fig13_combined": ("actuator", "end_effector"),
    "fig2_working_mode_pp": (),
    "fig2_working_mode_pm": (),
    "fig2_working_mode_mp": (),
    "fig2_working_mode_mm": (),
    "eq9_distal_aligned": ("actuator",),
    "sec34_elbows_coincide": ("actuator",),
    "eq3c_left_leg_stretched": ("end_effector",),
    "eq3c_left_leg_folded": ("end_effector",),
    "eq3c_right_leg_stretched": ("end_effector",),
    "eq3c_right_leg_folded": ("end_effector",),
}
#: A configuration near each singular named one: parameter overrides (small input changes).
NEARBY = {
    "fig1a_collinear": {"theta1": 0.05, "theta2": 0.1},
    "fig1b_collinear": {"theta1": math.pi + 0.1, "theta2": math.pi + 0.02},
    "fig1c_collinear": {"theta1": 0.05, "theta2": math.pi + 0.05, "assembly": -1},
    "fig1d_collinear": {"theta1": 0.05, "theta2": math.pi + 0.05, "assembly": 1},
    "fig6a_distal_aligned": {"theta1": math.pi / 2 - 0.01},
    "fig6b_elbows_coincide": {"theta1": 0.05, "theta2": math.pi - 0.05, "assembly": 1},
    "fig13_combined": {"theta2": math.pi - math.atan2(3.0, 2.0) + 0.01},
}


def angles(mechanism):
    """Chablat, Wenger & Angeles 1998's θ1..θ4 (from AB) read off the joint centres of a built five-bar."""
    point = {joint.name: np.array(joint.point) for joint in mechanism.joints}
    heading = point["B"] - point["A"]
    reference = math.atan2(heading[1], heading[0])

    def angle(vector):
        return math.atan2(vector[1], vector[0]) - reference

    return (angle(point["C"] - point["A"]), angle(point["D"] - point["B"]),
            angle(point["P"] - point["C"]), angle(point["P"] - point["D"]))


def predicted_kinds(mechanism, tolerance=1e-9):
    """The kinds Chablat, Wenger & Angeles 1998's conditions predict: A singular → actuator, B singular → end_effector."""
    theta1, theta2, theta3, theta4 = angles(mechanism)
    kinds = set()
    if abs(math.sin(theta3 - theta4)) < tolerance:
        kinds.add("actuator")
    if abs(math.sin(theta3 - theta1)) < tolerance or abs(math.sin(theta4 - theta2)) < tolerance:
        kinds.add("end_effector")
    return tuple(sorted(kinds))


def working_mode(mechanism):
    """Signs of sin(θ3 − θ1), sin(θ4 − θ2): B's diagonal (Chablat, Wenger & Angeles 1998, eq. 3c, Sec. 3.3)."""
    theta1, theta2, theta3, theta4 = angles(mechanism)
    return "".join("+" if math.sin(value) > 0 else "-" for value in (theta3 - theta1, theta4 - theta2))


@lru_cache(maxsize=None)
def named_report(name, **parameters):
    """The classification of a named configuration (cached: several tests read the same one)."""
    return classified(ENTRY.mechanism(name, **parameters))


# ----------------------------------------------------------------------------- named configurations

@pytest.mark.parametrize("name", EXPECTED_KINDS)
def test_named_configurations_build_and_have_their_kinds(name):
    """Every named configuration builds, closes, and has the kinds the tests below establish."""
    report = named_report(name)
    assert report.dof == 2
    assert report.kinds == EXPECTED_KINDS[name]


def test_every_named_configuration_is_checked():
    assert set(ENTRY.configurations) == set(EXPECTED_KINDS)


def test_the_named_configurations_are_at_the_papers_geometry():
    """Our reading of Park & Kim's Figs. 1, 6 (the paper gives no coordinates; J1..J5 = A, C, P, D, B) is reproduced."""
    expected = {
        "fig1a_collinear": [(0, 0), (1, 0), (2, 0), (3, 0), (2, 0)],
        "fig1b_collinear": [(0, 0), (-1, 0), (0, 0), (1, 0), (2, 0)],
        "fig1c_collinear": [(0, 0), (1, 0), (0, 0), (1, 0), (2, 0)],
        "fig1d_collinear": [(0, 0), (1, 0), (2, 0), (1, 0), (2, 0)],
        "fig6a_distal_aligned": [(0, 0), (0, 1), (1, 1), (2, 1), (2, 0)],
        "fig6b_elbows_coincide": [(0, 0), (1, 0), (1, 1), (1, 0), (2, 0)],
    }
    for name, points in expected.items():
        joints = ENTRY.mechanism(name).joints
        np.testing.assert_allclose([joint.point for joint in joints], points, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("name", ["fig1a_collinear", "fig1b_collinear", "fig1c_collinear", "fig1d_collinear"])
def test_fig1_collinear_joints_are_cspace_singularities(name):
    """Park & Kim Fig. 1, eq. (8): all five joints collinear, rank ∇Φ < 3. (Chablat, Wenger & Angeles 1998's conditions call
    these both A- and B-singular; in the G-A correspondence a C-space singularity is type III.)"""
    report = named_report(name)
    assert report.cspace.rank == 2 and report.cspace.expected_rank == 3
    assert predicted_kinds(ENTRY.mechanism(name)) == ("actuator", "end_effector")


def test_fig6a_distal_links_aligned_is_a_nondegenerate_actuator_singularity():
    """Park & Kim Fig. 6a: locked, the linkage is a structure (Chablat, Wenger & Angeles 1998, eq. 9: θ3 − θ4 = π)."""
    report = named_report("fig6a_distal_aligned")
    assert report.actuator.rank == 1 and report.actuator.expected_rank == 2
    assert report.degeneracy == "nondegenerate"


@pytest.mark.parametrize("name", ["fig6b_elbows_coincide", "sec34_elbows_coincide"])
def test_coincident_elbows_are_degenerate_actuator_singularities(name):
    """Park & Kim Fig. 6b: "the middle two links are free to rotate about the two overlapping
    joints"; Chablat, Wenger & Angeles 1998, Sec. 3.4: "Each configuration where points C and D coincide leads to a
    singularity where the position of point P is not controllable" (θ3 − θ4 = 0, eq. 9)."""
    report = named_report(name)
    assert report.degeneracy == "degenerate"
    direction = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert set(direction) == {"C", "D"}


def test_fig13_is_a_combined_actuator_and_end_effector_singularity():
    """Park & Kim Fig. 13: the left leg stretched (θ3 = θ1) and the distal links aligned."""
    mechanism = ENTRY.mechanism("fig13_combined")
    assert predicted_kinds(mechanism) == ("actuator", "end_effector")
    report = named_report("fig13_combined")
    assert report.kinds == ("actuator", "end_effector")
    assert report.degeneracy == "nondegenerate"


@pytest.mark.parametrize("name", NEARBY)
def test_near_the_park_kim_singularities_is_regular(name):
    """A small change of the inputs of each Park & Kim figure (P stays within 0.2) is regular."""
    singular = {joint.name: joint.point for joint in ENTRY.mechanism(name).joints}["P"]
    mechanism = ENTRY.mechanism(name, **NEARBY[name])
    nearby = {joint.name: joint.point for joint in mechanism.joints}["P"]
    assert math.dist(singular, nearby) < 0.2
    assert classified(mechanism).kinds == ()


def test_redundant_actuation_removes_the_fig6a_singularity():
    """Park & Kim Sec. 3: driving a third joint (C) removes the actuator singularity."""
    report = classified(ENTRY.mechanism("fig6a_distal_aligned", actuated="A,C,B"))
    assert report.kinds == ()


@pytest.mark.parametrize("end_effector", ["distal_left", "distal_right"])
def test_the_link_carrying_p_does_not_change_the_kinds(end_effector):
    """P is a revolute centre of both distal links: either carries the same point."""
    report = classified(ENTRY.mechanism("fig13_combined", end_effector=end_effector))
    assert report.kinds == ("actuator", "end_effector")


# ----------------------------------------------------------------------------- Chablat, Wenger & Angeles 1998's conditions

@pytest.mark.parametrize("mode", WORKING_MODES)
def test_each_working_mode_builds_and_is_regular(mode):
    """Chablat, Wenger & Angeles 1998, Sec. 3.3, Fig. 2: the four inverse-kinematics solutions of one generic P = (3, 7)."""
    name = f"fig2_working_mode_{mode.replace('+', 'p').replace('-', 'm')}"
    mechanism = ENTRY.mechanism(name)
    assert working_mode(mechanism) == mode
    np.testing.assert_allclose({joint.name: joint.point for joint in mechanism.joints}["P"], (3.0, 7.0),
                               atol=1e-12)
    assert named_report(name).kinds == ()


def _on_actuator_locus(rng):
    """θ3 − θ4 = π: |CD| = 2 L2 (Chablat, Wenger & Angeles 1998, eq. 9, k odd), C at a random θ1."""
    while True:
        theta1 = rng.uniform(-math.pi, math.pi)
        c = (8.0 * math.cos(theta1), 8.0 * math.sin(theta1))
        try:
            d = circle_intersection(c, 10.0, (6.0, 0.0), 8.0, rng.choice([1, -1]))
        except MechanismError:
            continue
        return {"theta1": theta1, "theta2": math.atan2(d[1], d[0] - 6.0)}


def _on_leg_locus(rng, leg):
    """θ3 − θ1 = kπ (leg "left") or θ4 − θ2 = kπ ("right"): P at L1 ± L2 from the leg's base."""
    centre = 0.0 if leg == "left" else 6.0
    while True:
        reach = rng.choice([13.0, 3.0])
        angle = rng.uniform(-math.pi, math.pi)
        mode = str(rng.choice(WORKING_MODES))
        try:
            return five_bar_inputs(centre + reach * math.cos(angle), reach * math.sin(angle),
                                   working_mode=mode)
        except MechanismError:
            continue


def _generic(rng):
    while True:
        inputs = {"theta1": rng.uniform(-math.pi, math.pi), "theta2": rng.uniform(-math.pi, math.pi),
                  "assembly": int(rng.choice([1, -1]))}
        try:
            five_bar_points(**inputs)
        except MechanismError:
            continue
        return inputs


def _samples():
    rng = np.random.default_rng(4)
    samples = [("generic", _generic(rng)) for _ in range(4)]
    samples += [("theta3 - theta4 = pi", _on_actuator_locus(rng)) for _ in range(3)]
    samples += [("theta3 - theta1 = k pi", _on_leg_locus(rng, "left")) for _ in range(3)]
    samples += [("theta4 - theta2 = k pi", _on_leg_locus(rng, "right")) for _ in range(3)]
    return samples


@pytest.mark.parametrize("locus, inputs", _samples())
def test_kinds_agree_with_the_004_conditions_across_the_workspace(locus, inputs):
    """Chablat, Wenger & Angeles 1998, eqs. (9)-(13): singular exactly when θ3 − θ4 = kπ (A: actuator) or θ3 − θ1 = kπ,
    θ4 − θ2 = kπ (B: end_effector); checked at seeded samples on each locus and off them."""
    mechanism = five_bar(**inputs)
    expected = predicted_kinds(mechanism)
    assert (expected == ()) == (locus == "generic")
    assert classified(mechanism).kinds == expected


@pytest.mark.parametrize("name, step", [("eq3c_left_leg_stretched", -0.1), ("eq3c_left_leg_folded", 0.1),
                                        ("eq3c_right_leg_stretched", -0.1), ("eq3c_right_leg_folded", 0.1)])
def test_near_the_inverse_kinematic_singularities_is_regular(name, step):
    """Chablat, Wenger & Angeles 1998, eq. (3c): moving P off the circle |P − base| = L1 ± L2, in the same working mode."""
    point = {joint.name: joint.point for joint in ENTRY.mechanism(name).joints}
    base = point["A"] if "left" in name else point["B"]
    radial = np.subtract(point["P"], base)
    radial *= 1 + step / np.linalg.norm(radial)
    inputs = five_bar_inputs(*(np.add(base, radial)), working_mode="++")  # as the named configuration
    assert classified(five_bar(**inputs)).kinds == ()


def test_the_direct_kinematic_singularity_bounds_the_joint_space():
    """Chablat, Wenger & Angeles 1998, Sec. 3.1: "Such singularities occur at the boundary of the Joint space": past the
    locus θ3 − θ4 = π the loop cannot close, and just inside it both assemblies are regular."""
    values = ENTRY.values("eq9_distal_aligned")
    outcomes = {}
    for step in (0.01, -0.01):
        try:
            outcomes[step] = [five_bar(**{**values, "theta2": values["theta2"] + step, "assembly": assembly})
                              for assembly in (1, -1)]
        except MechanismError:
            outcomes[step] = None
    assert sorted(outcome is None for outcome in outcomes.values()) == [False, True]
    (inside,) = [outcome for outcome in outcomes.values() if outcome is not None]
    assert [classified(mechanism).kinds for mechanism in inside] == [(), ()]


def test_equations_3_hold_by_finite_differences():
    """Chablat, Wenger & Angeles 1998, eq. (3a): A ṗ = B θ˙ with A, B of eqs. (3b)-(3c), checked against central differences
    of the closed-form direct kinematics at seeded generic inputs (validates our angle reading)."""
    rng = np.random.default_rng(7)
    step = 1e-6
    for _ in range(5):
        inputs = _generic(rng)
        mechanism = five_bar(**inputs)
        theta1, theta2, theta3, theta4 = angles(mechanism)
        points = five_bar_points(**inputs)
        p, c, d = (np.array(points[name]) for name in "PCD")
        velocity = np.empty((2, 2))
        for column, name in enumerate(("theta1", "theta2")):
            plus = five_bar_points(**{**inputs, name: inputs[name] + step})["P"]
            minus = five_bar_points(**{**inputs, name: inputs[name] - step})["P"]
            velocity[:, column] = (np.array(plus) - np.array(minus)) / (2 * step)
        direct = np.array([p - c, p - d])
        inverse = 8.0 * 5.0 * np.diag([math.sin(theta3 - theta1), math.sin(theta4 - theta2)])
        np.testing.assert_allclose(direct @ velocity, inverse, atol=1e-6)


def test_inputs_out_of_reach_name_the_inputs():
    with pytest.raises(MechanismError, match="theta2 = 0.0: the circles do not meet"):
        five_bar(theta1=math.pi, theta2=0.0, **DESIGN)
    with pytest.raises(MechanismError, match="assembly = 0"):
        five_bar(assembly=0)
    with pytest.raises(MechanismError, match="use assembly = 0"):
        ENTRY.mechanism("fig6b_elbows_coincide", assembly=1)
    with pytest.raises(MechanismError, match="actuated"):
        five_bar(actuated="A,Q")
