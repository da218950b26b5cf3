"""Spherical 3-RRR parallel wrist: Gosselin & Angeles (1990) Section VI,
Fig. 9, eqs. (66)-(70).

The paper's A (eq. 68) and B (eq. 69) are computed here from the axes of the built mechanism,
independently of the classifier, and compared with the Park–Kim kinds (type I ↔ end_effector,
type II ↔ actuator, type III ↔ degenerate actuator or C-space).
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.spatial.transform import Rotation

from checks import classified
from mechanisms.catalogue.spherical_3rrr import ENTRIES, spherical_3rrr

ENTRY = ENTRIES[0]


def axes(mechanism, kind):
    """The unit axes uᵢ ('motor'), wᵢ ('elbow') or vᵢ ('wrist') of the three legs, shape=[3, 3]."""
    vectors = np.array([mechanism.joint(f"{kind}{index}").axis for index in (1, 2, 3)])
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


def paper_matrices(mechanism):
    """G-A eq. (68) A (rows (wᵢ × vᵢ)ᵀ) and eq. (69) B = diag((wᵢ × uᵢ)·vᵢ)."""
    motors, elbows, wrists = (axes(mechanism, kind) for kind in ("motor", "elbow", "wrist"))
    direct = np.cross(elbows, wrists)
    inverse = np.diag(np.einsum("ij,ij->i", np.cross(elbows, motors), wrists))
    return direct, inverse


@pytest.mark.parametrize("configuration", [None, *ENTRY.configurations])
def test_every_named_configuration_builds(configuration):
    mechanism = ENTRY.mechanism(configuration)
    assert mechanism.space == "spherical" and len(mechanism.joints) == 9
    assert mechanism.actuated_coordinates == (0, 3, 6)


def test_the_default_configuration_is_regular():
    """A generic orientation: det A ≠ 0 and det B ≠ 0 (eqs. 68-69), no kind holds."""
    direct, inverse = paper_matrices(spherical_3rrr())
    assert abs(np.linalg.det(direct)) > 0.1 and np.min(np.abs(np.diag(inverse))) > 0.1
    report = classified(spherical_3rrr())
    assert report.kinds == () and report.dof == 3


@pytest.mark.parametrize("configuration", ["eq70_leg1_extended", "eq70_leg1_folded"])
def test_eq70_a_fully_extended_or_folded_leg_is_an_end_effector_singularity(configuration):
    """G-A eq. (70): (w₁ × u₁)·v₁ = 0 — leg 1 fully extended (∠(u₁, v₁) = α₁ + α₂) or folded
    (∠ = α₁ − α₂); B loses one rank, A stays regular: kind I ↔ end_effector, the gripper
    loses one direction of angular velocity."""
    mechanism = ENTRY.mechanism(configuration)
    direct, inverse = paper_matrices(mechanism)
    assert abs(inverse[0, 0]) < 1e-12 and min(abs(inverse[1, 1]), abs(inverse[2, 2])) > 0.1
    assert abs(np.linalg.det(direct)) > 0.05
    report = classified(mechanism)
    assert report.kinds == ("end_effector",)
    assert report.end_effector.rank == 2 and report.end_effector.expected_rank == 3


def _rotation_vector(precession, nutation):
    """Rotation-vector parameters of Q = R_z(precession) R_x(nutation)."""
    vector = Rotation.from_euler("ZXZ", [precession, nutation, 0.0]).as_rotvec()
    return dict(zip(("rotation_x", "rotation_y", "rotation_z"), vector))


_EXTENDED = ENTRY.configurations["eq70_leg1_extended"]


@pytest.mark.parametrize("configuration, overrides", [
    # rotation angle α₁ + α₂ = 105° → 104.9°, same axis
    ("eq70_leg1_extended", {name: value * (1 - 1e-3) for name, value in _EXTENDED.items()}),
    # precession α₁ − α₂ = 15° → 15° + 10⁻³ rad
    ("eq70_leg1_folded", _rotation_vector(math.pi / 12 + 1e-3, 0.8)),
])
def test_near_eq70_is_regular(configuration, overrides):
    """G-A eq. (70): just inside the reach of leg 1 the wrist is regular."""
    mechanism = ENTRY.mechanism(configuration, **overrides)
    assert 1e-3 < abs(paper_matrices(mechanism)[1][0, 0]) < 0.1
    assert classified(mechanism).kinds == ()


def test_eq68_distal_links_orthogonal_to_the_gripper_is_a_nondegenerate_actuator_singularity():
    """G-A eq. (68) and the text after it: the gripper in the base plane rotated by ψ with
    cos ψ = cos α₁ / cos α₂, so wᵢ = cos α₂ vᵢ + sin α₂ z and every distal link is orthogonal
    to the gripper plane: the wᵢ × vᵢ are coplanar, det A = 0 (kind II ↔ actuator)."""
    mechanism = ENTRY.mechanism("eq68_distal_links_orthogonal")
    direct, inverse = paper_matrices(mechanism)
    assert np.linalg.matrix_rank(direct, tol=1e-12) == 2
    assert np.min(np.abs(np.diag(inverse))) > 0.1
    report = classified(mechanism)
    assert report.kinds == ("actuator",)
    assert report.degeneracy == "nondegenerate"


def _det_direct(rotation_z):
    return np.linalg.det(paper_matrices(spherical_3rrr(rotation_z=rotation_z))[0])


def test_eq68_a_generic_root_of_det_a_is_a_nondegenerate_actuator_singularity():
    """G-A eq. (68): det A = 0 found by root-finding the paper's A along the rotation_z line
    through the default orientation (a non-symmetric configuration); the classifier finds the
    actuator singularity there."""
    root = brentq(_det_direct, 0.6, 0.8, xtol=1e-15)
    report = classified(spherical_3rrr(rotation_z=root))
    assert report.kinds == ("actuator",)
    assert report.degeneracy == "nondegenerate"


@pytest.mark.parametrize("offset", [-0.01, 0.01])
def test_near_eq68_is_regular(offset):
    """G-A eq. (68): 0.01 rad on either side of the generic root and of the symmetric one."""
    root = brentq(_det_direct, 0.6, 0.8, xtol=1e-15)
    assert classified(spherical_3rrr(rotation_z=root + offset)).kinds == ()
    symmetric = ENTRY.configurations["eq68_distal_links_orthogonal"]["rotation_z"]
    assert classified(ENTRY.mechanism("eq68_distal_links_orthogonal", rotation_z=symmetric + offset)).kinds == ()


@pytest.mark.parametrize("rotation_z", [1.0, 2.5, -0.6])
def test_right_link_angles_with_the_gripper_in_the_motor_plane_are_degenerate(rotation_z):
    """G-A Section VI: α₁ = α₂ = π/2 and vᵢ coplanar with uᵢ — every wᵢ is the normal of that
    plane, and the gripper turns about it with the motors locked (kind III ↔ a degenerate
    actuator singularity with a self-motion). Independent check: the wrist built at ψ + 0.3
    has the same motor-side geometry (wᵢ unchanged), so the motion is finite."""
    overrides = {"rotation_z": rotation_z}
    mechanism = ENTRY.mechanism("section6_right_alphas_coplanar", **overrides)
    turned = ENTRY.mechanism("section6_right_alphas_coplanar", rotation_z=rotation_z + 0.3)
    np.testing.assert_allclose(axes(turned, "elbow"), axes(mechanism, "elbow"), atol=1e-12)
    report = classified(mechanism)
    assert report.kinds == ("actuator",)
    assert report.degeneracy == "degenerate"
    motion = report.second_order.self_motion
    assert motion.distance >= 0.1 and motion.largest_residual < 1e-9
    direction = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert not any(name.startswith("motor") for name in direction)


def test_near_right_link_angles_coplanar_is_regular():
    """G-A Section VI: tilting the gripper 0.1 rad out of the motor plane ends the self-motion."""
    assert classified(ENTRY.mechanism("section6_right_alphas_coplanar", rotation_x=0.1)).kinds == ()


def test_equal_link_angles_folded_legs_leave_the_gripper_still():
    """G-A Section VI, first set: α₁ = α₂ and uᵢ = vᵢ — condition (70) holds for the three legs,
    rank B = 0: the motors turn the legs about uᵢ = vᵢ and the gripper cannot move at all
    (end_effector, rank J = 0). For a generic input angle the C-space is smooth there."""
    mechanism = ENTRY.mechanism("section6_equal_alphas_folded")
    assert np.allclose(paper_matrices(mechanism)[1], 0.0, atol=1e-12)
    report = classified(mechanism)
    assert report.kinds == ("end_effector",)
    assert report.end_effector.rank == 0


@pytest.mark.parametrize("theta_folded", [0.0, math.pi / 2])
def test_equal_link_angles_folded_at_theta_zero_or_right_is_a_branch_crossing(theta_folded):
    """G-A Section VI: with α₁ = α₂, uᵢ = vᵢ and θ₁ = θ₂ = θ₃ = 0 or π/2 "the first and second
    kinds meet": det A = 0 as well as B = 0 (eqs. 68-69). In Park–Kim terms the folded
    family (gripper still, motors free) crosses the branch on which the gripper moves: a C-space
    singularity (kind III ↔ C-space), with the gripper stopped (end_effector)."""
    mechanism = ENTRY.mechanism("section6_equal_alphas_folded", theta_folded=theta_folded)
    direct, inverse = paper_matrices(mechanism)
    assert abs(np.linalg.det(direct)) < 1e-12 and np.allclose(inverse, 0.0, atol=1e-12)
    report = classified(mechanism)
    assert report.kinds == ("cspace", "end_effector")


def test_the_moving_branch_reaches_the_folded_legs_at_theta_right():
    """The crossing of the previous test, independently: on the branch Q = R_z(ε) the elbow axes
    tend, as ε → 0, to those of the folded legs at θ = π/2 (wᵢ = cos α uᵢ + sin α z)."""
    folded = axes(ENTRY.mechanism("section6_equal_alphas_folded", theta_folded=math.pi / 2), "elbow")
    for epsilon in (1e-3, 1e-5):
        moving = axes(ENTRY.mechanism("section6_equal_alphas_folded", rotation_z=epsilon), "elbow")
        assert np.max(np.abs(moving - folded)) < epsilon


def test_near_the_folded_legs_is_regular():
    """G-A Section VI: α₁ = α₂, the gripper turned 0.05 rad off uᵢ = vᵢ: every kind is regular."""
    mechanism = ENTRY.mechanism("section6_equal_alphas_folded", rotation_x=0.05, rotation_y=0.03, rotation_z=0.04)
    assert classified(mechanism).kinds == ()
