"""Three-dof hybrid manipulator: Chablat, Wenger & Angeles (1998) Fig. 6,
eqs. (14)-(30).

The Chablat, Wenger & Angeles 1998 conditions are evaluated from the joint centres of the built mechanism, independently of
the classifier: A (eq. 22a) is singular iff θ4 − θ5 = kπ (eqs. 24-25): actuator; B (eq. 22b) iff
d1 = 0, θ2 = θ4 + kπ or θ3 = θ5 + kπ (eq. 30): end_effector.
"""

import math
from functools import lru_cache

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.five_bar import WORKING_MODES, circle_intersection, five_bar_inputs
from mechanisms.catalogue.hybrid import ENTRIES, hybrid, hybrid_points

(ENTRY,) = ENTRIES
PROXIMAL, DISTAL = 8.0, 5.0  # L1, L2 of Chablat, Wenger & Angeles 1998, Sec. 3.4 (L0 = 6)
EXPECTED_KINDS = {
    "regular": (),
    "eq30_on_the_axis": ("end_effector",),
    "eq30_left_leg_stretched": ("end_effector",),
    "eq30_left_leg_folded": ("end_effector",),
    "eq30_right_leg_stretched": ("end_effector",),
    "eq30_right_leg_folded": ("end_effector",),
    "eq25_distal_aligned": ("actuator",),
    "eq25_elbows_coincide": ("actuator",),
}


def plane_coordinates(mechanism):
    """Joint centres in the five-bar's plane: u along AB (the Y axis), v across it, and P."""
    point = {joint.name: np.array(joint.point) for joint in mechanism.joints}
    normal = np.array(next(joint.axis for joint in mechanism.joints if joint.name == "A"))
    along = (point["B"] - point["A"]) / np.linalg.norm(point["B"] - point["A"])
    across = np.cross(normal / np.linalg.norm(normal), along)
    return {name: np.array([(value - point["A"]) @ along, (value - point["A"]) @ across])
            for name, value in point.items() if name != "base"}


def angles(mechanism):
    """Chablat, Wenger & Angeles 1998's θ2..θ5 of the hybrid (from AB, in the five-bar's plane) and d1 (eq. 27)."""
    plane = plane_coordinates(mechanism)

    def angle(vector):
        return math.atan2(vector[1], vector[0])

    return (angle(plane["C"] - plane["A"]), angle(plane["D"] - plane["B"]), angle(plane["P"] - plane["C"]),
            angle(plane["P"] - plane["D"]), plane["P"][1])


def predicted_kinds(mechanism, tolerance=1e-9):
    """The kinds eqs. (24)-(25) and (30) predict."""
    theta2, theta3, theta4, theta5, distance = angles(mechanism)
    kinds = set()
    if abs(math.sin(theta4 - theta5)) < tolerance:
        kinds.add("actuator")
    if (abs(distance) < tolerance * PROXIMAL or abs(math.sin(theta2 - theta4)) < tolerance
            or abs(math.sin(theta3 - theta5)) < tolerance):
        kinds.add("end_effector")
    return tuple(sorted(kinds))


@lru_cache(maxsize=None)
def named_report(name):
    return classified(ENTRY.mechanism(name))


@pytest.mark.parametrize("name", EXPECTED_KINDS)
def test_named_configurations_build_and_have_the_004_kinds(name):
    """Chablat, Wenger & Angeles 1998, eqs. (25), (30): each named configuration builds, is where its name says (the
    conditions hold, checked from the joint centres), and the classifier finds those kinds."""
    mechanism = ENTRY.mechanism(name)
    assert predicted_kinds(mechanism) == EXPECTED_KINDS[name]
    report = named_report(name)
    assert report.dof == 3
    assert report.kinds == EXPECTED_KINDS[name]


def test_every_named_configuration_is_checked():
    assert set(ENTRY.configurations) == set(EXPECTED_KINDS)


def test_on_the_axis_the_base_revolute_does_not_move_p():
    """Chablat, Wenger & Angeles 1998, eq. (27), Sec. 5.2: "postures whereby point P lies on the Y axis are singular": the lost
    end-effector direction is the turn of the base revolute."""
    report = named_report("eq30_on_the_axis")
    assert report.end_effector.rank == 2 and report.end_effector.expected_rank == 3
    assert "base" in report.to_dict()["end_effector"]["kernel"][0]


def test_distal_links_aligned_is_a_nondegenerate_actuator_singularity():
    """Chablat, Wenger & Angeles 1998, eq. (25): κ(A) → ∞ at θ4 − θ5 = π; with the inputs locked the manipulator is a structure."""
    report = named_report("eq25_distal_aligned")
    assert report.actuator.rank == 2 and report.actuator.expected_rank == 3
    assert report.degeneracy == "nondegenerate"


def test_coincident_elbows_are_a_degenerate_actuator_singularity():
    """Chablat, Wenger & Angeles 1998, eq. (25) with k = 0 (θ4 = θ5: C = D, as in Sec. 3.4): P turns about the elbows."""
    report = named_report("eq25_elbows_coincide")
    assert report.degeneracy == "degenerate"
    assert set(report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]) == {"C", "D"}


def _nearby(name):
    """A configuration near a singular named one: P moved by 0.1 off the locus, in the same working
    mode (the inverse kinematics is regular off eq. 30's loci), at the same θ1."""
    values = ENTRY.values(name)
    plane = plane_coordinates(ENTRY.mechanism(name))
    theta2, theta3, theta4, theta5, _ = angles(ENTRY.mechanism(name))
    mode = "".join("+" if math.sin(value) >= 0 else "-" for value in (theta4 - theta2, theta5 - theta3))
    if name.startswith("eq30") and name != "eq30_on_the_axis":
        base = plane["A"] if "left" in name else plane["B"]
        radial = plane["P"] - base
        direction = -radial / np.linalg.norm(radial) * np.sign(np.linalg.norm(radial) - PROXIMAL)  # inward
    else:
        direction = np.array([0.6, 0.8])
    inputs = five_bar_inputs(*(plane["P"] + 0.1 * direction), working_mode=mode)
    return {**values, "theta2": inputs["theta1"], "theta3": inputs["theta2"], "assembly": inputs["assembly"]}


@pytest.mark.parametrize("name", [name for name, kinds in EXPECTED_KINDS.items() if kinds])
def test_near_each_singularity_is_regular(name):
    """A posture with P at 0.1 from each singular named configuration is regular."""
    mechanism = hybrid(**_nearby(name))
    singular = {joint.name: joint.point for joint in ENTRY.mechanism(name).joints}["P"]
    nearby = {joint.name: joint.point for joint in mechanism.joints}["P"]
    assert math.dist(singular, nearby) == pytest.approx(0.1)
    assert predicted_kinds(mechanism) == ()
    assert classified(mechanism).kinds == ()


def _samples():
    """Seeded postures: generic ones and ones on each locus of eqs. (25), (30), at random θ1."""
    rng = np.random.default_rng(5)
    samples = []

    def add(locus, inputs):
        samples.append((locus, {"theta1": float(rng.uniform(-math.pi, math.pi)), **inputs}))

    def posture(x, y):
        inputs = five_bar_inputs(x, y, working_mode=str(rng.choice(WORKING_MODES)))
        return {"theta2": inputs["theta1"], "theta3": inputs["theta2"], "assembly": inputs["assembly"]}

    while len(samples) < 3:
        try:
            add("generic", posture(*rng.uniform(-12.0, 12.0, size=2)))
        except MechanismError:
            continue
    for locus in ("d1 = 0", "theta2 = theta4 + k pi", "theta3 = theta5 + k pi", "theta4 - theta5 = pi"):
        count = len(samples)
        while len(samples) < count + 2:
            try:
                if locus == "d1 = 0":
                    add(locus, posture(rng.choice([rng.uniform(-7.0, -3.0), rng.uniform(9.0, 13.0)]), 0.0))
                elif locus == "theta4 - theta5 = pi":
                    theta2 = rng.uniform(-math.pi, math.pi)
                    c = (PROXIMAL * math.cos(theta2), PROXIMAL * math.sin(theta2))
                    d = circle_intersection(c, 2 * DISTAL, (6.0, 0.0), PROXIMAL, rng.choice([1, -1]))
                    add(locus, {"theta2": theta2, "theta3": math.atan2(d[1], d[0] - 6.0)})
                else:
                    centre = 0.0 if locus.startswith("theta2") else 6.0
                    reach, angle = rng.choice([PROXIMAL + DISTAL, PROXIMAL - DISTAL]), rng.uniform(-math.pi, math.pi)
                    add(locus, posture(centre + reach * math.cos(angle), reach * math.sin(angle)))
            except MechanismError:
                continue
    return samples


@pytest.mark.parametrize("locus, inputs", _samples())
def test_kinds_agree_with_the_004_conditions_across_the_workspace(locus, inputs):
    """Chablat, Wenger & Angeles 1998, eqs. (24)-(25), (30): singular exactly on those loci, with the kinds they predict."""
    mechanism = hybrid(**inputs)
    expected = predicted_kinds(mechanism)
    assert (expected == ()) == (locus == "generic")
    assert classified(mechanism).kinds == expected


def test_equation_22_holds_by_finite_differences():
    """Chablat, Wenger & Angeles 1998, eq. (22): A ṗ = B θ˙, A = [L2 nᵀ; (p − c)ᵀ; (p − d)ᵀ] (n: the five-bar's normal, k at
    θ1 = 0), B = L1 L2 diag(sin θ2 + λ1 sin θ4, sin(θ2 − θ4), sin(θ3 − θ5)), λ1 = L2/L1, checked
    against central differences of the closed-form positions at seeded postures. The signs of the
    last two diagonal entries depend on the sense in which the angles are measured, so those are
    compared in absolute value; the first is L2 d1 exactly (eq. 27)."""
    rng = np.random.default_rng(8)
    step = 1e-6
    checked = 0
    while checked < 4:
        inputs = {"theta1": rng.uniform(-math.pi, math.pi), "theta2": rng.uniform(-math.pi, math.pi),
                  "theta3": rng.uniform(-math.pi, math.pi), "assembly": int(rng.choice([1, -1]))}
        try:
            points, normal = hybrid_points(**inputs)
        except MechanismError:
            continue
        checked += 1
        theta2, theta3, theta4, theta5, _ = angles(hybrid(**inputs))
        p, c, d = (np.array(points[name]) for name in "PCD")
        velocity = np.empty((3, 3))
        for column, name in enumerate(("theta1", "theta2", "theta3")):
            plus = hybrid_points(**{**inputs, name: inputs[name] + step})[0]["P"]
            minus = hybrid_points(**{**inputs, name: inputs[name] - step})[0]["P"]
            velocity[:, column] = (np.array(plus) - np.array(minus)) / (2 * step)
        direct = np.array([DISTAL * np.array(normal), p - c, p - d])
        diagonal = PROXIMAL * DISTAL * np.array([math.sin(theta2) + DISTAL / PROXIMAL * math.sin(theta4),
                                                 math.sin(theta2 - theta4), math.sin(theta3 - theta5)])
        product = direct @ velocity
        np.testing.assert_allclose(product - np.diag(np.diag(product)), 0.0, atol=1e-6)
        assert product[0, 0] == pytest.approx(diagonal[0], abs=1e-6)
        np.testing.assert_allclose(np.abs(np.diag(product))[1:], np.abs(diagonal[1:]), atol=1e-6)
