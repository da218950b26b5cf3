"""C-space singularities searched for deliberately (:func:`classify.loci.search_cspace`: Gauss–Newton on
(Φ, σ_r) from seeds), not only where a traced actuator or end-effector locus passes through one.

* Slider-crank with crank = coupler (Park & Kim 1999 Fig. 3a): from points of M alone, no sign function, the
  two C-space singularities θ = ±π/2 with the slider at the crank's pivot.
* Five-bar of Park & Kim 1999's design (base 2, links 1): the C-space singularities are the configurations with
  all five joint centres on one line (Park & Kim 1999 Fig. 1); the search from a grid's local minima of σ_r
  finds such configurations, each one of the catalogue's Fig. 1 configurations.
"""

import numpy as np
import pytest

from classify import classify, model_of, survey_of
from classify.figures.drawing import joint_places
from classify.loci import CSPACE_TOLERANCE, cspace_function, search_cspace, trace_loci
from manifold import sample_manifold
from mechanisms import configuration
from tests.builders import catalogue_mechanism

#: closed forms hold to this at every point found (found to CSPACE_TOLERANCE = 1e-8: a 100× margin)
CLOSED_FORM = 1e-6
#: Park & Kim 1999's five-bar (Fig. 1): ‖AB‖ = 2, every link 1
PARK_KIM = {"base": 2.0, "proximal": 1.0, "distal": 1.0}


def test_slider_crank_fig3a_points_found_from_samples_of_m():
    mechanism = catalogue_mechanism("slider-crank", "fig3a_self_intersection")
    model = model_of(mechanism)
    survey = survey_of(model)
    start = configuration(mechanism, {}).point
    samples = sample_manifold(model.manifold, np.random.default_rng(0), start[None], random_count=12,
                              walk_count=12)[1:]  # not the start itself: the start is a Fig. 3a point
    value, _ = cspace_function(model, survey.constraint_rank)
    assert np.min(value(samples)) > 1e-3  # no seed is on a singularity already
    points, residuals = search_cspace(model, survey, samples, 0.05)
    assert len(points) == 2 and np.all(residuals <= CSPACE_TOLERANCE)
    places = joint_places(mechanism, points)
    crank = places["pin"] - places["crank"]
    np.testing.assert_allclose(np.abs(crank[:, 1]) / np.linalg.norm(crank, axis=1), 1.0, atol=CLOSED_FORM)
    np.testing.assert_allclose(places["wrist"][:, :2], places["crank"][:, :2], atol=CLOSED_FORM)
    for point in points:
        assert "cspace" in classify(mechanism, point).kinds


def test_cspace_function_batched_equals_single():
    mechanism = catalogue_mechanism("five-bar", **PARK_KIM, theta1=1.2, theta2=1.9)
    model = model_of(mechanism)
    value, gradient = cspace_function(model, survey_of(model).constraint_rank)
    points = sample_manifold(model.manifold, np.random.default_rng(1), configuration(mechanism, {}).point[None],
                             random_count=3, walk_count=3)[:4]
    np.testing.assert_allclose(value(points), [value(point[None])[0] for point in points], rtol=1e-12)
    np.testing.assert_allclose(gradient(points), np.concatenate([gradient(point[None]) for point in points]),
                               rtol=1e-9, atol=1e-12)


@pytest.fixture(scope="module")
def five_bar_search():
    mechanism = catalogue_mechanism("five-bar", **PARK_KIM, theta1=1.2, theta2=1.9)
    loci = trace_loci(mechanism, configuration(mechanism, {}).point, counts=(6, 6), kinds=("cspace",))
    return mechanism, loci


def test_five_bar_cspace_points_are_park_kim_fig1(five_bar_search):
    mechanism, loci = five_bar_search
    assert loci.coverage["cspace_search"]["confirmed"] >= 3
    points = np.concatenate([piece.points for piece in loci.pieces if piece.kind == "cspace"])
    assert len(points) >= 3
    places = joint_places(mechanism, points)
    names = ("A", "C", "P", "D", "B")
    line = places["B"] - places["A"]
    for name in names:  # every joint centre on the line AB
        offset = places[name] - places["A"]
        cross = offset[:, 0] * line[:, 1] - offset[:, 1] * line[:, 0]
        assert np.max(np.abs(cross) / np.linalg.norm(line, axis=1)) < CLOSED_FORM
    figure1 = []
    for name in ("fig1a_collinear", "fig1b_collinear", "fig1c_collinear", "fig1d_collinear"):
        target = catalogue_mechanism("five-bar", name)
        places_there = joint_places(target, configuration(target, {}).point[None])
        figure1.append(np.concatenate([places_there[joint][0] for joint in names]))
    found = np.stack([np.concatenate([places[joint][index] for joint in names]) for index in range(len(points))])
    distances = np.linalg.norm(found[:, None] - np.array(figure1)[None], axis=-1)
    assert np.all(distances.min(axis=1) < CLOSED_FORM)  # each point is one of Fig. 1's
    assert len(set(distances.argmin(axis=1).tolist())) == len(points)  # and no two are the same
    for point in points:
        assert "cspace" in classify(mechanism, point).kinds


def test_redundantly_actuated_five_bar_actuator_points_are_coincident_elbows():
    """The five-bar driven at A, B and P (three inputs, two dof): with every input still it moves only when
    the elbows C and D coincide (the two free joints then turn together, as Park & Kim 1999 Fig. 6b and
    Chablat, Wenger & Angeles 1998 Sec. 3.4 describe for the two-input five-bar). The distal links aligned
    (eq. 9), an actuator singularity of the two-input five-bar, is none here."""
    import dataclasses

    from mechanisms import Mechanism

    base = catalogue_mechanism("five-bar")
    joints = [dataclasses.replace(joint, actuated=joint.name in ("A", "B", "P")) for joint in base.joints]
    mechanism = Mechanism("five-bar-driven-at-p", base.space, joints, end_effector=base.end_effector)
    aligned = catalogue_mechanism("five-bar", "eq9_distal_aligned")
    assert "actuator" not in classify(mechanism, configuration(aligned, {}).point).kinds
    loci = trace_loci(mechanism, configuration(mechanism, {}).point, columns=[0, 4], counts=(8, 8),
                      kinds=("actuator",))
    assert "searched for as points" in loci.coverage["not_traced"]["actuator"]
    points = np.concatenate([piece.points for piece in loci.pieces])
    assert len(points) >= 2 and loci.coverage["actuator_search"]["confirmed"] == len(points)
    places = joint_places(mechanism, points)
    assert np.max(np.linalg.norm(places["C"] - places["D"], axis=1)) < CLOSED_FORM
    for point in points[:2]:
        assert "actuator" in classify(mechanism, point).kinds
