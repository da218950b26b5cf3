"""Gough–Stewart platform (6-UPS): Gosselin & Angeles (1990) Section VII,
Figs. 10-12, eqs. (71)-(87).

The paper's A (eqs. 80-82, rows aᵢ = [wᵢᵀ, ((Q p′ᵢ) × wᵢ)ᵀ]) and B = diag(cᵢ) (eq. 83) are
computed here from the pose, independently of the joint graph and the classifier, and compared
with the Park–Kim kinds (type I ↔ end_effector, type II ↔ actuator, type III ↔ degenerate
actuator or C-space).
"""

import math

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from checks import classified
from mechanisms.catalogue.gough_stewart import ENTRIES, base_points, gough_stewart, platform_points

ENTRY = ENTRIES[0]


def paper_matrices(configuration=None, **overrides):
    """G-A eq. (81) A, shape=[6, 6], and the leg lengths cᵢ (eq. 75; B = diag(cᵢ), eq. 83)."""
    values = ENTRY.values(configuration, **overrides)
    orientation = Rotation.from_rotvec([values[f"rotation_{axis}"] for axis in "xyz"]).as_matrix()
    platform = platform_points(values["platform_radius"], values["platform_angle"]) @ orientation.T
    legs = np.array([values["x"], values["y"], values["z"]]) + platform - base_points(
        values["base_radius"], values["base_angle"])
    return np.hstack([legs, np.cross(platform, legs)]), np.linalg.norm(legs, axis=-1)


def relative_singular_values(matrix):
    values = np.linalg.svd(matrix, compute_uv=False)
    return values / values[0]


@pytest.mark.parametrize("configuration", [None, *ENTRY.configurations])
def test_every_named_configuration_builds(configuration):
    mechanism = ENTRY.mechanism(configuration)
    assert mechanism.space == "spatial" and mechanism.ambient_dimension == 36
    assert len(mechanism.actuated_coordinates) == 6


def test_the_default_configuration_is_regular():
    """The default pose (platform level above the base, Q = 1): A and B regular (eqs. 81-83)."""
    direct, lengths = paper_matrices()
    assert relative_singular_values(direct)[-1] > 0.1 and np.min(lengths) > 0.5
    report = classified(gough_stewart())
    assert report.kinds == () and report.dof == 6 and report.idle_freedoms == 0


def test_eq84_a_leg_of_zero_length_is_an_end_effector_singularity():
    """G-A eq. (84): c₁ = 0 makes B = diag(cᵢ) singular — kind I ↔ end_effector: the platform
    point P₁ = B₁ can only move along the (undefined, here vertical) leg, 2 directions are lost.
    The paper's own A (eq. 82) has then the zero row a₁ = w₁ = 0 as well, so it is also kind II:
    the classifier finds the actuator singularity too, degenerate — with the legs locked the U
    joint of the collapsed leg swings freely (the "undefined direction" of the prismatic joint)."""
    direct, lengths = paper_matrices("eq84_leg1_zero_length")
    assert lengths[0] < 1e-12 and np.min(lengths[1:]) > 0.3
    assert np.allclose(direct[0], 0.0, atol=1e-12)
    report = classified(ENTRY.mechanism("eq84_leg1_zero_length"))
    assert report.kinds == ("actuator", "end_effector")
    assert report.end_effector.rank == 4
    assert report.degeneracy == "degenerate"
    direction = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert set(direction) <= {"U1[1]", "U1[2]", "S1[x]", "S1[y]", "S1[z]"}


def test_near_eq84_is_regular():
    """G-A eq. (84): the platform moved 0.01 off the collapsed pose, c₁ ≈ 0.014 > 0: regular."""
    values = ENTRY.configurations["eq84_leg1_zero_length"]
    overrides = {"x": values["x"] + 0.01, "z": values["z"] + 0.01}
    assert 0.01 < paper_matrices("eq84_leg1_zero_length", **overrides)[1][0] < 0.02
    assert classified(ENTRY.mechanism("eq84_leg1_zero_length", **overrides)).kinds == ()


@pytest.mark.parametrize("configuration, overrides", [
    ("fichter_rotated_plus_90", {}),
    ("fichter_rotated_minus_90", {}),
    ("fichter_rotated_plus_90", {"x": 0.2, "y": -0.1, "z": 0.6}),
])
def test_rotated_90_degrees_about_the_vertical_is_a_nondegenerate_actuator_singularity(configuration,
                                                                                     overrides):
    """G-A eqs. (81)-(82): the rows of A are the (unnormalised) Plücker lines of the legs; with
    the platform turned ±90° about the vertical the lines are linearly dependent at any centre
    (Fichter, the paper's ref. [28]): det A = 0 with every cᵢ > 0 — kind II ↔ actuator."""
    direct, lengths = paper_matrices(configuration, **overrides)
    assert relative_singular_values(direct)[-1] < 1e-14 and relative_singular_values(direct)[-2] > 0.05
    assert np.min(lengths) > 0.5
    report = classified(ENTRY.mechanism(configuration, **overrides))
    assert report.kinds == ("actuator",)
    assert report.actuator.rank == 5
    assert report.degeneracy == "nondegenerate"


@pytest.mark.parametrize("offset", [-0.01, 0.01])
def test_near_the_90_degree_rotation_is_regular(offset):
    """G-A eq. (82): 0.01 rad away from the +90° rotation, det A ≠ 0: regular."""
    overrides = {"rotation_z": math.pi / 2 + offset}
    assert relative_singular_values(paper_matrices(**overrides)[0])[-1] > 1e-3
    assert classified(gough_stewart(**overrides)).kinds == ()


def test_eq87_equal_legs_are_parallel_and_move_the_platform_on_a_sphere():
    """G-A eq. (87): R_P = R_B, θ = η, Q = 1 and equal legs: every leg is the vector x, so
    the platform translates on the sphere |x| = c with the legs locked (checked here from
    eqs. 75-78), A has rank 3 (six parallel lines), B = c·1 is regular; the classifier finds the
    actuator singularity (rank G = 3) and no end-effector singularity."""
    centre = np.array([0.3, -0.2, 1.0])
    direct, lengths = paper_matrices("eq87_parallel_legs")
    assert np.allclose(lengths, np.linalg.norm(centre), atol=1e-12)
    assert np.sum(relative_singular_values(direct) > 1e-12) == 3
    moved = centre @ Rotation.from_rotvec([0.2, 0.5, -0.1]).as_matrix().T  # same |x|
    assert np.allclose(paper_matrices("eq87_parallel_legs", **dict(zip("xyz", moved)))[1], lengths, atol=1e-12)
    report = classified(ENTRY.mechanism("eq87_parallel_legs"))
    assert report.kinds == ("actuator",)
    assert report.actuator.rank == 3


def test_eq87_design_is_architecturally_singular():
    """Beyond the paper: with θ = η (similar base and platform hexagons) det A (eq. 81) vanishes at
    every pose — an architecture singularity — and with the legs locked at a generic pose the
    platform still moves (a 1-dof self-motion: poses 0.2 away with the same cᵢ, eq. 75, found
    independently by least squares). The classifier sees rank G ≤ 5 all over M while the stacked map
    (G; J) reaches 6: a locked-actuator freedom that moves the end-effector, which is not idle
    (docs/design.rst, "The three kinds"): every pose is a degenerate actuator singularity, flagged as
    an architecture singularity."""
    pose = {"x": 0.3, "y": -0.2, "z": 0.8, "rotation_x": 0.4, "rotation_y": -0.3, "rotation_z": 0.5}
    direct, lengths = paper_matrices("eq87_parallel_legs", **pose)
    assert relative_singular_values(direct)[-1] < 1e-14 and relative_singular_values(direct)[-2] > 1e-3

    def leg_residual(vector, start):
        values = dict(zip(pose, vector))
        moved = paper_matrices("eq87_parallel_legs", **values)[1]
        return np.append(moved - lengths, np.linalg.norm(vector - start) - 0.2)

    start = np.array(list(pose.values()))
    solution = least_squares(leg_residual, start + 0.2 / math.sqrt(6), args=(start,), xtol=1e-15, ftol=1e-15,
                             gtol=1e-15)
    assert np.max(np.abs(leg_residual(solution.x, start))) < 1e-12
    report = classified(ENTRY.mechanism("eq87_parallel_legs", **pose))
    assert report.idle_freedoms == 0 and report.moving_idle_freedoms == 1 and report.architecture_singular
    assert report.kinds == ("actuator",)
    assert (report.actuator.rank, report.actuator.expected_rank) == (5, 6)
    assert report.degeneracy == "degenerate"
    assert any("architecture singularity" in note for note in report.notes)
    assert report.to_dict()["architecture_singular"] is True
    assert "ARCHITECTURE SINGULARITY" in report.to_text()


def test_a_generic_design_has_no_idle_freedom():
    report = classified(ENTRY.mechanism())
    assert report.idle_freedoms == 0 and report.moving_idle_freedoms == 0 and not report.architecture_singular


def test_eq87_equal_legs_are_a_degenerate_actuator_singularity():
    """G-A eq. (87): kind III, "motions of a finite amplitude even if the actuators are locked"
    (verified from eqs. 75-78 in the test above) ↔ a degenerate actuator singularity, with a
    certified self-motion."""
    report = classified(ENTRY.mechanism("eq87_parallel_legs"))
    assert report.degeneracy == "degenerate" and report.architecture_singular
    motion = report.second_order.self_motion
    assert motion.distance >= 0.1 and motion.largest_residual < 1e-9
