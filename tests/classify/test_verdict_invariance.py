"""Degeneracy verdicts do not hang on the sign or order an SVD returns.

Every degenerate and nondegenerate actuator singularity of the catalogue (and the architecture
singularity of Gosselin & Angeles 1990 eq. 87) keeps its verdict under 20 random changes of
representation each: the tangent basis rotated (T → TQ, Q orthogonal), the joints listed in another
order (another spanning tree and chord set), axis signs flipped, the base frame moved by a rigid
motion and, for mechanisms of one-coordinate joints, another home on the same M. The survey (largest
ranks on M, representation-invariant integers) is shared: the one every classification of the catalogue
mechanism uses (:func:`classify.survey_of`, shared with the other tests through
:func:`builders.catalogue_mechanism`); everything else is recomputed.
"""

import zlib

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.stats import ortho_group

import classify.classification as classification
import classify.second_order as second_order
from builders import catalogue_mechanism
from classify import classify, model_of, survey_of
from manifold import ProjectionError, project
from mechanisms import Mechanism, closes, configuration_space, flip_axis, home, kinematics_of, move_base
from mechanisms import rehome

REPRESENTATIONS = 20

#: (entry, configuration, degeneracy) at the catalogue's degenerate and nondegenerate configurations
CASES = [
    ("slider-crank", "fig3b_actuator", "nondegenerate"),
    ("slider-crank", "fig3d_dead_centre", "nondegenerate"),
    ("slider-crank", "eq17_constant_branch_slider_driven", "degenerate"),
    ("five-bar", "fig6a_distal_aligned", "nondegenerate"),
    ("five-bar", "fig6b_elbows_coincide", "degenerate"),
    ("five-bar", "fig13_combined", "nondegenerate"),
    ("five-bar", "sec34_elbows_coincide", "degenerate"),
    ("spherical-six-bar", "fig7_actuator", "nondegenerate"),
    ("eclipse", "fig10_actuator", "nondegenerate"),  # isolated at third order
    ("eclipse", "fig10_turned", "nondegenerate"),
    ("watt-six-bar", "eq39_d1_coupler_aligned_with_rocker", "nondegenerate"),
    ("watt-six-bar", "eq41_joints_2_4_superimposed", "degenerate"),
    ("planar-3rrr", "eq61_distal_links_concurrent", "nondegenerate"),
    ("planar-3rrr", "eq63_distal_links_parallel", "degenerate"),
    ("planar-3rrr", "eq64_elbows_at_centroid_turned", "degenerate"),
    ("spherical-3rrr", "eq68_distal_links_orthogonal", "nondegenerate"),
    ("spherical-3rrr", "section6_right_alphas_coplanar", "degenerate"),
    ("gough-stewart", "eq84_leg1_zero_length", "degenerate"),
    ("gough-stewart", "fichter_rotated_plus_90", "nondegenerate"),
    ("gough-stewart", "eq87_parallel_legs", "degenerate"),
    ("3-prr", "fig2_concurrent_at_centre", "nondegenerate"),
    ("3-prr", "fig2_parallel_legs", "degenerate"),
    ("hybrid", "eq25_distal_aligned", "nondegenerate"),
    ("hybrid", "eq25_elbows_coincide", "degenerate"),
    ("5-spu", "eq33_w_zero_locked", "nondegenerate"),
    ("5-spu", "eq33_second_factor_locked", "nondegenerate"),
    ("5-spu", "eq33_w_zero", "nondegenerate"),  # the free spin: an idle freedom of the tool output
]

ONE_COORDINATE = {"R", "P"}


def random_motion(space, rng):
    """A random element of the mechanism's group, shape=[n, n]."""
    rotation = Rotation.random(random_state=rng).as_matrix()
    if space == "planar":
        angle = rng.uniform(-np.pi, np.pi)
        return np.array([[np.cos(angle), -np.sin(angle), rng.normal()],
                         [np.sin(angle), np.cos(angle), rng.normal()], [0.0, 0.0, 1.0]])
    if space == "spherical":
        return rotation
    motion = np.eye(4)
    motion[:3, :3], motion[:3, 3] = rotation, rng.normal(size=3)
    return motion


def another_home(mechanism, rng):
    """(the mechanism rehomed at a configuration near home, the old home in the new description), or
    None: for one-coordinate joints the old home is minus the new home's values."""
    if any(joint.type not in ONE_COORDINATE for joint in mechanism.joints):
        return None
    space = kinematics_of(mechanism).ambient
    for _ in range(20):
        try:
            nearby = project(configuration_space(mechanism),
                             space.retract(home(mechanism), 0.1 * space.tangent_scales * rng.standard_normal(space.dim)))
        except ProjectionError:
            continue
        moved = rehome(mechanism, nearby)
        if closes(moved, -nearby):
            return moved, -nearby
    return None


def representation(mechanism, rng):
    """A random other description of the same mechanism at the same configuration: (mechanism, point)."""
    order = rng.permutation(len(mechanism.joints))
    mechanism = Mechanism(mechanism.name, mechanism.space, [mechanism.joints[i] for i in order],
                          mechanism.ground, mechanism.end_effector)
    for joint in mechanism.joints:
        if (joint.axis is not None or (joint.type == "R" and mechanism.space == "planar")) and rng.random() < 0.5:
            mechanism = flip_axis(mechanism, joint.name)
    mechanism = move_base(mechanism, random_motion(mechanism.space, rng))
    point = home(mechanism)
    if rng.random() < 0.5:
        moved = another_home(mechanism, rng)
        if moved is not None:
            mechanism, point = moved
    return mechanism, point


@pytest.fixture
def rotated_bases(monkeypatch):
    """Make every tangent basis of the classification and of the second-order test (its neighbours' bases) T·Q
    for a fresh random orthogonal Q."""
    rng = np.random.default_rng(7)
    original = classification.tangent_basis

    def rotated(manifold, point, **options):
        basis, decision = original(manifold, point, **options)
        if basis.shape[1] > 1:
            basis = basis @ ortho_group.rvs(basis.shape[1], random_state=rng)
        return basis, decision

    monkeypatch.setattr(classification, "tangent_basis", rotated)
    monkeypatch.setattr(second_order, "tangent_basis", rotated)


@pytest.mark.parametrize("name, configuration, degeneracy", CASES)
def test_the_verdict_survives_every_change_of_representation(name, configuration, degeneracy, rotated_bases):
    mechanism = catalogue_mechanism(name, configuration)
    shared = survey_of(model_of(mechanism))  # = survey(model, numpy.random.default_rng(0))
    rng = np.random.default_rng(zlib.crc32(f"{name}/{configuration}".encode()))
    reference = classify(mechanism, home(mechanism), survey=shared, rng=np.random.default_rng(0))
    assert reference.degeneracy == degeneracy
    for index in range(REPRESENTATIONS):
        other, point = representation(mechanism, rng)
        report = classify(other, point, survey=shared, rng=np.random.default_rng(index))
        assert (report.kinds, report.degeneracy, report.actuator.rank) == \
            (reference.kinds, reference.degeneracy, reference.actuator.rank), index
