"""Random starts far from M reach it: the survey samples M globally (another description finds the same
ranks), and the grid's branch search finds other assembly branches.

Φ's rotation rows vanish at half-turns too, and Gauss-Newton from a random point of K ended there for
nearly every start of the survey (every one of 24 for the Gough-Stewart platform, the Eclipse, the 5-SPU
and the spherical 3-RRR), leaving the walk from home as the only sampling: whether the survey found the
largest ranks then hung on the description (found by an audit of the verdicts under joint orders and axis
flips). Random points are now projected onto the closing map first (:func:`mechanisms.kinematics.closing_space`),
there and in the branch search of the grids (:func:`classify.grid_continuation.assemble_branches`).
"""

import numpy as np
import pytest

from builders import rsur
from classify import classify
from manifold import sample_manifold
from mechanisms import Mechanism, catalogue, closes, configuration_space, flip_axis, home, kinematics_of


@pytest.mark.parametrize("name", ["gough-stewart", "eclipse", "5-spu", "spherical-3rrr", "five-bar"])
def test_random_points_of_k_reach_m(name):
    mechanism = catalogue.entry(name).mechanism()
    manifold = configuration_space(mechanism)
    start = home(mechanism)[None]
    points = sample_manifold(manifold, np.random.default_rng(3), start, random_count=24, walk_count=0)[1:]
    assert len(points) >= 20
    assert all(closes(mechanism, point) for point in points)


def test_random_points_of_k_reach_the_rsur_loop():
    """Capped Gauss-Newton on the closing map stalled or circled far from M for 13 of 48 random starts of this
    RSUR loop (residual ≈ 1.5 after 100 iterations); damped (Levenberg-Marquardt, manifold.project with
    `damped`), sample_manifold's random starts all reach M."""
    mechanism = rsur()
    manifold = configuration_space(mechanism)
    start = home(mechanism)[None]
    points = sample_manifold(manifold, np.random.default_rng(3), start, random_count=24, walk_count=0)[1:]
    assert len(points) == 24
    assert all(closes(mechanism, point) for point in points)


def flipped(mechanism, point, names):
    """The mechanism with the axes of `names` flipped, and `point` carried over (their coordinates negated)."""
    point = point.copy()
    for name in names:
        for part in kinematics_of(mechanism).point_parts[name]:
            point[part] *= -1.0
        mechanism = flip_axis(mechanism, name)
    return mechanism, point


def reordered(mechanism, order):
    return Mechanism(mechanism.name, mechanism.space, [mechanism.joints[index] for index in order],
                     mechanism.ground, mechanism.end_effector)


def test_the_folded_spherical_3rrr_is_an_end_effector_singularity_in_every_description():
    """Gosselin & Angeles 1990 §VI, every leg folded onto its motor axis (α₁ = α₂): near it M is a torus of leg
    spins that leaves the gripper fixed (J ≡ 0), elsewhere the gripper turns (rank 3). The walk from home stays
    on the torus; with three axes flipped, or 12 of 30 joint orders, the survey found rank 0 and called the
    configuration regular."""
    mechanism = catalogue.entry("spherical-3rrr").mechanism("section6_equal_alphas_folded")
    rng = np.random.default_rng(6)
    descriptions = [(mechanism, home(mechanism)), flipped(mechanism, home(mechanism), ("motor2", "wrist2", "motor3"))]
    for _ in range(4):
        other = reordered(mechanism, rng.permutation(len(mechanism.joints)))
        descriptions.append((other, home(other)))
    for described, point in descriptions:
        report = classify(described, point)
        assert report.kinds == ("end_effector",)
        assert (report.end_effector.rank, report.end_effector.expected_rank) == (0, 3)


def test_the_watt_six_bar_is_not_called_architecturally_singular_in_another_joint_order():
    """Watt six-bar eq. 41 (joints 2 and 4 superimposed): in the joint order below the survey found no
    configuration where the input moves and called the design architecturally singular."""
    mechanism = catalogue.entry("watt-six-bar").mechanism("eq41_joints_2_4_superimposed")
    for described in (mechanism, reordered(mechanism, [4, 2, 1, 3, 5, 0, 6])):
        report = classify(described, home(described))
        assert (report.kinds, report.degeneracy, report.moving_idle_freedoms) == (("actuator",), "degenerate", 0)


def test_the_grid_finds_other_assembly_branches_of_the_spherical_3rrr():
    """assemble_branches solves the loops from random values at a few grid points: on Φ every start of the
    spherical 3-RRR ended at a half-turn, and the grid had the start's branch only."""
    from classify.grid_continuation import assemble_branches

    mechanism = catalogue.entry("spherical-3rrr").mechanism()
    ambient = kinematics_of(mechanism).ambient
    held = [index for index, joint in enumerate(mechanism.joints) if joint.actuated][:2]
    values = np.linspace(-0.3, 0.3, 3)
    targets = []
    for first in values:
        for second in values:
            step = np.zeros(ambient.dim)
            step[held] = first, second
            targets.append(ambient.retract(home(mechanism), step))
    points, reached, _, solutions = assemble_branches(mechanism, home(mechanism), np.array(targets), (3, 3), held,
                                                      4, np.random.default_rng(0))
    assert solutions > 0 and len(points) == 4
    for branch, mask in zip(points, reached):
        assert mask.any() and all(closes(mechanism, point) for point in branch[mask])
