"""Singularity loci (:mod:`classify.loci`) against the closed forms of Chablat, Wenger & Angeles 1998 and
Park & Kim 1999.

* Five-bar, actuator locus: the distal links aligned, θ3 − θ4 = kπ (Chablat, Wenger & Angeles 1998 eq. 9;
  Park & Kim 1999 Fig. 6a); end-effector loci: a leg stretched or folded, θ3 − θ1 = kπ or θ4 − θ2 = kπ
  (eqs. 3c, 10–13). Checked at every traced point to 1e-6 (the refinement reaches ‖(Φ, s)‖ ≤ 1e-11).
* Slider-crank with crank = coupler (Park & Kim 1999 Fig. 3a): two branches of M crossing at the C-space
  singularities θ = ±π/2 with the slider at the crank's pivot; the dead centres (Fig. 3c) on the moving branch.
"""

import numpy as np
import pytest

from classify import classify, classify_many, model_of
from classify.figures.drawing import joint_places
from classify.loci import TOLERANCE, locus_coordinates, sign_functions, trace_loci
from mechanisms import configuration
from tests.builders import catalogue_mechanism

#: closed forms hold to this at every traced point (the issue asked for 1e-6; the points are refined to
#: loci.TOLERANCE = 1e-11 and the closed forms follow to about 2e-11: a 50× margin)
CLOSED_FORM = 1e-9


def _sine(first, second):
    """|sin| of the angle between 2-D vectors, shape=[n]."""
    cross = first[:, 0] * second[:, 1] - first[:, 1] * second[:, 0]
    return np.abs(cross) / (np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1))


@pytest.fixture(scope="module")
def five_bar():
    mechanism = catalogue_mechanism("five-bar")
    start = configuration(mechanism, {}).point
    loci = trace_loci(mechanism, start, counts=(8, 8), kinds=("actuator", "end_effector", "cspace"))
    return mechanism, start, loci


def test_five_bar_actuator_locus_is_distal_alignment(five_bar):
    mechanism, _, loci = five_bar
    pieces = [piece for piece in loci.pieces if piece.kind == "actuator"]
    assert pieces and all(piece.closed for piece in pieces)
    points = np.concatenate([piece.points for piece in pieces])
    places = joint_places(mechanism, points)
    assert np.max(_sine(places["P"] - places["C"], places["P"] - places["D"])) < CLOSED_FORM


def test_five_bar_end_effector_loci_are_legs_stretched_or_folded(five_bar):
    mechanism, _, loci = five_bar
    pieces = [piece for piece in loci.pieces if piece.kind == "end_effector"]
    assert len(pieces) >= 2 and all(piece.closed for piece in pieces)
    points = np.concatenate([piece.points for piece in pieces])
    places = joint_places(mechanism, points)
    left = _sine(places["C"] - places["A"], places["P"] - places["C"])
    right = _sine(places["D"] - places["B"], places["P"] - places["D"])
    assert np.max(np.minimum(left, right)) < CLOSED_FORM
    assert np.any(left < CLOSED_FORM) and np.any(right < CLOSED_FORM)  # both legs' loci were found


def test_five_bar_points_are_on_the_curves_and_confirmed(five_bar):
    mechanism, _, loci = five_bar
    model = model_of(mechanism)
    for piece in loci.pieces:
        assert np.all(piece.residuals <= TOLERANCE)
        result = classify_many(model, piece.points)
        assert result.kind(piece.kind).all()
    sample = loci.pieces[0]
    for index in (0, len(sample.points) // 2):  # the single classification agrees
        assert sample.kind in classify(mechanism, sample.points[index]).kinds
    # by default a turn of each actuated angle around the start (displacements 0 at the home), 8 × 8 points
    assert loci.coverage["grid"] == {"A": pytest.approx([-np.pi, np.pi, 8], abs=1e-12),
                                     "B": pytest.approx([-np.pi, np.pi, 8], abs=1e-12)}
    assert loci.coverage["unconfirmed"] == {"actuator": 0, "end_effector": 0}


def test_five_bar_catalogue_eq9_point_lies_on_the_actuator_locus(five_bar):
    """The catalogue's eq9_distal_aligned configuration (Chablat, Wenger & Angeles 1998 eq. 9, θ1 = 1.2) is
    within one tracing step of the traced actuator locus, in the absolute input angles (θ1, θ2)."""
    mechanism, start, loci = five_bar
    target = catalogue_mechanism("five-bar", "eq9_distal_aligned")
    aligned = joint_places(target, configuration(target, {}).point)
    points = np.concatenate([piece.points for piece in loci.pieces if piece.kind == "actuator"])
    places = joint_places(mechanism, points)

    def angles(places, index=slice(None)):
        return np.stack([np.arctan2(*(places["C"] - places["A"])[index, ::-1].T),
                         np.arctan2(*(places["D"] - places["B"])[index, ::-1].T)], axis=-1)

    differences = np.angle(np.exp(1j * (angles(places) - angles(aligned, 0))))
    assert np.min(np.linalg.norm(differences, axis=1)) < loci.coverage["step"]


def test_sign_functions_batched_equal_single(five_bar):
    mechanism, start, loci = five_bar
    functions, refused = sign_functions(model_of(mechanism), start)
    assert set(functions) == {"actuator", "end_effector"} and not refused
    points = loci.pieces[0].points[:5]
    for function in functions.values():
        batched = function(points)
        single = np.array([function(point[None])[0] for point in points])
        np.testing.assert_allclose(batched, single, rtol=1e-12, atol=1e-15)


def test_locus_coordinates_end_effector_and_joints(five_bar):
    mechanism, start, loci = five_bar
    values, names = locus_coordinates(mechanism, start[None], "end-effector")
    assert names == ("x", "y") and np.allclose(values[0], mechanism.end_effector.point)
    values, names = locus_coordinates(mechanism, start[None], [0, 4])
    assert names == ("A", "B") and np.allclose(values, 0)


@pytest.fixture(scope="module")
def slider_crank():
    mechanism = catalogue_mechanism("slider-crank", "fig3a_self_intersection")
    start = configuration(mechanism, {}).point
    return mechanism, trace_loci(mechanism, start, kinds=("actuator", "end_effector", "cspace"))


def test_slider_crank_two_branches_meet_at_fig3a(slider_crank):
    """Park & Kim 1999 Fig. 3a: crank = coupler, two closed branches of M (the slider moving, x = 2 cos θ, and
    the slider still at the pivot, x = 0) crossing where θ = ±π/2."""
    mechanism, loci = slider_crank
    assert len(loci.branches) == 2 and all(branch.closed for branch in loci.branches)
    slides = [locus_coordinates(mechanism, branch.points, [3])[0][:, 0] for branch in loci.branches]
    home_slide = mechanism.joint("wrist").point[0]  # the slider's home position (0 at θ = π/2)
    still = [np.ptp(slide) < 1e-8 for slide in slides]
    assert sorted(still) == [False, True]
    points = [piece.points[0] for piece in loci.pieces if piece.kind == "cspace"]
    assert len(points) == 2
    crank = locus_coordinates(mechanism, np.array(points), [0])[0][:, 0]  # displacement from θ = π/2
    np.testing.assert_allclose(np.sort(np.cos(crank)), [-1.0, 1.0], atol=1e-9)  # θ = −π/2 and π/2
    slide = locus_coordinates(mechanism, np.array(points), [3])[0][:, 0]
    np.testing.assert_allclose(slide + home_slide, 0.0, atol=1e-6)
    for point in points:
        assert "cspace" in classify(mechanism, point).kinds


def test_slider_crank_dead_centres_are_end_effector_points(slider_crank):
    """Park & Kim 1999 Fig. 3c: the dead centres, slider at ±(crank + coupler) = ±2, are end-effector singular."""
    mechanism, loci = slider_crank
    points = np.array([piece.points[0] for piece in loci.pieces if piece.kind == "end_effector"])
    slide = locus_coordinates(mechanism, points, [3])[0][:, 0]
    for dead_centre in (2.0, -2.0):
        assert np.min(np.abs(slide - dead_centre)) < 1e-6
    assert loci.coverage["not_traced"] == {}
    assert "actuator" in loci.coverage["pieces"]


def test_more_than_three_dof_is_refused():
    mechanism = catalogue_mechanism("gough-stewart")
    with pytest.raises(ValueError, match="1-, 2- and 3-dof"):
        trace_loci(mechanism, configuration(mechanism, {}).point)
