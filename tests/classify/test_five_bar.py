"""Planar five-bar: Park & Kim (1999) eq. (8), Figs. 1, 6a, 6b, 13.

Design of Figs. 1 and 6: base 2, proximal and distal links 1, J1 and J5 actuated, end-effector
at the middle joint J3."""

import numpy as np
import pytest

from builders import five_bar, five_bar_eq8, five_bar_positions, shared_mechanism
from classify import classify
from mechanisms import home

P = lambda x, y: (float(x), float(y))  # noqa: E731

CONFIGURATIONS = {
    "regular": five_bar_positions(np.radians(75), np.radians(115)),
    "regular elbow down": five_bar_positions(np.radians(60), np.radians(150), elbow=-1),
    "fig1a": [P(0, 0), P(1, 0), P(2, 0), P(3, 0), P(2, 0)],
    "fig1b": [P(0, 0), P(-1, 0), P(0, 0), P(1, 0), P(2, 0)],
    "fig1c": [P(0, 0), P(1, 0), P(0, 0), P(1, 0), P(2, 0)],
    "fig1d": [P(0, 0), P(1, 0), P(2, 0), P(1, 0), P(2, 0)],
    "fig6a": [P(0, 0), P(0, 1), P(1, 1), P(2, 1), P(2, 0)],
    "fig6b": [P(0, 0), P(1, 0), P(1, 1), P(1, 0), P(2, 0)],
    # Fig. 13 (another design): the left arm stretched and the distal links aligned
    "fig13": [P(0, 0), P(0, 1), P(0, 2), P(0, 3), P(2, 3)],
}
EXPECTED = {
    "regular": (), "regular elbow down": (),
    "fig1a": ("cspace",), "fig1b": ("cspace",), "fig1c": ("cspace",), "fig1d": ("cspace",),
    "fig6a": ("actuator",), "fig6b": ("actuator",), "fig13": ("actuator", "end_effector"),
}


def classified(points, **options):
    """The classification at home of the five-bar at `points` (its model and survey shared by the tests
    that build the same five-bar, :func:`builders.shared_mechanism`)."""
    mechanism = shared_mechanism(five_bar(points, **options))
    return classify(mechanism, home(mechanism), rng=np.random.default_rng(0))


@pytest.mark.parametrize("name", sorted(CONFIGURATIONS))
def test_kinds_of_the_papers_configurations(name):
    report = classified(CONFIGURATIONS[name])
    kinds = tuple(kind for kind in report.kinds if kind != "end_effector" or "cspace" not in report.kinds)
    assert kinds == EXPECTED[name]
    assert report.dof == 2


@pytest.mark.parametrize("name", ["fig1a", "fig1b", "fig1c", "fig1d"])
def test_fig1_collinear_joints_drop_the_rank_of_the_constraint(name):
    report = classified(CONFIGURATIONS[name])
    assert report.cspace.rank == 2 and report.cspace.expected_rank == 3
    assert report.to_dict()["actuator"]["on_kernel_of_constraint"] is True


def test_fig6a_distal_links_aligned_is_nondegenerate():
    report = classified(CONFIGURATIONS["fig6a"])
    assert report.actuator.rank == 1 and report.actuator.expected_rank == 2
    assert report.degeneracy == "nondegenerate"


def test_fig6b_coincident_elbows_is_degenerate_with_the_middle_links_free():
    report = classified(CONFIGURATIONS["fig6b"])
    assert report.degeneracy == "degenerate"
    direction = report.to_dict()["actuator"]["second_order"]["self_motion"]["direction"]
    assert set(direction) == {"J2", "J4"}  # the distal links turn about the overlapping elbows


def test_fig13_combined_actuator_and_end_effector():
    report = classified(CONFIGURATIONS["fig13"])
    assert report.kinds == ("actuator", "end_effector")
    assert report.degeneracy == "nondegenerate"


def test_redundant_actuation_removes_the_fig6a_singularity():
    """Park & Kim Section 3: adding an actuator (here J2) removes the actuator singularity."""
    report = classified(CONFIGURATIONS["fig6a"], actuated=("J1", "J2", "J5"))
    assert report.kinds == ()
    assert report.actuator.rank == 2 and report.actuator.expected_rank == 2


def test_moving_an_actuator_changes_the_singularity():
    """With J1 and J4 driven, Fig. 6a is no longer singular (actuator placement matters)."""
    assert classified(CONFIGURATIONS["fig6a"], actuated=("J1", "J4")).kinds == ()


@pytest.mark.parametrize("name", sorted(CONFIGURATIONS))
def test_joint_graph_and_eq8_agree(name):
    """The five-bar written as eq. (8) (an implicit manifold in T⁵ with E = diag(1,0,0,0,1)) and
    as a joint graph give the same kinds, ranks and proper values."""
    points = CONFIGURATIONS[name]
    graph = classified(points)
    model, x = five_bar_eq8(points)
    implicit = classify(model, x, rng=np.random.default_rng(0))
    assert implicit.kinds == graph.kinds
    assert implicit.degeneracy == graph.degeneracy
    for kind in ("cspace", "actuator", "end_effector"):
        ours, theirs = getattr(graph, kind), getattr(implicit, kind)
        assert (ours.rank, ours.expected_rank) == (theirs.rank, theirs.expected_rank), kind
    assert (graph.manipulability is None) == (implicit.manipulability is None)
    if graph.manipulability is not None:
        np.testing.assert_allclose(implicit.manipulability.eigenvalues, graph.manipulability.eigenvalues,
                                   rtol=1e-9)
        np.testing.assert_allclose(implicit.manipulability.volume, graph.manipulability.volume, rtol=1e-9)
