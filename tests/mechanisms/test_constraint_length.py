"""The description of M (Φ's rows, the tangent scales of the joint coordinates) depends on the joints alone.

The end-effector point is no part of M: moving it along a link must change
neither the C-space rank nor its margin nor the verdict. Φ's translation rows
and the tangent scale of prismatic coordinates take the characteristic length
of the joints' points (:attr:`mechanisms.Mechanism.characteristic_length`);
the end-effector point enters it only where no link carries two joint points.
"""

import numpy as np
import pytest

from builders import rsur
from classify import classify
from manifold import jacobian_rank
from mechanisms import EndEffector, Joint, Mechanism, configuration_space, home, kinematics_of

OFFSETS = (1.0, 1e3, 1e5, 1e6)


def moved_end_effector(mechanism, offset, output="position"):
    """The mechanism with its end-effector point moved `offset` along x on its link."""
    point = np.add(mechanism.end_effector.point, (offset, 0.0, 0.0))
    end_effector = EndEffector(mechanism.end_effector.link, tuple(float(value) for value in point), output)
    return Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, end_effector)


def test_rsur_cspace_rank_and_margin_do_not_depend_on_end_effector():
    """An RSUR with its end-effector point 1 … 1e6 away: one C-space rank, margin and verdict (1e-9 relative)."""
    base = rsur()
    decisions, lengths, scales = [], [], []
    for offset in OFFSETS:
        mechanism = moved_end_effector(base, offset)
        decisions.append(jacobian_rank(configuration_space(mechanism), home(mechanism)))
        lengths.append(mechanism.characteristic_length)
        scales.append(kinematics_of(mechanism).ambient.tangent_scales)
        report = classify(mechanism, home(mechanism))
        assert "cspace" not in report.kinds, (offset, report.kinds)
        assert report.cspace.rank == 6 and report.dof == 1, offset
    first = decisions[0]
    assert first.rank == 6
    for offset, decision, length, scale in zip(OFFSETS, decisions, lengths, scales):
        assert decision.rank == first.rank, offset
        np.testing.assert_allclose(decision.singular_values, first.singular_values, rtol=1e-9, atol=0)
        assert decision.margin[0] == pytest.approx(first.margin[0], rel=1e-9), offset
        assert decision.tolerance == pytest.approx(first.tolerance, rel=1e-9), offset
        assert length == lengths[0], offset
        np.testing.assert_array_equal(scale, scales[0])


def test_characteristic_length_is_the_joints_largest_link_diameter():
    """The RSUR's length: the largest distance between two joint points carried by one link (here B–C on the
    coupler, the end-effector on the coupler left out)."""
    mechanism = rsur()
    points = {joint.name: np.asarray(joint.point) for joint in mechanism.joints}
    diameters = [np.linalg.norm(points["A"] - points["B"]), np.linalg.norm(points["B"] - points["C"]),
                 np.linalg.norm(points["C"] - points["D"]), np.linalg.norm(points["D"] - points["A"])]
    assert mechanism.characteristic_length == pytest.approx(max(diameters), rel=1e-15)
    assert kinematics_of(mechanism).length == mechanism.characteristic_length


def _slotted(end_effector_point):
    """A planar P–R–P loop: no link carries two joint points (the ground only the rails, a and b one pin each)."""
    return Mechanism("slotted", "planar", [
        Joint("rail1", "P", ("ground", "a"), axis=(1.0, 0.0), actuated=True),
        Joint("pin", "R", ("a", "b"), point=(0.5, 0.5)),
        Joint("rail2", "P", ("b", "ground"), axis=(0.6, 0.8)),
    ], end_effector=EndEffector("a", end_effector_point, "position"))


def test_fallback_when_no_link_carries_two_joint_points():
    """No link carries two joint points: the length falls back to the points with the end-effector's (the
    rule before), then to 1."""
    mechanism = _slotted((2.5, 0.5))
    assert mechanism.characteristic_length == pytest.approx(2.0, rel=1e-15)
    assert kinematics_of(mechanism).length == mechanism.characteristic_length
    assert _slotted((0.5, 0.5)).characteristic_length == 1.0


def test_length_scales_with_the_unit():
    """Drawn in another unit of length, the joints' length scales with it (a verdict then does not move)."""
    mechanism = rsur()
    factor = 1e3
    scaled = Mechanism(mechanism.name, mechanism.space, [
        Joint(joint.name, joint.type, joint.links, point=tuple(factor * value for value in joint.point),
              axis=joint.axis, axes=joint.axes, actuated=joint.actuated) for joint in mechanism.joints
    ], end_effector=EndEffector("coupler", tuple(factor * value for value in mechanism.end_effector.point)))
    assert scaled.characteristic_length == pytest.approx(factor * mechanism.characteristic_length, rel=1e-12)


def test_joints_too_small_are_refused_whatever_the_end_effector():
    """Joints 1e-10 apart are refused as too small for the rank tolerances, an end-effector point 1 away (which
    made the length 1 before) or not: the length the rows take is the joints'."""
    from mechanisms.errors import MechanismError

    mechanism = rsur()
    joints = [Joint(joint.name, joint.type, joint.links, point=tuple(1e-10 * value for value in joint.point),
                    axis=joint.axis, axes=joint.axes, actuated=joint.actuated) for joint in mechanism.joints]
    for point in ((1.0, 0.0, 0.0), (1e-10, 0.0, 0.0)):
        with pytest.raises(MechanismError, match="the geometry is too small"):
            Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground,
                      EndEffector("coupler", point, "position"))


def test_two_pins_within_rounding_of_each_other_are_one_point_in_any_unit():
    """A review found the joints-only length taking two pins 1e-10 apart at coordinates of 1000 (rounding, by
    the package's own cut 1e-12 × the coordinates) as the length: L = 1e-10 in millimetres and the actuator rank
    1/1, but L = 0.002 and rank 0/0 in metres. They are one point: the end-effector point gives the length."""
    from classify import classify
    from mechanisms import EndEffector, Joint, Mechanism, home

    def slotted(delta, unit):
        x0 = 1000.0 * unit
        return Mechanism("slotted", "planar", [
            Joint("rail1", "P", ("ground", "a"), axis=(1.0, 0.0), actuated=True),
            Joint("pin", "R", ("a", "b"), point=(x0 + 0.5 * unit, x0 + 0.5 * unit)),
            Joint("pin2", "R", ("b", "c"), point=(x0 + 0.5 * unit, x0 + 0.5 * unit + delta * unit)),
            Joint("rail2", "P", ("c", "ground"), axis=(0.6, 0.8)),
        ], end_effector=EndEffector("a", (x0 + 2.5 * unit, x0 + 0.5 * unit), "position"))

    for delta in (0.0, 1e-10):
        for unit in (1.0, 1e-3):
            mechanism = slotted(delta, unit)
            assert mechanism.characteristic_length == pytest.approx(2.0 * unit, rel=1e-9)
            report = classify(mechanism, home(mechanism))
            assert (report.actuator.rank, report.actuator.expected_rank) == (0, 0)
