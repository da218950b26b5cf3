"""Self-motion certificates: a near-miss curve of a nearly degenerate design is no self-motion.

A planar 3-RPR with its legs parallel, the third longer by a factor 1 + δ: an actuator singularity, and with
the slides locked legs 1 and 2 make a parallelogram, so the platform can only translate, and leg 3's length
then changes as |r| |δ + e^{iα}| − |r|(1 + δ): isolated in its fibre for δ ≠ 0 (Park & Kim 1999,
nondegenerate), a circle of translations for δ = 0 (degenerate). For δ = 1e-7 the continuation followed a
curve whose residual grows like t² (6e-11 at distance 0.11, under its 1e-10) and certified a self-motion.
"""

import numpy as np
import pytest

from classify import classify
from mechanisms import Joint, Mechanism, home


def parallel_legs(stretch):
    base, leg = ((0.0, 0.0), (4.0, 0.0), (1.0, 3.0)), np.array([1.5, 2.0])
    joints = []
    for index, (anchor, vector) in enumerate(zip(base, (leg, leg, leg * (1.0 + stretch))), 1):
        anchor = np.array(anchor)
        axis = tuple(vector / np.linalg.norm(vector))
        joints += [Joint(f"R{index}a", "R", ("ground", f"leg{index}a"), point=tuple(anchor)),
                   Joint(f"P{index}", "P", (f"leg{index}a", f"leg{index}b"), axis=axis, actuated=True),
                   Joint(f"R{index}b", "R", (f"leg{index}b", "platform"), point=tuple(anchor + vector))]
    return Mechanism("3-RPR, legs parallel", "planar", joints)


@pytest.mark.parametrize("stretch", [1e-5, 1e-7, 1e-9])
def test_a_nearly_degenerate_design_is_not_certified_degenerate(stretch):
    mechanism = parallel_legs(stretch)
    report = classify(mechanism, home(mechanism))
    assert report.kinds == ("actuator",)
    assert report.degeneracy in ("nondegenerate", "undetermined")
    assert report.second_order.self_motion is None


def test_a_nearly_degenerate_design_moved_far_away_is_not_certified_degenerate():
    """δ = 1e-9 sat at the certificate's cut (residual 3e-13 at distance 0.1, cut 1e-13 √9): with the base turned
    and moved 1e5 lengths away, rounding took the near-miss curve under it, certified (found by an audit)."""
    from mechanisms import move_base

    mechanism = parallel_legs(1e-9)
    frame = np.eye(3)
    frame[:2, :2] = [[-0.8510734406421797, 0.525046663291447], [-0.525046663291447, -0.8510734406421797]]
    direction = np.array([415574.10338915343, 85429.29604240757])
    frame[:2, 2] = 1e5 * mechanism.characteristic_length * direction / np.linalg.norm(direction)
    moved = move_base(mechanism, frame)
    report = classify(moved, home(moved))
    assert report.kinds == ("actuator",) and report.second_order.self_motion is None


def test_the_degenerate_design_is_certified_with_a_residual_at_rounding():
    mechanism = parallel_legs(0.0)
    report = classify(mechanism, home(mechanism))
    assert report.degeneracy == "degenerate"
    motion = report.second_order.self_motion
    assert motion.distance >= 0.1 and motion.largest_residual < 1e-15


@pytest.mark.parametrize("stretch", [1e-7, 1e-9])
@pytest.mark.parametrize("offset", [1e-11, 5e-10])
def test_a_point_given_off_m_does_not_loosen_the_certificate(stretch, offset):
    """A configuration accepted within the closure tolerance (1e-9) but off M: its own residual allowed the
    near-miss curve (the cut was 10 ‖Φ(p̄)‖); the walk now starts from the point of M nearest it."""
    from classify import model_of

    mechanism = parallel_legs(stretch)
    point = home(mechanism)
    jacobian = model_of(mechanism).manifold.constraint_jacobian(point)
    shift = np.linalg.pinv(jacobian) @ np.ones(len(jacobian))
    point = point + offset * shift / np.linalg.norm(jacobian @ shift)
    report = classify(mechanism, point)
    assert report.kinds == ("actuator",) and report.second_order.self_motion is None
