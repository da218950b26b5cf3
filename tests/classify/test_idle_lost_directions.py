"""Lost directions leave the idle freedoms out (Park & Kim 1999 §3: a kind's singular directions are ker G, ker J).

With idle freedoms (motions that move neither an actuator nor the end-effector: an SPS leg's spin) ker G and
ker J contain them at every configuration; two audits found the Gough–Stewart with SPS legs reporting 7 lost
actuator directions at Fichter's singularity (rank 5/6: one is lost) where the UPS platform reports 1, the real
one mixed with the six leg spins in an arbitrary basis. A kind now lists as many directions as it lost, the idle
directions (their limit from neighbours, as the second-order test's slice takes them) projected out.
"""

import math

import numpy as np
import pytest

from classify import classify
from mechanisms import Joint, Mechanism, home
from mechanisms.catalogue.gough_stewart import _collapsed_leg_pose, gough_stewart
from mechanisms.kinematics import end_effector_jacobian


def with_ball_legs(mechanism):
    """The platform with every U joint an S joint at the same point: six idle leg spins."""
    joints = [Joint(joint.name, "S", joint.links, point=joint.point, actuated=joint.actuated) if joint.type == "U"
              else joint for joint in mechanism.joints]
    return Mechanism(mechanism.name + "-sps", mechanism.space, joints, mechanism.ground, mechanism.end_effector)


@pytest.mark.parametrize("pose", [dict(rotation_z=math.pi / 2), _collapsed_leg_pose()], ids=["fichter", "eq84"])
def test_ball_legs_lose_the_directions_of_the_universal_legs(pose):
    universal = gough_stewart(**pose)
    balls = with_ball_legs(universal)
    first, second = classify(universal, home(universal)), classify(balls, home(balls))
    assert second.idle_freedoms == 6
    for kind in ("actuator", "end_effector"):
        one, other = getattr(first, kind), getattr(second, kind)
        assert (one.rank, one.expected_rank) == (other.rank, other.expected_rank)
        assert other.kernel.shape[1] == one.kernel.shape[1] == one.expected_rank - one.rank
        # the same platform motions: the end-effector twists of the lost directions span one space (where the
        # end-effector is regular: at eq. 84 it is singular along them too, and their twists vanish)
        spans = [end_effector_jacobian(mechanism, home(mechanism)) @ report_kind.kernel
                 for mechanism, report_kind in ((universal, one), (balls, other))]
        if one.kernel.shape[1] and kind == "actuator" and not first.end_effector.singular:
            bases = [np.linalg.svd(span, full_matrices=False)[0][:, :span.shape[1]] for span in spans]
            cosines = np.linalg.svd(bases[0].T @ bases[1], compute_uv=False)
            np.testing.assert_allclose(cosines, 1.0, atol=1e-6)


def test_an_architecture_singular_platform_with_ball_legs_is_degenerate_whatever_the_seed_and_frame():
    """Gosselin & Angeles 1990 eq. 87 (similar hexagons, legs parallel at the home): a 6-UPS is degenerate for
    every seed and base frame; with ball legs (six idle spins) the test on the slice transverse to them was
    undetermined for 3 of 8 seeds and with the base moved (Gauss–Newton converged too slowly on the slice's fibre).
    The slice's roots are transverse to the idle freedoms, and are now walked on M's fibre as well."""
    from scipy.spatial.transform import Rotation

    from mechanisms import move_base

    balls = with_ball_legs(gough_stewart(platform_radius=1.0, platform_angle=math.pi / 18, x=0.3, y=-0.2, z=1.0))
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = Rotation.from_rotvec([0.4, -0.7, 1.1]).as_matrix(), [3.0, -2.0, 5.0]
    for mechanism, seed in ((move_base(balls, pose), 0),):
        report = classify(mechanism, home(mechanism), rng=np.random.default_rng(seed))
        assert report.architecture_singular and report.idle_freedoms == 6
        assert report.degeneracy == "degenerate", (seed, report.second_order.reason)
