"""The regular neighbour of a singular start (:func:`classify.grid_continuation.regular_start`): equally well
conditioned neighbours, and a start at a C-space singularity (the last test).

The slider-crank driven at its slider, at the dead centre (crank and
coupler aligned: an actuator singularity, the start of ``closedchain map``
over the slide), is symmetric between its two mirror-image assembly modes:
its neighbours along T_pM have margins equal to the rounding of their
corrections. The choice between them was ``(−margin, sign, axis)``, so that
the rounding of the margins, or an axis written the other way, picked the
other mirror image without saying so. Ties are now within
:data:`~classify.grid_continuation.TIE_RTOL`, chosen by the coordinates'
convention, and reported (``alternatives``, ``tied``).
"""

import json

import numpy as np
import pytest

from classify import grid_continuation
from classify.cli import main
from classify.displacements import displacements_of
from classify.grid_continuation import regular_start
from mechanisms import catalogue, configuration, flip_axis


@pytest.fixture(scope="module")
def dead_centre():
    """The slider-crank at its dead centre driven at the slide, its start and held coordinates."""
    mechanism = catalogue.entry("slider-crank").mechanism("fig3d_dead_centre")
    return mechanism, configuration(mechanism, {}).point, tuple(sorted(mechanism.actuated_coordinates))


def neighbours(mechanism, starting, flipped=None):
    """The tied neighbours' joint displacements, chosen first, shape=[t, 4], in the coordinates of the
    mechanism before `flipped` (a joint name) was flipped."""
    found = displacements_of(mechanism, np.concatenate([starting.point[None], starting.alternatives]))
    if flipped is not None:
        found[:, [joint.name for joint in mechanism.joints].index(flipped)] *= -1.0
    return found


def test_the_two_mirror_images_at_a_dead_centre_are_reported_tied(dead_centre):
    mechanism, start, held = dead_centre
    found = regular_start(mechanism, start, held)
    assert found.singular and found.moved > 0 and found.tied == 2 and found.to_dict()["tied"] == 2
    chosen, other = neighbours(mechanism, found)
    revolute = [joint.type == "R" for joint in mechanism.joints]
    # the mirror image across the slide: every angle negated, the slide the same
    np.testing.assert_allclose(other[revolute], -chosen[revolute], atol=1e-9)
    np.testing.assert_allclose(other[~np.array(revolute)], chosen[~np.array(revolute)], atol=1e-9)
    assert np.max(np.abs(chosen[revolute])) > 1e-2


@pytest.mark.parametrize("joint", ["crank", "pin", "wrist", "slide"])
def test_the_tied_neighbours_do_not_depend_on_an_axis_sign(dead_centre, joint):
    """Flipping the crank's axis made ``map`` follow the other mirror image without a word; which one is
    chosen still follows the coordinates (no choice could not: module notes), but the pair is the same."""
    mechanism, _, held = dead_centre
    expected = neighbours(mechanism, regular_start(mechanism, dead_centre[1], held))
    flipped = flip_axis(mechanism, joint)
    found = regular_start(flipped, configuration(flipped, {}).point, held)
    assert found.tied == 2
    got = neighbours(flipped, found, joint)
    order = np.argsort(got[:, 0] * 1e6 + got[:, 1])  # the pair as a set
    np.testing.assert_allclose(got[order], expected[np.argsort(expected[:, 0] * 1e6 + expected[:, 1])], atol=1e-9)


def test_rounding_of_the_margins_does_not_choose_between_mirror_images(dead_centre, monkeypatch):
    """The margins of the − neighbours raised by 1e-12 (relative): the exact comparison took them."""
    mechanism, start, held = dead_centre
    expected = regular_start(mechanism, start, held)
    original = grid_continuation.held_margins

    def rounded(mechanism, points, held, constraint_rank=None):
        margins = original(mechanism, points, held, constraint_rank)
        if np.ndim(points) == 2 and len(points) > 1:
            margins[len(margins) // 2:] *= 1.0 + 1e-12
        return margins

    monkeypatch.setattr(grid_continuation, "held_margins", rounded)
    found = regular_start(mechanism, start, held)
    np.testing.assert_array_equal(found.point, expected.point)
    assert found.tied == 2


def test_the_map_says_the_start_was_tied(capsys):
    argv = ["map", "slider-crank", "--configuration", "fig3d_dead_centre", "--grid", "slide=-0.3:0:4"]
    assert main(argv + ["--format", "json"]) == 0
    start = json.loads(capsys.readouterr().out)["start"]
    assert start["singular"] and start["tied"] == 2
    assert main(argv) == 0
    assert "one of 2 as well conditioned" in capsys.readouterr().out


def test_a_regular_start_is_untied():
    mechanism = catalogue.entry("slider-crank").mechanism()
    found = regular_start(mechanism, configuration(mechanism, {}).point, tuple(mechanism.actuated_coordinates))
    assert not found.singular and found.tied == 1 and found.alternatives.shape[0] == 0


def test_a_start_at_a_cspace_singularity_is_singular_and_left_for_a_regular_neighbour(capsys):
    """Park & Kim (1999) Fig. 1a: the five-bar with all five joints collinear, a C-space singularity (DΦ of
    rank 2, 3 on M). DΦ restricted to the free joints has rank 2 there too, so the start counted as regular for
    the inputs: ``map`` said so, continued from it and reached 2 of 25 grid points. With the survey's rank of DΦ
    the start is singular and the grid is continued from a regular neighbour."""
    from classify import model_of, survey_of
    from classify.grid_continuation import held_margins

    mechanism = catalogue.entry("five-bar").mechanism("fig1a_collinear")
    start, held = configuration(mechanism, {}).point, tuple(sorted(mechanism.actuated_coordinates))
    rank = survey_of(model_of(mechanism)).constraint_rank
    assert rank == 3 and regular_start(mechanism, start, held).singular is False  # DΦ's own rank: 2
    found = regular_start(mechanism, start, held, rank)
    assert found.singular and found.moved > 0 and found.margin > grid_continuation.REGULAR_RTOL
    assert held_margins(mechanism, start, held, rank)[0] < 1e-12
    np.testing.assert_allclose(held_margins(mechanism, found.point, held, rank),
                               held_margins(mechanism, found.point, held), rtol=1e-12)  # a regular point of M
    argv = ["map", "five-bar", "--configuration", "fig1a_collinear", "--grid", "A=-0.2:0.2:5", "B=-0.2:0.2:5",
            "--format", "json"]
    assert main(argv) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["start"]["singular"] and document["start"]["cspace"] and document["start"]["moved"] > 0
    assert document["summary"]["reachable"] > 2
    assert main(argv[:-2]) == 0
    assert "(the start is a C-space singularity; the points it leaves continued from" in capsys.readouterr().out


def test_a_grid_at_a_cspace_singularity_is_continued_from_the_neighbour_alone(monkeypatch):
    """Where branches of M cross (Park & Kim Fig. 1a), the start's own continuation reached grid points on
    another branch than its regular neighbour's, and the map joined them (a review found neighbouring grid
    points 0.35 apart in the free joints, continuation failing between them both ways). With the survey's
    rank the whole grid is continued from the neighbour: no continuation leaves the start itself."""
    from classify.grid_continuation import assemble_grid, held_columns, Grid, grid_targets

    mechanism = catalogue.entry("five-bar").mechanism("fig1a_collinear")
    start = configuration(mechanism, {}).point
    grid = Grid(("A", "B"), (0, 4), (-0.2, -0.2), (0.2, 0.2), (5, 5))
    origins = []
    original = grid_continuation._continue

    def recorded(mechanism, current, targets, held, entries):
        origins.extend(np.all(np.isclose(current, start, rtol=0, atol=1e-12), axis=-1))
        return original(mechanism, current, targets, held, entries)

    monkeypatch.setattr(grid_continuation, "_continue", recorded)
    _, reached, starting = assemble_grid(mechanism, start, grid_targets(mechanism, grid, start), grid.shape,
                                         held_columns(mechanism, grid), with_start=True, constraint_rank=3)
    assert starting.cspace and starting.moved > 0 and reached.sum() > 2
    assert origins and not any(origins)


def test_a_start_that_reaches_the_whole_grid_is_not_said_to_be_left():
    """Park & Kim Fig. 1c without the survey's rank (the start counts as regular): every grid point is reached
    from the start, yet a regular neighbour was looked for and reported as where the grid was continued from
    (moved 0.048, tied 2; a review)."""
    from classify.grid_continuation import assemble_grid, held_columns, Grid, grid_targets

    mechanism = catalogue.entry("five-bar").mechanism("fig1c_collinear")
    start = configuration(mechanism, {}).point
    grid = Grid(("A", "B"), (0, 4), (-0.2, -0.2), (0.2, 0.2), (5, 5))
    _, reached, starting = assemble_grid(mechanism, start, grid_targets(mechanism, grid, start), grid.shape,
                                         held_columns(mechanism, grid), with_start=True)
    assert reached.all() and starting.moved == 0 and starting.tied == 1 and not starting.cspace


def test_the_loci_leave_a_cspace_singular_start_too():
    from classify.loci import trace_loci

    mechanism = catalogue.entry("five-bar").mechanism("fig1a_collinear")
    found = trace_loci(mechanism, configuration(mechanism, {}).point, counts=(5, 5),
                       ranges=((-0.2, 0.2), (-0.2, 0.2)), kinds=("actuator",))
    assert found.coverage["start"]["cspace"] and found.coverage["start"]["moved"] > 0


def test_the_tied_neighbours_do_not_depend_on_the_order_they_come_in():
    """A neighbour merged into another that a better one later pruned was dropped with it, and chained
    neighbours were counted once or twice, by the order the axes came in (a review): the set kept is now every
    neighbour within the band of the final best, grouped in key order."""
    import itertools

    from mechanisms import kinematics_of

    mechanism = catalogue.entry("slider-crank").mechanism()
    space = kinematics_of(mechanism).ambient
    home_point = configuration(mechanism, {}).point
    unit = np.zeros(space.dim)

    def near(offset):
        step = unit.copy()
        step[0] = offset
        return space.retract(home_point, step * space.tangent_scales)

    margin = 0.01
    cases = {"dropped": [(margin, (0, 1), near(0.0)), (margin * (1 + 0.9e-6), (0, 4), near(5e-4)),
                         (margin * (1 + 1.5e-6), (1, 2), near(0.5))],
             "chained": [(margin, (0, 1), near(0.0)), (margin, (0, 2), near(8e-4)), (margin, (0, 3), near(1.6e-3))]}
    for name, entries in cases.items():
        results = set()
        for order in itertools.permutations(entries):
            found = grid_continuation._Neighbours(space)
            for value, key, point in order:
                found.add(value, key, point, 0.0)
                assert not any(np.shares_memory(point, kept[2]) for kept in found.tied)
            chosen = found.choice(False)
            results.add((tuple(np.round(chosen.point, 12)), chosen.tied))
        assert len(results) == 1, (name, results)
