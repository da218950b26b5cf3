"""Singularity loci from a singular start, a branch of M singular everywhere, and a grid on several assembly
branches (:mod:`classify.loci`, :mod:`classify.grid_continuation`).

* Slider-crank (Park & Kim 1999 Fig. 3b): started at the actuator singularity θ = π/6 of that design (crank
  R = 2, coupler l = 1: R sin θ = l, the coupler perpendicular to the slide), the start itself is one of the
  four actuator points (θ = ±π/6 and π ± π/6, two on each closed curve of M), as when started from θ = 0.3.
* Five-bar started at an actuator singularity (Chablat, Wenger & Angeles 1998 eq. 9): the grid continues from
  a regular neighbour and finds what a regular start finds. Two assembly branches of the grid on Park & Kim
  1999 Fig. 1's design find its four collinear C-space singularities.
* Slider-crank with crank = coupler (Park & Kim 1999 Fig. 3a; Gosselin & Angeles 1990 eq. 17, the branch on
  which the output is constant): the branch with the slider still at the crank's pivot is end-effector singular
  at every point, reported as one whole-branch piece, not as isolated points.
"""

import numpy as np
import pytest

from classify import classify_many, model_of
from classify.loci import ZERO_TOLERANCE, locus_coordinates, sign_magnitudes, trace_loci
from mechanisms import configuration
from tests.builders import catalogue_mechanism


def _actuator_crank_angles(mechanism, loci):
    points = np.concatenate([piece.points for piece in loci.pieces if piece.kind == "actuator"])
    return np.sort(locus_coordinates(mechanism, points, [0])[0][:, 0])


def test_slider_crank_started_at_its_actuator_singularity_finds_it():
    """Park & Kim 1999 Fig. 3b: the start (θ = π/6, displacement 0 from it) is among the actuator points, and the
    points are those found from a regular start (θ = 0.3)."""
    mechanism = catalogue_mechanism("slider-crank", "fig3b_actuator")
    start = configuration(mechanism, {}).point
    found = _actuator_crank_angles(mechanism, trace_loci(mechanism, start, kinds=("actuator",)))
    assert len(found) == 4
    assert np.min(np.abs(found)) < 1e-9  # the start itself
    other = catalogue_mechanism("slider-crank", theta=0.3)  # the same design, home at θ = 0.3
    expected = _actuator_crank_angles(other, trace_loci(other, configuration(other, {}).point, kinds=("actuator",)))
    np.testing.assert_allclose(np.sort(np.angle(np.exp(1j * (found + np.pi / 6)))),
                               np.sort(np.angle(np.exp(1j * (expected + 0.3)))), atol=1e-6)


@pytest.fixture(scope="module", params=["fig3a_self_intersection", "eq17_constant_branch"])
def equal_links(request):
    mechanism = catalogue_mechanism("slider-crank", request.param)
    start = configuration(mechanism, {}).point
    return mechanism, trace_loci(mechanism, start, kinds=("actuator", "end_effector"))


def test_branch_singular_everywhere_is_one_whole_branch_piece(equal_links):
    """Crank = coupler: the branch x = 0 (the slider at the crank's pivot) is one end-effector piece flagged
    whole_branch, its points classified end-effector singular, its sign function below the tolerance everywhere
    (the margin in the coverage); the dead centres x = ±2 (Park & Kim 1999 Figs. 3c, 3d) stay isolated points."""
    mechanism, loci = equal_links
    end_effector = [piece for piece in loci.pieces if piece.kind == "end_effector"]
    whole = [piece for piece in end_effector if piece.whole_branch]
    assert len(whole) == 1
    piece = whole[0]
    assert piece.closed and len(piece.points) > 20
    home_slide = mechanism.joint("wrist").point[0]
    slide = locus_coordinates(mechanism, piece.points, [3])[0][:, 0] + home_slide
    np.testing.assert_allclose(slide, 0.0, atol=1e-9)
    crank = locus_coordinates(mechanism, piece.points, [0])[0][:, 0]
    assert np.ptp(np.unwrap(crank)) > 6.0  # the crank goes round the whole branch
    assert classify_many(model_of(mechanism), piece.points).kind("end_effector").all()
    isolated = [piece for piece in end_effector if not piece.whole_branch]
    slides = np.sort([locus_coordinates(mechanism, piece.points, [3])[0][0, 0] + home_slide for piece in isolated])
    np.testing.assert_allclose(slides, [-2.0, 2.0], atol=1e-6)
    (record,) = loci.coverage["whole_branch"]
    assert record["kind"] == "end_effector" and record["largest"] < record["tolerance"] == ZERO_TOLERANCE


def test_the_whole_branch_piece_does_not_depend_on_the_base_frame():
    """Fig. 3a's home is where the slider-crank's two branches cross: a trace started there leaves along an
    arbitrary direction of the 2-D null space, and with the base turned 0.7 rad and moved 30 lengths the branch
    x = 0 was traced from the home, split there (the crossing is C-space singular, not confirmed end-effector
    singular) and no longer closed (found by an audit). Crossing seeds now come last."""
    from mechanisms import move_base

    mechanism = catalogue_mechanism("slider-crank", "fig3a_self_intersection")
    length = mechanism.characteristic_length
    frame = np.array([[np.cos(0.7), -np.sin(0.7), 30 * length], [np.sin(0.7), np.cos(0.7), -30 * length],
                      [0.0, 0.0, 1.0]])
    pieces = []
    for each in (mechanism, move_base(mechanism, frame)):
        loci = trace_loci(each, configuration(each, {}).point, kinds=("actuator", "end_effector"))
        pieces.append(sorted((piece.kind, piece.closed, piece.whole_branch, len(piece.points))
                             for piece in loci.pieces))
    assert [piece[:3] for piece in pieces[0]] == [piece[:3] for piece in pieces[1]]
    assert ("end_effector", True, True) in [piece[:3] for piece in pieces[1]]
    whole = [[piece[3] for piece in each if piece[2]] for each in pieces]  # the same curve, stepped alike
    assert len(whole[0]) == len(whole[1]) == 1 and abs(whole[0][0] - whole[1][0]) <= 2


def test_sign_magnitudes_are_relative_and_batched(equal_links):
    mechanism, loci = equal_links
    model = model_of(mechanism)
    branch = loci.branches[0].points[:6]
    for magnitude in sign_magnitudes(model, branch[0]).values():
        values = magnitude(branch)
        assert np.all((values >= 0) & (values <= 1 + 1e-12))
        np.testing.assert_allclose(values, [magnitude(point[None])[0] for point in branch], rtol=1e-12, atol=1e-15)


def test_whole_branch_is_drawn_along_the_branch(equal_links):
    from classify.figures.loci import draw_cspace_map

    mechanism, loci = equal_links
    axes = draw_cspace_map(mechanism, loci, [0, 3]).axes[0]
    whole = [line for line in axes.get_lines() if (line.get_gid() or "").endswith(":whole-branch")]
    assert len(whole) == 1 and whole[0].get_linestyle() == "--"
    piece = next(piece for piece in loci.pieces if piece.whole_branch)
    assert len(whole[0].get_xdata()) >= len(piece.points) + 1  # closed: back to its first point
    assert "end-effector locus: a whole branch" in axes.get_legend_handles_labels()[1]


def _sine(first, second):
    cross = first[:, 0] * second[:, 1] - first[:, 1] * second[:, 0]
    return np.abs(cross) / (np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1))


def _five_bar_loci(configuration_name):
    mechanism = catalogue_mechanism("five-bar", configuration_name)
    start = configuration(mechanism, {}).point
    return mechanism, trace_loci(mechanism, start, counts=(8, 8), kinds=("actuator", "end_effector"))


def test_five_bar_grid_from_an_actuator_singular_start():
    """Started at the catalogue's eq9_distal_aligned configuration (Chablat, Wenger & Angeles 1998 eq. 9: distal
    links aligned, an actuator singularity), the grid starts from a regular neighbour on M (said in the coverage)
    and finds the loci a regular start finds: the same number of pieces, on the same closed forms (eq. 9; the legs
    stretched or folded, eqs. 3c) to 1e-6."""
    from classify.figures.drawing import joint_places

    mechanism, loci = _five_bar_loci("eq9_distal_aligned")
    _, regular = _five_bar_loci(None)
    assert loci.coverage["reached"] > 0
    start = loci.coverage["start"]
    assert start["singular"] and 0 < start["moved"] <= 0.2 and start["margin"] > 0
    assert not regular.coverage["start"]["singular"]
    for kind in ("actuator", "end_effector"):
        assert loci.coverage["pieces"][kind] == regular.coverage["pieces"][kind] > 0
    places = joint_places(mechanism, np.concatenate([p.points for p in loci.pieces if p.kind == "actuator"]))
    assert np.max(_sine(places["P"] - places["C"], places["P"] - places["D"])) < 1e-6
    places = joint_places(mechanism, np.concatenate([p.points for p in loci.pieces if p.kind == "end_effector"]))
    left = _sine(places["C"] - places["A"], places["P"] - places["C"])
    right = _sine(places["D"] - places["B"], places["P"] - places["D"])
    assert np.max(np.minimum(left, right)) < 1e-6


@pytest.fixture(scope="module")
def five_bar_branches():
    """Park & Kim 1999 Fig. 1's design (base 2, links 1), on two assembly branches of a 12 × 12 grid."""
    mechanism = catalogue_mechanism("five-bar", "fig1a_collinear")
    start = configuration(mechanism, {}).point
    loci = trace_loci(mechanism, start, counts=(12, 12), kinds=("cspace",), assembly_branches=2,
                      rng=np.random.default_rng(0))
    return mechanism, loci


def test_five_bar_fig1_collinear_cspace_points(five_bar_branches):
    """Park & Kim 1999 Fig. 1 (a)–(d): the C-space singularities of the five-bar with base 2 and links 1 are its
    four configurations with every link on the base line: (C, D, P) on the x-axis at x = (−1, 1, 0), (1, 3, 2),
    (1, 1, 2) and (1, 1, 0). The last is on the other assembly branch of the grid (the same inputs as the third)."""
    from classify.figures.drawing import joint_places

    mechanism, loci = five_bar_branches
    assert {piece.kind for piece in loci.pieces} == {"cspace"}
    places = joint_places(mechanism, np.concatenate([piece.points for piece in loci.pieces]))
    for name in "CDP":
        np.testing.assert_allclose(places[name][:, 1], 0.0, atol=1e-6)
    found = sorted(tuple(np.round([places["C"][i, 0], places["D"][i, 0], places["P"][i, 0]], 6) + 0.0)
                   for i in range(len(loci.pieces)))
    assert found == [(-1.0, 1.0, 0.0), (1.0, 1.0, 0.0), (1.0, 1.0, 2.0), (1.0, 3.0, 2.0)]
    assert classify_many(model_of(mechanism), np.concatenate([p.points for p in loci.pieces])).kind("cspace").all()


def test_five_bar_second_assembly_branch(five_bar_branches):
    """Two assembly branches over the inputs' grid: at a grid point both reach, two configurations with the same
    inputs, the end-effector on either side of the distal links' line, i.e. of opposite sign of the actuator
    function det A (Chablat, Wenger & Angeles 1998 eq. 9: det A vanishes where the two meet, the distal links
    aligned)."""
    from classify.displacements import displacements_of
    from mechanisms.kinematics import closes

    mechanism, loci = five_bar_branches
    branches = loci.sample_branches
    assert sorted(set(branches.tolist())) == [0, 1]
    assert loci.coverage["assembly_branches"]["found"] == 2
    assert loci.coverage["assembly_branches"]["reached"] == [np.sum(branches == 0), np.sum(branches == 1)]
    assert np.all(closes(mechanism, loci.samples, 1e-9))
    inputs = displacements_of(mechanism, loci.samples)[:, [0, 4]]
    first, second = np.flatnonzero(branches == 0), np.flatnonzero(branches == 1)
    shared = [(i, j) for i in first for j in second if np.all(inputs[i] == inputs[j])]
    assert shared
    for i, j in shared:
        assert np.linalg.norm(loci.samples[i] - loci.samples[j]) > 1e-3
        assert loci.sample_signs[i, 0] * loci.sample_signs[j, 0] == -1


def test_branches_coloured_in_the_map(five_bar_branches):
    from classify.figures.loci import draw_cspace_map

    mechanism, loci = five_bar_branches
    axes = draw_cspace_map(mechanism, loci, [0, 4]).axes[0]
    gids = {line.get_gid() for line in axes.get_lines()}
    assert {"grid-branch:0", "grid-branch:1"} <= gids
    for index in (0, 1):
        line = next(line for line in axes.get_lines() if line.get_gid() == f"grid-branch:{index}")
        assert len(line.get_xdata()) == np.sum(loci.sample_branches == index)


def test_lines_break_only_where_an_angle_wraps_not_where_a_length_jumps():
    """A line of a C-space map is broken (a NaN row) only where a wrapped angle jumps by more than π.

    Park & Kim 1999 Fig. 3 (slider-crank) in millimetres (crank 200, coupler 100): the slide (a length) moves by
    more than π between traced points, which must not break the branches; the breaks left are the crank angle's
    wraps, and there are as many as at unit scale (crank 2, coupler 1), where the slide never jumps by π.
    """
    from classify.figures.loci import draw_cspace_map
    from mechanisms import home

    def branch_lines(scale):
        mechanism = catalogue_mechanism("slider-crank", crank=2.0 * scale, coupler=1.0 * scale)
        loci = trace_loci(mechanism, home(mechanism), kinds=("actuator", "end_effector"))
        columns = [mechanism.coordinate_names.index("crank"), mechanism.coordinate_names.index("slide")]
        axes = draw_cspace_map(mechanism, loci, columns).axes[0]
        lines = [line for line in axes.get_lines() if (line.get_gid() or "").startswith("branch:")]
        return [np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float) for line in lines]

    millimetres, unit = branch_lines(100.0), branch_lines(1.0)
    assert len(millimetres) == len(unit) == 2
    slide_jumps = 0
    for drawn, at_unit in zip(millimetres, unit):
        breaks = np.flatnonzero(np.isnan(drawn[:, 0]))
        assert len(breaks) == np.count_nonzero(np.isnan(at_unit[:, 0]))
        for row in breaks:  # every break sits between two crank angles more than π apart
            assert abs(drawn[row + 1, 0] - drawn[row - 1, 0]) > np.pi
        pieces = np.split(drawn, breaks)
        slide_jumps += sum(np.count_nonzero(np.abs(np.diff(piece[~np.isnan(piece[:, 0]), 1])) > np.pi)
                           for piece in pieces)
    assert slide_jumps > 0  # the slide does jump by more than π inside the unbroken pieces
