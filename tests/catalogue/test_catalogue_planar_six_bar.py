"""Planar six-bar with equal links: Park & Kim (1999) Case 3, Fig. 12a/b."""

import numpy as np
import pytest

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.planar_six_bar import ENTRIES, planar_six_bar

ENTRY = ENTRIES[0]
FIG12 = ENTRY.configurations["fig12a_end_effector"]


def midpoint(angles, link, length=1.0):
    """Closed-form midpoint of link 1, 2 or 3, from the serial angles θ1, θ2, θ3 (independent model)."""
    headings = np.cumsum(angles)
    joints = [np.zeros(2)]
    for heading in headings:
        joints.append(joints[-1] + length * np.array([np.cos(heading), np.sin(heading)]))
    return (joints[link - 1] + joints[link]) / 2


def finite_difference_jacobian(link, angles, step=1e-6):
    angles = np.asarray(angles, dtype=float)
    columns = []
    for index in range(3):
        delta = np.zeros(3)
        delta[index] = step
        columns.append((midpoint(angles + delta, link) - midpoint(angles - delta, link)) / (2 * step))
    return np.stack(columns, axis=1)


@pytest.mark.parametrize("name", sorted(ENTRY.configurations))
def test_every_named_configuration_builds(name):
    mechanism = ENTRY.mechanism(name)
    assert mechanism.ambient_dimension == 6


def test_default_configuration_is_regular():
    report = classified(planar_six_bar())
    assert report.kinds == ()
    assert report.dof == 3


@pytest.mark.parametrize("actuated, kinds", [
    ("135", ("end_effector",)), ("246", ("end_effector",)), ("123", ("end_effector",)),
    ("1234", ("end_effector",)),
    # locked J4, J5, J6 leave the passive J1, J2, J3 on one line: also an actuator singularity
    ("456", ("actuator", "end_effector")),
    # two actuators for three freedoms: with J1, J6 locked the third freedom still moves the end-effector,
    # everywhere on M — not an idle freedom but an architecture singularity (docs/design.rst, "The three
    # kinds"): every configuration is an actuator singularity
    ("16", ("actuator", "end_effector")),
])
def test_fig12a_end_effector_on_the_aligned_link_is_singular_whatever_is_actuated(actuated, kinds):
    """Park & Kim Fig. 12a: links 1 and 2 aligned, end-effector on link 2; "regardless of the number
    and choice of joints that are actuated" the end-effector position loses a direction."""
    report = classified(ENTRY.mechanism("fig12a_end_effector", actuated=actuated))
    assert report.kinds == kinds
    assert report.architecture_singular == (len(actuated) < 3)
    assert report.end_effector.rank == 1 and report.end_effector.expected_rank == 2


def test_fig12a_the_end_effector_cannot_translate_along_its_link():
    """Park & Kim Fig. 12a, checked on an independent closed-form model: the midpoint of link 2 only
    moves across link 2 (finite-difference Jacobian of rank 1, image normal to the link)."""
    angles = [FIG12["theta1"], FIG12["theta2"], FIG12["theta3"]]
    jacobian = finite_difference_jacobian(2, angles)
    singular_values = np.linalg.svd(jacobian, compute_uv=False)
    assert singular_values[1] < 1e-8 * singular_values[0]
    along_link = np.array([np.cos(angles[0]), np.sin(angles[0])])
    assert np.allclose(along_link @ jacobian, 0.0, atol=1e-8)


def test_fig12b_end_effector_relocated_to_the_adjacent_link_is_regular():
    """Park & Kim Fig. 12b: the same configuration with the end-effector on link 3 moves in every
    direction of the plane (rank 2, also by finite differences of the closed-form model)."""
    report = classified(ENTRY.mechanism("fig12b_relocated"))
    assert report.kinds == ()
    assert report.end_effector.rank == 2
    angles = [FIG12["theta1"], FIG12["theta2"], FIG12["theta3"]]
    singular_values = np.linalg.svd(finite_difference_jacobian(3, angles), compute_uv=False)
    assert singular_values[1] > 0.1 * singular_values[0]


@pytest.mark.parametrize("theta2", [0.05, -0.05])
def test_near_fig12a_is_regular(theta2):
    """Park & Kim Fig. 12a with link 2 turned slightly off link 1: the end-effector is regular."""
    assert classified(ENTRY.mechanism("fig12a_end_effector", theta2=theta2)).kinds == ()


@pytest.mark.parametrize("parameters", [
    {"length": 0.0}, {"branch": 0}, {"actuated": "17"}, {"actuated": "113"}, {"end_effector_link": 6},
    {"theta1": np.pi, "theta2": 0.0, "theta3": 0.0},  # J4 at (-3, 0), out of reach of J6 = (1, 0)
])
def test_impossible_parameters_are_refused(parameters):
    with pytest.raises(MechanismError):
        planar_six_bar(**parameters)
