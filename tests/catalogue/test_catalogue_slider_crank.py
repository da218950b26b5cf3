"""Slider-crank: Park & Kim (1999) Fig. 3 a-d; Gosselin & Angeles
(1990) eqs. (6)-(17)."""

import numpy as np
import pytest

from checks import classified
from mechanisms.catalogue.slider_crank import ENTRIES, slider_crank

(ENTRY,) = ENTRIES
#: The kinds each named configuration must have (the tests below say why).
EXPECTED_KINDS = {
    "fig3a_self_intersection": ("cspace",),
    "fig3b_actuator": ("actuator",),
    "fig3c_dead_centre": ("end_effector",),
    "fig3d_dead_centre": ("actuator", "end_effector"),
    "eq17_constant_branch": ("end_effector",),
    "eq17_constant_branch_slider_driven": ("actuator", "end_effector"),
}


@pytest.mark.parametrize("name", EXPECTED_KINDS)
def test_named_configurations_have_the_kinds_the_tests_below_establish(name):
    assert classified(ENTRY.mechanism(name)).kinds == EXPECTED_KINDS[name]


def test_every_named_configuration_is_checked():
    assert set(ENTRY.configurations) == set(EXPECTED_KINDS)


@pytest.mark.parametrize("theta", [0.3, -0.4, 2.9])
def test_generic_configurations_are_regular(theta):
    report = classified(slider_crank(crank=2.0, coupler=1.0, theta=np.arcsin(0.5 * np.sin(theta))))
    assert report.kinds == ()
    assert report.dof == 1


def test_fig3a_self_intersection_is_a_cspace_singularity():
    """Equal crank and coupler (G-A eq. 15): the branches x = 2R cos θ and x = 0 (eq. 17) cross
    at θ = π/2 — a self-intersection of M (Park & Kim Fig. 3a, Fig. 4)."""
    report = classified(slider_crank(crank=1.0, coupler=1.0, theta=np.pi / 2))
    assert "cspace" in report.kinds
    assert report.cspace.rank == 2 and report.cspace.expected_rank == 3
    assert report.to_dict()["cspace"]["kernel_dimension"] == 2
    assert report.to_dict()["cspace"]["tangent_cone_span"] == 2  # two branches cross


@pytest.mark.parametrize("theta, branch", [(np.pi / 2 + 0.05, -1), (np.pi / 2 - 0.05, 1)])
def test_near_the_self_intersection_is_regular(theta, branch):
    """On the branch x = 2R cos θ near θ = π/2 (for θ > π/2 the "+" root of eq. 9 is x = 0)."""
    assert classified(slider_crank(crank=1.0, coupler=1.0, theta=theta, branch=branch)).kinds == ()


@pytest.mark.parametrize("sign", [1, -1])
def test_fig3b_coupler_square_to_the_slide_is_a_nondegenerate_actuator_singularity(sign):
    """G-A eq. (14): sin θ = l/R, the two direct-kinematics branches meet (A = 0)."""
    report = classified(slider_crank(crank=2.0, coupler=1.0, theta=sign * np.arcsin(0.5)))
    assert report.kinds == ("actuator",)
    assert report.degeneracy == "nondegenerate"
    assert report.second_order.smallest > 1e3 * report.second_order.tolerance


def test_near_fig3b_is_regular():
    assert classified(slider_crank(crank=2.0, coupler=1.0, theta=np.arcsin(0.5) - 1e-3)).kinds == ()


@pytest.mark.parametrize("theta, branch", [(0.0, 1), (0.0, -1), (np.pi, 1), (np.pi, -1)])
def test_fig3c_dead_centre_is_an_end_effector_singularity(theta, branch):
    """G-A eqs. (12)-(13): B = 0 at θ = 0, π; with the crank driven and the end-effector on the
    slider, the slider's velocity vanishes (Park & Kim Fig. 3c)."""
    report = classified(slider_crank(crank=2.0, coupler=1.0, theta=theta, branch=branch))
    assert report.kinds == ("end_effector",)
    assert report.manipulability.condition_number is None
    assert report.manipulability.eigenvalues[0] == pytest.approx(0.0, abs=1e-12)


def test_fig3d_dead_centre_with_the_slider_driven_combines_actuator_and_end_effector():
    """Our reading of Fig. 3d (the figure is not in the text): slider driven and carrying the
    end-effector; at dead centre both G and J lose rank."""
    report = classified(slider_crank(crank=2.0, coupler=1.0, theta=0.0, actuated="slider"))
    assert report.kinds == ("actuator", "end_effector")
    assert report.degeneracy == "nondegenerate"


def test_constant_branch_with_the_slider_driven_is_degenerate_with_a_self_motion():
    """Equal links, slider locked at x = 0 (G-A eq. 17, the constant branch, kind III): the crank
    and coupler fold freely — a degenerate actuator singularity with a self-motion certificate."""
    report = classified(slider_crank(crank=1.0, coupler=1.0, theta=0.4, branch=0, actuated="slider"))
    assert "actuator" in report.kinds
    assert report.degeneracy == "degenerate"
    motion = report.second_order.self_motion
    assert motion.distance >= 0.1 and motion.largest_residual < 1e-9
    direction = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert "slide" not in direction and "crank" in direction


def test_constant_branch_with_the_crank_driven_is_regular_for_the_actuator():
    """G-A after eq. (17): "when x is equal to zero, the input can undergo arbitrary rotations,
    whereas the output remains at rest" — an end-effector singularity all along the branch."""
    report = classified(slider_crank(crank=1.0, coupler=1.0, theta=0.4, branch=0, actuated="crank"))
    assert "actuator" not in report.kinds
    assert "end_effector" in report.kinds  # the slider does not move on that branch
