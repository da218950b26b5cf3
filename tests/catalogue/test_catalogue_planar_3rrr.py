"""Planar 3-RRR: Gosselin & Angeles (1990) Fig. 7, eqs. (42)-(65).

Each singular configuration the paper states is checked against the paper's Jacobians A and
B (eqs. 44-48, rebuilt here from the joint positions, up to the positive row factors of
eqs. 45-48: row i of A is [v_i, (A_i − c) × v_i] with v_i = A_i − D_i along the distal link,
eq. 62, and B_ii ∝ d_i ∝ sin ψ_i) and by the Park–Kim classifier, with a nearby configuration
that must be regular.
"""

import functools
import math

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.planar_3rrr import ENTRIES, planar_3rrr, planar_3rrr_positions

(ENTRY,) = ENTRIES
#: The kinds each named configuration must have (the tests below say why).
EXPECTED_KINDS = {
    "eq58_leg_stretched": ("end_effector",),
    "eq58_leg_folded": ("end_effector",),
    "eq61_distal_links_concurrent": ("actuator",),
    "eq63_distal_links_parallel": ("actuator",),
    "eq64_elbows_at_centroid": ("cspace", "end_effector"),
    "eq64_elbows_at_centroid_turned": ("actuator",),
    "eq65_vertices_on_motors": ("cspace", "end_effector"),
    "eq65_vertices_on_motors_other_inputs": ("end_effector",),
}
#: Nearby configurations (parameter changes from the named one) that must be regular.
NEARBY = {
    "eq58_leg_stretched": {"shift": -0.01, "mode1": 1},  # the gripper 0.01 back along leg 1 (θ₁ solved again)
    "eq58_leg_folded": {"shift": 0.01, "mode1": 1},
    "eq61_distal_links_concurrent": {"phi": 0.02},
    "eq63_distal_links_parallel": {"phi": 0.02},
    "eq64_elbows_at_centroid": {"phi": 0.05, "mode1": -1, "mode2": -1, "mode3": -1},
    "eq64_elbows_at_centroid_turned": {"x": 0.02},
    "eq65_vertices_on_motors": {"phi": 0.05, "mode1": 1, "mode2": 1, "mode3": 1},
}
#: Direction of leg 1 in the eq. (58) configurations (see the module's ENTRIES).
LEG_HEADING = math.radians(40)


@functools.lru_cache(maxsize=None)
def report(name):
    """The classification of a named configuration (shared by the tests)."""
    return classified(ENTRY.mechanism(name))


def legs(values):
    """Motors M_i, elbows D_i, gripper vertices A_i (shape [3, 2] each) and inputs θ_i."""
    return planar_3rrr_positions(
        **{key: values[key] for key in ("base", "l1", "l2", "l3", "x", "y", "phi")},
        modes=(values["mode1"], values["mode2"], values["mode3"]),
        thetas=(values["theta1"], values["theta2"], values["theta3"]))


def cross(first, second):
    return first[..., 0] * second[..., 1] - first[..., 1] * second[..., 0]


def paper_jacobians(values):
    """G-A's A and B (eqs. 44-48, up to positive row factors), normalised by the link lengths."""
    motors, elbows, vertices, _ = legs(values)
    centre = np.array([values["x"], values["y"]])
    distal = (vertices - elbows) / values["l2"]
    matrix_a = np.column_stack([distal, cross(vertices - centre, distal) / values["l3"]])
    matrix_b = np.diag(cross((elbows - motors) / values["l1"], distal))
    return matrix_a, matrix_b


def nearby(name):
    """The values of the named configuration moved as NEARBY says."""
    change = dict(NEARBY[name])
    values = ENTRY.values(name)
    shift = change.pop("shift", 0.0)
    values["x"] += shift * math.cos(LEG_HEADING)
    values["y"] += shift * math.sin(LEG_HEADING)
    for key, value in change.items():
        values[key] = values[key] + value if key in ("x", "y", "phi") else value
    return values


# --------------------------------------------------------------------------- the catalogue entry

@pytest.mark.parametrize("name", EXPECTED_KINDS)
def test_named_configurations_have_the_kinds_the_tests_below_establish(name):
    assert report(name).kinds == EXPECTED_KINDS[name]
    assert report(name).dof == 3


def test_every_named_configuration_is_checked_and_builds():
    assert set(ENTRY.configurations) == set(EXPECTED_KINDS)
    for name in ENTRY.configurations:
        assert len(ENTRY.mechanism(name).joints) == 9


def test_default_configuration_is_regular():
    matrix_a, matrix_b = paper_jacobians(ENTRY.values())
    assert abs(np.linalg.det(matrix_a)) > 1e-2 and abs(np.linalg.det(matrix_b)) > 1e-2
    assert classified(planar_3rrr()).kinds == ()


def test_unreachable_pose_names_the_parameter():
    with pytest.raises(MechanismError, match="pose x = 3"):
        planar_3rrr(x=3.0)


def test_a_given_input_that_does_not_close_names_the_parameter():
    with pytest.raises(MechanismError, match="theta1"):
        planar_3rrr(mode1=0, theta1=0.0)


@pytest.mark.parametrize("name", sorted(NEARBY))
def test_near_each_singular_configuration_is_regular(name):
    """The same design moved a little (gripper pose, or the other working mode where the
    singular branch is the whole neighbourhood): det A and det B are away from zero and the
    classifier finds nothing."""
    values = nearby(name)
    matrix_a, matrix_b = paper_jacobians(values)
    assert abs(np.linalg.det(matrix_a)) > 1e-4 and abs(np.linalg.det(matrix_b)) > 1e-4
    assert classified(planar_3rrr(**values)).kinds == ()


# --------------------------------------------------------------------------- kind I, eq. (58)

@pytest.mark.parametrize("name", ["eq58_leg_stretched", "eq58_leg_folded"])
def test_eq58_leg_stretched_or_folded_is_an_end_effector_singularity(name):
    """G-A eqs. (57)-(59): d₁ = 0, leg 1's links aligned (sin ψ₁ = 0), det A ≠ 0: "the set
    of Cartesian velocities ... along the folded or extended leg cannot be produced" — the
    end-effector (gripper pose) loses one rank, the actuators none."""
    matrix_a, matrix_b = paper_jacobians(ENTRY.values(name))
    assert abs(matrix_b[0, 0]) < 1e-12
    assert min(abs(matrix_b[1, 1]), abs(matrix_b[2, 2])) > 0.05 and abs(np.linalg.det(matrix_a)) > 0.01
    result = report(name)
    assert result.kinds == ("end_effector",)
    assert (result.end_effector.rank, result.end_effector.expected_rank) == (2, 3)


# --------------------------------------------------------------------------- kind II, eqs. (60)-(63)

def test_eq61_concurrent_distal_links_is_a_nondegenerate_actuator_singularity():
    """G-A eq. (61), Fig. 8: the lines of the three distal links meet (here at the gripper's
    centroid), c₁ = c₂ = c₃ = 0 and the null space of A is [0, 0, 1]ᵀ, the rotations about the
    centroid; B is regular. Park–Kim: an actuator singularity, nondegenerate (the rotation is
    only infinitesimal)."""
    matrix_a, matrix_b = paper_jacobians(ENTRY.values("eq61_distal_links_concurrent"))
    np.testing.assert_allclose(matrix_a[:, 2], 0.0, atol=1e-12)
    assert np.linalg.matrix_rank(matrix_a[:, :2]) == 2 and abs(np.linalg.det(matrix_b)) > 1e-2
    result = report("eq61_distal_links_concurrent")
    assert result.kinds == ("actuator",)
    assert (result.actuator.rank, result.actuator.expected_rank) == (2, 3)
    assert result.degeneracy == "nondegenerate"


def test_eq63_parallel_distal_links_is_a_degenerate_actuator_singularity():
    """G-A eq. (63): the three distal links parallel, the first two columns of A dependent,
    the null space of A a translation orthogonal to them; B is regular. The paper calls it
    kind II; Park–Kim finds it degenerate, and rightly: the legs being equal (eq. 42), the
    elbows D_i = A_i − l₂ v form a translate of the gripper triangle, so with the motors locked
    the gripper translates along a circle of radius l₂ (a finite motion). Independently: the
    mechanism closes with the same inputs θ_i at the gripper translated by l₂(e(ω + 0.3) − e(ω))."""
    values = ENTRY.values("eq63_distal_links_parallel")
    matrix_a, matrix_b = paper_jacobians(values)
    assert abs(cross(matrix_a[0, :2], matrix_a[1, :2])) < 1e-12
    assert abs(cross(matrix_a[0, :2], matrix_a[2, :2])) < 1e-12
    assert abs(np.linalg.det(matrix_b)) > 1e-2
    _, elbows, vertices, thetas = legs(values)
    direction = math.atan2(*(vertices[0] - elbows[0])[::-1])
    move = values["l2"] * (np.array([math.cos(direction + 0.3), math.sin(direction + 0.3)])
                           - np.array([math.cos(direction), math.sin(direction)]))
    locked = {**values, "x": values["x"] + move[0], "y": values["y"] + move[1], "mode1": 0, "mode2": 0, "mode3": 0,
              "theta1": thetas[0], "theta2": thetas[1], "theta3": thetas[2]}
    planar_3rrr(**locked)  # closes: raises MechanismError otherwise
    result = report("eq63_distal_links_parallel")
    assert result.kinds == ("actuator",)
    assert result.degeneracy == "degenerate"
    motion = result.to_dict()["actuator"]["second_order"]["self_motion"]
    assert motion["distance"] >= 0.1 and motion["largest_residual"] < 1e-9
    assert not {"motor1", "motor2", "motor3"} & set(motion["direction"])


# --------------------------------------------------------------------------- kind III, eqs. (64)-(65)

def test_eq64_elbows_at_the_centroid_turn_the_gripper_freely():
    """G-A eq. (64), l₁ = √3/3, l₂ = l₃: the three elbows meet at the base centroid, which is
    the gripper's centroid; "the gripper can then undergo arbitrary rotations about its
    centroid while the motors remain at rest". At φ = 0.5: c_i = 0 (A singular), B regular;
    Park–Kim: a degenerate actuator singularity (the self-motion turns the gripper). The same
    inputs close at φ = 1.0 (the finite motion, independently)."""
    values = ENTRY.values("eq64_elbows_at_centroid_turned")
    _, elbows, _, thetas = legs(values)
    np.testing.assert_allclose(elbows, [[values["x"], values["y"]]] * 3, atol=1e-12)
    matrix_a, matrix_b = paper_jacobians(values)
    np.testing.assert_allclose(matrix_a[:, 2], 0.0, atol=1e-12)
    assert abs(np.linalg.det(matrix_b)) > 1e-2
    planar_3rrr(**{**values, "phi": 1.0, "mode1": 0, "mode2": 0, "mode3": 0,
                   "theta1": thetas[0], "theta2": thetas[1], "theta3": thetas[2]})
    result = report("eq64_elbows_at_centroid_turned")
    assert result.kinds == ("actuator",)
    assert result.degeneracy == "degenerate"
    motion = result.to_dict()["actuator"]["second_order"]["self_motion"]
    assert motion["distance"] >= 0.1 and not {"motor1", "motor2", "motor3"} & set(motion["direction"])


def test_eq64_at_phi_zero_kinds_one_and_two_meet_in_a_cspace_singularity():
    """G-A after eq. (64): "This indeterminacy is due to the zeroing of both the c_i's and the
    d_i's when the gripper is oriented such that φ = 0" — det A = det B = 0 (kind III). There
    the self-rotation branch (elbows at the centroid) crosses the branch where the legs fold
    (both working modes meet): Park–Kim finds a C-space singularity (and the end-effector rank
    drops on ker DΦ)."""
    matrix_a, matrix_b = paper_jacobians(ENTRY.values("eq64_elbows_at_centroid"))
    np.testing.assert_allclose(matrix_a[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.diag(matrix_b), 0.0, atol=1e-12)
    result = report("eq64_elbows_at_centroid")
    assert result.kinds == ("cspace", "end_effector")
    assert (result.cspace.rank, result.cspace.expected_rank) == (5, 6)


def test_eq65_vertices_on_the_motors_at_the_papers_inputs_is_a_cspace_singularity():
    """G-A eq. (65), l₁ = l₂, l₃ = √3/3, gripper vertices on the motors, φ = 0 and θ = (−150°,
    −30°, 90°): "both the c_i's and the d_i's are equal to zero" (kind III). Park–Kim: the
    branch on which the motors turn with the gripper at rest crosses, at those inputs, the
    branch on which the gripper moves: a C-space singularity."""
    values = ENTRY.values("eq65_vertices_on_motors")
    assert [round(math.degrees(values[f"theta{i}"])) for i in (1, 2, 3)] == [-150, -30, 90]
    motors, _, vertices, _ = legs(values)
    np.testing.assert_allclose(vertices, motors, atol=1e-12)
    matrix_a, matrix_b = paper_jacobians(values)
    np.testing.assert_allclose(matrix_a[:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.diag(matrix_b), 0.0, atol=1e-12)
    result = report("eq65_vertices_on_motors")
    assert result.kinds == ("cspace", "end_effector")
    assert (result.cspace.rank, result.cspace.expected_rank) == (5, 6)


def test_eq65_vertices_on_the_motors_at_other_inputs_is_an_end_effector_singularity():
    """G-A eq. (65): "the motors can undergo arbitrary rotations while the gripper remains at
    rest" — at other inputs only B vanishes (kind I, the d_i's zero, A regular); Park–Kim: the
    end-effector has rank 0 there (the whole tangent space moves the motors only)."""
    values = ENTRY.values("eq65_vertices_on_motors_other_inputs")
    matrix_a, matrix_b = paper_jacobians(values)
    np.testing.assert_allclose(np.diag(matrix_b), 0.0, atol=1e-12)
    assert abs(np.linalg.det(matrix_a)) > 1e-2
    result = report("eq65_vertices_on_motors_other_inputs")
    assert result.kinds == ("end_effector",)
    assert (result.end_effector.rank, result.end_effector.expected_rank) == (0, 3)
