"""The Eclipse: Park & Kim (1999) Case 2 (Figs. 9, 10) and Case 3 (Fig. 11c)."""

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from checks import classified
from mechanisms import MechanismError
from mechanisms.catalogue.eclipse import ENTRIES, eclipse, plucker_lines

ENTRY = ENTRIES[0]


def joints_of(mechanism):
    return {joint.name: joint for joint in mechanism.joints}


def passes_through(point, line_point, direction):
    direction = np.asarray(direction) / np.linalg.norm(direction)
    return np.linalg.norm(np.cross(np.asarray(point) - line_point, direction)) < 1e-12


def locked_fibre_residual(mechanism, step):
    """Independent model of the platform with the six actuators locked at home: each ball bᵢ stays on
    the circle of radius l about its hinge rᵢ in the column's vertical plane (6 equations in the 6
    pose coordinates). Returns the smallest residual over poses at distance `step` along the kernel
    of the equations' Jacobian (both senses): zero for a self-motion, positive for an isolated pose."""
    joints = joints_of(mechanism)
    hinges = np.array([joints[f"hinge{leg}"].point for leg in (1, 2, 3)])
    tangents = np.array([joints[f"hinge{leg}"].axis for leg in (1, 2, 3)])
    balls = np.array([joints[f"ball{leg}"].point for leg in (1, 2, 3)])
    centre = np.array(mechanism.end_effector.point)
    lengths = np.linalg.norm(balls - hinges, axis=1)

    def residual(pose):
        moved = pose[:3] + Rotation.from_rotvec(pose[3:]).apply(balls - centre)
        return np.concatenate([np.linalg.norm(moved - hinges, axis=1) - lengths,
                               np.einsum("ij,ij->i", moved, tangents)])

    home_pose = np.concatenate([centre, np.zeros(3)])
    jacobian = np.array([(residual(home_pose + delta) - residual(home_pose - delta)) / 2e-7
                         for delta in np.eye(6) * 1e-7]).T
    _, _, right = np.linalg.svd(jacobian)
    kernel, complement = right[-1], right[:-1].T
    return min(np.linalg.norm(least_squares(lambda shift: residual(home_pose + sign * step * kernel
                                                                   + complement @ shift),
                                            np.zeros(5), xtol=1e-15, ftol=1e-15, gtol=1e-15).fun)
               for sign in (1, -1))


@pytest.mark.parametrize("name", sorted(ENTRY.configurations))
def test_every_named_configuration_builds(name):
    mechanism = ENTRY.mechanism(name)
    assert mechanism.ambient_dimension == 18
    assert sum(joint.actuated for joint in mechanism.joints) == 6


def test_default_configuration_is_regular():
    """Park & Kim Fig. 9: a generic pose of the 6-dof Eclipse, six actuators, regular."""
    report = classified(eclipse())
    assert report.kinds == ()
    assert report.dof == 6
    assert abs(np.linalg.det(plucker_lines(eclipse()))) > 1e-2


def test_fig10_four_lines_meet_at_ball_one():
    """Park & Kim Fig. 10: "four lines meet at a single point, which indicates a singular J_f" --
    the link and tangent lines of leg 1 and the tangent lines of legs 2 and 3 pass through ball 1."""
    mechanism = ENTRY.mechanism("fig10_actuator")
    joints = joints_of(mechanism)
    ball = np.array(joints["ball1"].point)
    lines = [(joints["hinge1"].point, ball - np.array(joints["hinge1"].point))]
    lines += [(joints[f"ball{leg}"].point, joints[f"hinge{leg}"].axis) for leg in (1, 2, 3)]
    assert all(passes_through(ball, np.array(point), direction) for point, direction in lines)
    singular_values = np.linalg.svd(plucker_lines(mechanism), compute_uv=False)
    assert singular_values[-1] < 1e-12 * singular_values[0]


@pytest.mark.parametrize("name", ["fig10_actuator", "fig10_turned"])
def test_fig10_is_an_actuator_singularity_and_not_an_end_effector_one(name):
    """Park & Kim Fig. 10 (and the same platform turned about its centre): rank G = 5 < 6."""
    report = classified(ENTRY.mechanism(name))
    assert report.kinds == ("actuator",)
    assert report.actuator.rank == 5 and report.actuator.expected_rank == 6


def test_fig10_turned_is_nondegenerate():
    """Park & Kim Fig. 10 states a nondegenerate actuator singularity; off the mirror-symmetric pose
    the second-order test confirms it (locked, the Eclipse is a structure)."""
    report = classified(ENTRY.mechanism("fig10_turned"))
    assert report.degeneracy == "nondegenerate"


def test_fig10_locked_platform_is_isolated_at_third_order():
    """Park & Kim Fig. 10, checked on an independent model: with the actuators locked, the nearest
    poses along the kernel violate the leg circles by a residual ∝ t³ (no self-motion), so the pose is
    isolated in its fibre -- nondegenerate in the paper's sense, at third order."""
    mechanism = ENTRY.mechanism("fig10_actuator")
    residuals = [locked_fibre_residual(mechanism, step) for step in (1e-2, 1e-3)]
    assert residuals[1] > 1e-12
    assert residuals[0] / residuals[1] == pytest.approx(1e3, rel=0.05)


def test_fig10_is_nondegenerate_as_the_paper_states():
    """Park & Kim Fig. 10: "a nondegenerate actuator singularity for the Eclipse". At the mirror-symmetric
    pose the second-order forms Q_e vanish on ker G by symmetry; no self-motion continues from the root,
    and the fibre is obstructed at third order (the independent check above): p̄ is isolated."""
    report = classified(ENTRY.mechanism("fig10_actuator"))
    assert report.degeneracy == "nondegenerate"
    higher = report.second_order.higher_order
    assert higher.verdict == "isolated" and higher.order == 3
    assert higher.obstruction > 1e3 * higher.tolerance


@pytest.mark.parametrize("parameters", [{"y": 0.35}, {"y": 0.25}, {"x": 0.05}])
def test_near_fig10_is_regular(parameters):
    """Park & Kim Fig. 10 with the platform moved slightly: no longer singular."""
    assert classified(ENTRY.mechanism("fig10_actuator", **parameters)).kinds == ()


def test_fig11c_ball_above_the_centre_is_an_end_effector_singularity_only():
    """Park & Kim Fig. 11c: platform parallel to the base, ball 1 above the centre of the track: the
    platform loses a twist (rank J = 5 < 6) while G keeps full rank -- "not an actuator singularity";
    the lost joint motion is the track of leg 1 turning under its ball."""
    mechanism = ENTRY.mechanism("fig11c_end_effector")
    ball = joints_of(mechanism)["ball1"].point
    assert ball[0] == pytest.approx(0.0, abs=1e-15) and ball[1] == pytest.approx(0.0, abs=1e-15)
    report = classified(mechanism)
    assert report.kinds == ("end_effector",)
    assert report.end_effector.rank == 5 and report.end_effector.expected_rank == 6
    assert report.actuator.rank == 6
    lost = report.to_dict()["end_effector"]["kernel"][0]
    assert "track1" in lost and set(lost) <= {"track1", "ball1[x]", "ball1[y]", "ball1[z]"}


def test_fig11c_static_jacobian_is_nonsingular():
    """Park & Kim Fig. 11c: "one can readily verify that at this configuration the matrix J_f is
    nonsingular" (computed from the six Plücker lines, independently of the classifier)."""
    singular_values = np.linalg.svd(plucker_lines(ENTRY.mechanism("fig11c_end_effector")), compute_uv=False)
    assert singular_values[-1] > 1e-2 * singular_values[0]


@pytest.mark.parametrize("parameters", [{"y": -0.25}, {"y": -0.35}])
def test_near_fig11c_is_regular(parameters):
    """Park & Kim Fig. 11c with ball 1 moved off the track axis (within its column's plane)."""
    assert classified(ENTRY.mechanism("fig11c_end_effector", **parameters)).kinds == ()


@pytest.mark.parametrize("parameters", [{"track_radius": 0.0}, {"elbow": 0}, {"x": 3.0}])
def test_impossible_parameters_are_refused(parameters):
    with pytest.raises(MechanismError):
        eclipse(**parameters)
