"""Spherical six-bar with three actuators: Park & Kim (1999) Case 2, Figs. 7, 8a, 8b."""

import itertools
import math

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.spherical_six_bar import ENTRIES, joint_angles, spherical_six_bar, symmetric_hexagon

ENTRY = ENTRIES[0]
FIG7 = ENTRY.configurations["fig7_actuator"]


def axes_of(mechanism):
    return np.array([joint.axis for joint in mechanism.joints])


def actuator_rank_by_hand(axes, actuated):
    """Rank of G = Tᵀ E T computed directly: T spans ker [u1 ... u6] (Σ θ̇ᵢ uᵢ = 0), E selects `actuated`."""
    _, _, right = np.linalg.svd(axes.T)
    tangent = right[3:].T
    selection = tangent[[number - 1 for number in actuated]]
    return np.linalg.matrix_rank(selection.T @ selection, tol=1e-9)


@pytest.mark.parametrize("name", sorted(ENTRY.configurations))
def test_every_named_configuration_builds_and_closes_with_equal_twists(name):
    axes = axes_of(ENTRY.mechanism(name))
    twists = [math.acos(np.clip(axes[index] @ axes[(index + 1) % 6], -1, 1)) for index in range(6)]
    assert twists == pytest.approx([math.radians(70)] * 6, abs=1e-12)


def test_symmetric_hexagon_round_trips_through_the_builder():
    """The named configurations' angles rebuild the symmetric hexagon (up to a rotation)."""
    hexagon = symmetric_hexagon(math.radians(70))
    axes = axes_of(ENTRY.mechanism("fig7_actuator"))
    assert np.allclose(axes @ axes.T, hexagon @ hexagon.T, atol=1e-12)
    assert joint_angles(axes)[0] == pytest.approx(joint_angles(hexagon)[0], abs=1e-12)


def test_default_configuration_is_regular():
    report = classified(spherical_six_bar())
    assert report.kinds == ()
    assert report.dof == 3


def test_fig7_three_coplanar_axes_with_the_others_driven_is_a_nondegenerate_actuator_singularity():
    """Park & Kim Fig. 7: three coplanar axes (u2, u4, u6), J1, J3, J5 driven: rank G = 2 < 3, and,
    locked, the linkage is a structure (nondegenerate, as the paper states)."""
    mechanism = ENTRY.mechanism("fig7_actuator")
    assert abs(np.linalg.det(axes_of(mechanism)[[1, 3, 5]])) < 1e-12
    report = classified(mechanism)
    assert report.kinds == ("actuator",)
    assert report.actuator.rank == 2 and report.actuator.expected_rank == 3
    assert report.degeneracy == "nondegenerate"
    lost = report.to_dict()["actuator"]["kernel"][0]
    assert set(lost) == {"J2", "J4", "J6"}  # only the passive joints move


@pytest.mark.parametrize("step", [0.02, -0.02])
def test_near_fig7_is_regular(step):
    """Park & Kim Fig. 7 with θ3 moved slightly: u2, u4, u6 leave their plane, the singularity goes."""
    report = classified(ENTRY.mechanism("fig7_actuator", theta3=FIG7["theta3"] + step))
    assert report.kinds == ()


@pytest.mark.parametrize("name, actuators", [("fig8a_moved_actuator", 3), ("fig8b_added_actuator", 4)])
def test_fig8_moving_or_adding_an_actuator_removes_the_singularity(name, actuators):
    """Park & Kim Fig. 8a (the actuator of J5 moved to J4) and Fig. 8b (an actuator added at J2,
    redundant actuation): the same configuration is no longer an actuator singularity."""
    mechanism = ENTRY.mechanism(name)
    assert sum(joint.actuated for joint in mechanism.joints) == actuators
    report = classified(mechanism)
    assert report.kinds == ()
    assert report.actuator.rank == 3


def test_the_actuator_singularity_is_coplanar_passive_axes_by_hand():
    """Independent of the classifier: at the Fig. 7 configuration, over all 20 choices of three
    actuated joints, the rank of G computed by hand drops exactly when the three passive axes are
    coplanar (the implicit-function criterion Park & Kim give for the five-bar in Case 2)."""
    axes = axes_of(ENTRY.mechanism("fig7_actuator"))
    for actuated in itertools.combinations(range(1, 7), 3):
        passive = [number - 1 for number in range(1, 7) if number not in actuated]
        coplanar = abs(np.linalg.det(axes[passive])) < 1e-9
        assert (actuator_rank_by_hand(axes, actuated) < 3) == coplanar


@pytest.mark.xfail(reason="Park & Kim (Case 2, Fig. 7) state the condition as the three *actuated* axes "
                          "coplanar; the actuated coordinates fail as local coordinates when the three "
                          "*passive* axes are coplanar (their own implicit-function criterion), so driving "
                          "the three coplanar joints is regular", strict=True)
def test_fig7_as_stated_coplanar_actuated_axes_give_an_actuator_singularity():
    """Park & Kim Case 2, Fig. 7, read literally: the driven J2, J4, J6 have coplanar axes."""
    report = classified(ENTRY.mechanism("fig7_actuated_axes_coplanar"))
    assert "actuator" in report.kinds


@pytest.mark.parametrize("parameters", [
    {"twist": 0.0}, {"branch": 0}, {"actuated": "07"}, {"actuated": "11"},
    {"twist": math.radians(20), "theta1": math.pi, "theta2": math.pi, "theta3": math.pi},  # u4 at 80° from u6
])
def test_impossible_parameters_are_refused(parameters):
    with pytest.raises(MechanismError):
        spherical_six_bar(**parameters)
