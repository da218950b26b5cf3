"""``closedchain map``: a grid of joint coordinates, each point assembled (or projected) and classified.

Checked against closed forms: the five-bar map over its two inputs reaches exactly the inputs where the
catalogue's builder assembles the mechanism, in the same working mode (the same end-effector point); the
slider-crank map over its crank reaches exactly |R sin θ| ≤ l, with the slide where Gosselin & Angeles
eq. (9) puts it.
"""

import contextlib
import csv
import importlib
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from classify import classify_many, model_of
from classify import cli
from classify.cli import main, map_command
from mechanisms import MechanismError, catalogue, from_displacements, home
from mechanisms.kinematics import closes, end_effector

GRID_7X7 = ["A=-1:1:7", "B=-1:1:7"]


def run(argv):
    """(status, stdout, stderr) of ``closedchain ARGV``, with ``map`` registered if the command list lacks it."""
    registered = "map" in cli.COMMANDS
    if not registered:
        cli.COMMANDS["map"] = map_command
    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            status = main(argv, out=out)
    finally:
        if not registered:
            del cli.COMMANDS["map"]
    return status, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def five_bar_map(tmp_path_factory):
    """The five-bar (catalogue defaults) over A, B ∈ [−1, 1]²: the JSON document and the NPZ arrays."""
    folder = tmp_path_factory.mktemp("map")
    status, out, err = run(["map", "five-bar", "--grid", *GRID_7X7, "--format", "json"])
    assert status == 0, err
    status, _, err = run(["map", "five-bar", "--grid", *GRID_7X7, "--out", str(folder / "map.npz")])
    assert status == 0, err
    with np.load(folder / "map.npz") as saved:
        arrays = dict(saved)
    return json.loads(out), arrays


def _five_bar():
    item = catalogue.entry("five-bar")
    return item, item.values(None), item.mechanism()


def test_five_bar_reaches_exactly_the_assemblable_inputs_in_its_working_mode(five_bar_map):
    """Joint A turns the left crank θ1 counter-clockwise; B joins (proximal_right, ground), so it turns θ2 the
    other way: θ1 = 1.8 + A, θ2 = 1.3 − B. Where the builder assembles the five-bar (assembly +1, as the map's
    starting configuration) the map reached the same end-effector point; where it cannot, the map did not."""
    document, _ = five_bar_map
    item, values, mechanism = _five_bar()
    reached = 0
    for entry in document["points"]:
        a, b = entry["coordinates"]["A"], entry["coordinates"]["B"]
        try:
            built = item.assemble({**values, "theta1": 1.8 + a, "theta2": 1.3 - b})
        except MechanismError:
            assert not entry["reachable"], (a, b)
            continue
        assert entry["reachable"], (a, b)
        reached += 1
        point = from_displacements(mechanism, entry["displacements"])
        assert bool(closes(mechanism, point, 1e-10))
        np.testing.assert_allclose(end_effector(mechanism, point), end_effector(built, home(built)), atol=1e-9)
        assert (entry["displacements"]["A"], entry["displacements"]["B"]) == (a, b)  # held bit for bit
    assert 0 < reached < len(document["points"])


def test_five_bar_json_document(five_bar_map):
    document, _ = five_bar_map
    assert document["grid"] == {"A": [-1.0, 1.0, 7], "B": [-1.0, 1.0, 7]} and document["shape"] == [7, 7]
    assert document["method"] == "assemble" and document["held"] == ["A", "B"]
    points = document["points"]
    assert [entry["index"] for entry in points] == [[i, j] for i in range(7) for j in range(7)]
    axis = np.linspace(-1, 1, 7)
    assert [(entry["coordinates"]["A"], entry["coordinates"]["B"]) for entry in points] == \
        [(a, b) for a in axis for b in axis]
    summary = document["summary"]
    reachable = [entry for entry in points if entry["reachable"]]
    assert summary["total"] == 49 and summary["reachable"] == len(reachable)
    assert summary["unreachable"] == 49 - len(reachable)
    assert summary["regular"] == sum(not entry["kinds"] for entry in reachable)
    for kind in ("actuator", "cspace", "end_effector"):
        assert summary[kind] == sum(kind in entry["kinds"] for entry in reachable)
    assert all(set(entry) == {"index", "coordinates", "reachable"} for entry in points if not entry["reachable"])


def test_the_name_may_follow_the_grid_axes(five_bar_map):
    """``--grid`` takes several words, so argparse gave a NAME written after the axes to it (and asked for
    FILE|NAME): the last word without '=' is the mechanism; with none, the error is argparse's."""
    status, out, err = run(["map", "--grid", *GRID_7X7, "--format", "json", "five-bar"])
    assert status == 0, err
    assert json.loads(out) == five_bar_map[0]
    status, _, err = run(["map", "--grid", *GRID_7X7])
    assert status == 2 and err.count("\n") == 1 and "FILE|NAME" in err


def test_five_bar_npz_is_shaped_like_the_grid_and_equals_classify_many(five_bar_map):
    document, arrays = five_bar_map
    _, _, mechanism = _five_bar()
    reachable = arrays["reachable"]
    assert reachable.shape == (7, 7)
    assert reachable.reshape(-1).tolist() == [entry["reachable"] for entry in document["points"]]
    np.testing.assert_array_equal(arrays["coordinates"], np.stack(np.meshgrid(np.linspace(-1, 1, 7),
                                                                              np.linspace(-1, 1, 7),
                                                                              indexing="ij"), axis=-1))
    assert tuple(arrays["grid_names"]) == ("A", "B") and arrays["grid_count"].tolist() == [7, 7]
    points = arrays["points"][reachable]
    assert np.isnan(arrays["points"][~reachable]).all() and np.isnan(arrays["displacements"][~reachable]).all()
    expected = classify_many(model_of(mechanism), points)
    for name, column in expected.arrays().items():
        if name == "kinds":
            assert arrays[name].tolist() == column.tolist()
            continue
        np.testing.assert_allclose(arrays[name][reachable], column, rtol=1e-12, err_msg=name)
        spread = arrays[name][~reachable]
        assert (np.isnan(spread).all() if spread.dtype.kind == "f" else
                (spread == (False if spread.dtype == bool else -1)).all()), name
    rows = [entry for entry in document["points"] if entry["reachable"]]
    for entry, row in zip(rows, expected.rows()):
        assert {key: entry[key] for key in row} == row
    for displacement, point in zip(arrays["displacements"][reachable], points):
        np.testing.assert_array_equal(from_displacements(mechanism, dict(zip(mechanism.coordinate_names,
                                                                              displacement))), point)


def test_five_bar_points_equal_single_classify_at_calls(five_bar_map):
    document, _ = five_bar_map
    reachable = [entry for entry in document["points"] if entry["reachable"]]
    for entry in (reachable[0], reachable[len(reachable) // 2], reachable[-1]):
        status, out, _ = run(["classify", "five-bar", "--at", json.dumps(entry["displacements"]), "--format",
                              "json"])
        assert status == 0
        single = json.loads(out)
        assert entry["kinds"] == single["kinds"]
        for kind in ("cspace", "actuator", "end_effector"):
            assert entry["ranks"][kind] == single[kind]["rank"]
            assert entry["margins"][kind]["smallest_kept"] == pytest.approx(single[kind]["margin"]["smallest_kept"],
                                                                            rel=1e-9)
        assert entry["condition_number"] == pytest.approx(single["manipulability"]["condition_number"], rel=1e-9)


def test_five_bar_map_through_an_actuator_singularity():
    """From the distal-aligned configuration (Chablat, Wenger & Angeles eq. 9) the grid's centre is that
    configuration: reached, and an actuator singularity; beyond it the inputs leave the workspace."""
    status, out, err = run(["map", "five-bar", "--configuration", "eq9_distal_aligned", "--grid", "A=-0.3:0.3:7",
                            "B=-0.3:0.3:7", "--format", "json"])
    assert status == 0, err
    points = json.loads(out)["points"]
    centre = points[3 * 7 + 3]
    assert centre["coordinates"] == {"A": 0.0, "B": 0.0} and centre["reachable"]
    assert "actuator" in centre["kinds"] and centre["degenerate"] is False
    assert any(not entry["reachable"] for entry in points)
    assert all(not entry["kinds"] for entry in points if entry["reachable"] and entry is not centre)


# ------------------------------------------------------------------------------------------------ slider-crank

def test_slider_crank_over_its_crank_matches_the_closed_form():
    """Crank R = 2, coupler l = 1, built at θ = 0.3 on branch +1: assembled where |R sin θ| ≤ l, the slide at
    x(θ) = R cos θ + √(l² − R² sin² θ) (Gosselin & Angeles eq. 9), the dead centre θ = 0 an end-effector
    singularity."""
    status, out, err = run(["map", "slider-crank", "--grid", "crank=-1.0:0.4:15", "--format", "json"])
    assert status == 0, err
    document = json.loads(out)
    assert document["held"] == ["crank"]

    def slide(theta):
        return 2 * math.cos(theta) + math.sqrt(1 - 4 * math.sin(theta) ** 2)

    kinds = {}
    for entry in document["points"]:
        theta = 0.3 + entry["coordinates"]["crank"]
        assert entry["reachable"] == (abs(2 * math.sin(theta)) <= 1), theta
        if entry["reachable"]:
            assert entry["displacements"]["slide"] == pytest.approx(slide(theta) - slide(0.3), abs=1e-12)
            kinds[round(theta, 9)] = entry["kinds"]
    assert kinds.pop(0.0) == ["end_effector"]
    assert len(kinds) == 10 and all(value == [] for value in kinds.values())


def test_projection_map_equals_classify_at_project():
    status, out, err = run(["map", "slider-crank", "--grid", "crank=-0.6:0.6:5", "--project", "--format", "json"])
    assert status == 0, err
    document = json.loads(out)
    assert document["method"] == "project" and document["held"] is None
    for entry in document["points"][::2]:
        assert entry["reachable"]
        status, single, _ = run(["classify", "slider-crank", "--at", json.dumps(entry["coordinates"]), "--project",
                                 "--format", "json"])
        single = json.loads(single)
        assert entry["projection_distance"] == pytest.approx(single["projection_distance"], rel=1e-9, abs=1e-15)
        assert entry["kinds"] == single["kinds"]
        assert entry["displacements"] == pytest.approx(single["configuration"], abs=1e-12)


# ------------------------------------------------------------------------------------------------ files

@pytest.fixture(scope="module")
def slider_map(tmp_path_factory):
    folder = tmp_path_factory.mktemp("slider")
    status, out, err = run(["map", "slider-crank", "--grid", "crank=-1.0:0.4:15", "--format", "json"])
    assert status == 0, err
    return folder, json.loads(out)


@pytest.mark.parametrize("suffix", [".json", ".jsonl", ".csv"])
def test_out_files_read_back(slider_map, suffix):
    folder, document = slider_map
    path = folder / f"map{suffix}"
    status, out, _ = run(["map", "slider-crank", "--grid", "crank=-1.0:0.4:15", "--out", str(path)])
    assert status == 0 and out.count("\n") == 1 and "written to" in out and "4 unreachable" in out
    text = path.read_text()
    if suffix == ".json":
        assert json.loads(text) == document
    elif suffix == ".jsonl":
        assert [json.loads(line) for line in text.splitlines()] == document["points"]
    else:
        table = list(csv.DictReader(io.StringIO(text)))
        assert len(table) == len(document["points"])
        for line, entry in zip(table, document["points"]):
            assert float(line["coordinates_crank"]) == entry["coordinates"]["crank"]
            assert line["reachable"] == ("true" if entry["reachable"] else "false")
            assert line["kinds"] == ";".join(entry.get("kinds", []))
            condition = entry.get("condition_number")
            assert line["condition_number"] == ("" if condition is None else repr(condition))


def test_text_output_has_a_table_counts_and_a_picture():
    status, out, _ = run(["map", "slider-crank", "--grid", "crank=-1.0:0.4:15"])
    assert status == 0
    lines = out.splitlines()
    assert lines[0].split()[:2] == ["crank", "kinds"] and len(lines[2:17]) == 15
    assert "map of 15 grid points: 10 regular; singular: 1 end-effector; 4 unreachable" in lines
    assert lines[-1] == "xx.....E.....xx"
    status, out, _ = run(["map", "five-bar", "--grid", "A=-1:1:3", "B=-1:1:4"])
    picture = out.splitlines()[-3:]
    assert [len(line) for line in picture] == [4, 4, 4]


def test_a_grid_out_of_reach_is_all_unreachable_not_an_error(tmp_path):
    path = tmp_path / "far.npz"
    status, out, err = run(["map", "slider-crank", "--grid", "crank=1:1.2:3", "--out", str(path)])
    assert status == 0, err
    assert "3 unreachable" in out
    with np.load(path) as saved:
        assert not saved["reachable"].any() and np.isnan(saved["points"]).all()
        assert (saved["rank_actuator"] == -1).all() and np.isnan(saved["condition_number"]).all()


def test_survey_file_is_written_then_reused(tmp_path, monkeypatch):
    survey_module = importlib.import_module("classify.survey")
    calls = []
    original = survey_module.survey
    monkeypatch.setattr(survey_module, "survey", lambda *arguments, **options: calls.append(1) or
                        original(*arguments, **options))
    survey_path = tmp_path / "slider.survey.json"
    argv = ["map", "slider-crank", "--grid", "crank=-0.2:0.2:3", "--survey", str(survey_path), "--format", "json"]
    first = run(argv)
    assert first[0] == 0 and len(calls) == 1
    second = run(argv)
    assert second[0] == 0 and len(calls) == 1 and second[1] == first[1]
    assert json.loads(second[1])["survey"] == json.loads(survey_path.read_text())["survey"]


def test_threads_reach_classify_many_and_do_not_change_the_map(monkeypatch):
    batch = importlib.import_module("classify.batch")
    asked = []
    original = batch.classify_many

    def recording(*arguments, workers=1, **options):
        asked.append(workers)
        return original(*arguments, workers=workers, chunk=5, **options)  # several chunks, so threads have work

    monkeypatch.setattr(batch, "classify_many", recording)
    outputs = [run(["map", "five-bar", "--grid", *GRID_7X7, "--format", "json", *threads])
               for threads in ([], ["--threads", "1"], ["--threads", "2"])]
    assert asked == [-1, 1, 2]
    assert all(status == 0 for status, _, _ in outputs)
    assert outputs[0][1] == outputs[1][1] == outputs[2][1]


# ------------------------------------------------------------------------------------------------ bad input

@pytest.mark.parametrize("grid, fragment", [
    (["A=0:1"], "three fields"),
    (["A0:1:3"], "expected NAME=a:b:n"),
    (["=0:1:3"], "expected NAME=a:b:n"),
    (["A=0:1:0"], "n: expected an integer ≥ 1, got '0'"),
    (["A=0:1:2.5"], "n: expected an integer ≥ 1"),
    (["A=0:1:-3"], "n: expected an integer ≥ 1"),
    (["A=0:1:"], "n: expected an integer ≥ 1, got nothing"),
    (["A=nan:1:3"], "a: expected a finite number"),
    (["A=0:inf:3"], "b: expected a finite number"),
    (["A=x:1:3"], "a: expected a number, got 'x'"),
    (["A=0:1e13:3"], "b: 1e+13 is out of range"),
    (["A=0:1:1"], "n = 1 gives one point"),
    (["Z=0:1:3"], "unknown coordinate 'Z' (known: A, C, P, D, B)"),
    (["A=0:1:3", "A=0:2:3"], "coordinate 'A' is on the grid twice"),
    (["A=0:1:1001", "B=0:1:1000"], "more than 1000000 points"),
])
def test_grid_errors_exit_2_with_one_line(grid, fragment):
    status, out, err = run(["map", "five-bar", "--grid", *grid])
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("closedchain: error: --grid") and fragment in err, err


@pytest.mark.parametrize("argv, fragment", [
    (["map", "five-bar"], "--grid"),
    (["map", "five-bar", "--grid", "A=0:0:1", "--seed", "2"], "--seed: does not apply"),
    (["map", "five-bar", "--grid", "A=0:0:1", "--out", "map.txt"], "--out: map.txt: expected a file ending in"),
    (["map", "five-bar", "--grid", "A=0:0:1", "--param", "nothing=1"], "has no parameter 'nothing'"),
    # numbers read as written: other scripts' digits, underscores, a nonzero number that would read as 0
    (["map", "five-bar", "--grid", "A=\u0663:1:3"], "a: expected a number"),
    (["map", "five-bar", "--grid", "A=0:1:\u0663"], "n: expected an integer ≥ 1"),
    (["map", "five-bar", "--grid", "A=0_0:1:3"], "a: expected a number"),
    (["map", "five-bar", "--grid", "A=1e-400:1:3"], "is below the smallest float"),
    (["map", "five-bar", "--grid", "A=0:1:3", "--param", "base=\u0665"], "--param base: expected a number"),
    # an empty path was named '.'
    (["map", "", "--grid", "A=0:1:3"], "FILE|NAME: an empty path"),
    (["map", "five-bar", "--grid", "A=0:1:3", "--survey", ""], "--survey: an empty path"),
    (["map", "five-bar", "--grid", "A=0:1:3", "--threads", "0"], "--threads: expected a positive integer up to 256"),
    (["map", "five-bar", "--grid", "A=0:1:3", "--format", "json", "--out", "map.csv"],
     "--format: applies to what is printed"),  # was ignored
])
def test_other_bad_options_exit_2(argv, fragment):
    status, _, err = run(argv)
    assert status == 2 and err.count("\n") == 1 and fragment in err, err


def test_a_ball_joint_is_gridded_by_its_coordinates():
    status, _, err = run(["map", "eclipse", "--grid", "ball1=0:1:3"])
    assert status == 2 and err.count("\n") == 1
    assert "joint 'ball1' (S) has 3 coordinates: name one of ball1[x], ball1[y], ball1[z]" in err


def test_map_from_an_actuator_singular_start_reaches_the_grid():
    """Started at the five-bar's actuator singularity (Chablat, Wenger & Angeles 1998 eq. 9: distal links
    aligned), the continuation starts from a regular neighbour on M, said in the JSON's ``start``, and reaches
    grid points (none before); every reached point closes the loops at the grid's inputs."""
    status, out, err = run(["map", "five-bar", "--configuration", "eq9_distal_aligned", "--grid", "A=-3:3:5",
                            "B=-3:3:5", "--format", "json"])
    assert status == 0, err
    document = json.loads(out)
    start = document["start"]
    assert start["singular"] and 0 < start["moved"] <= 0.2 and start["margin"] > start["tolerance"]
    assert document["summary"]["reachable"] > 0
    status, out, _ = run(["map", "five-bar", "--grid", "A=-3:3:5", "B=-3:3:5", "--format", "json"])
    assert status == 0 and not json.loads(out)["start"]["singular"]
    status, out, _ = run(["map", "five-bar", "--grid", "A=-1:1:3", "B=-1:1:3", "--project", "--format", "json"])
    assert status == 0 and json.loads(out)["start"] is None


def test_from_a_singular_start_a_grid_point_is_reached_whatever_the_grid_resolution():
    """Gough–Stewart at Fichter's turned singularity (actuator, a fold of leg P1): a grid point tried from the
    singular start was never tried again from its regular neighbour, so P1 = −0.05 was unreachable on a
    3-point grid and reached on an 11-point one. The maps now agree where the grids share points."""
    pictures = []
    for count in (3, 11):
        status, out, err = run(["map", "gough-stewart", "--configuration", "fichter_rotated_plus_90",
                                "--grid", f"P1=-0.05:0.05:{count}", "--format", "json"])
        assert status == 0, err
        pictures.append([point["reachable"] for point in json.loads(out)["points"]])
    coarse, fine = pictures
    assert coarse == [fine[0], fine[5], fine[10]] == [True, True, False]


def test_project_starts_from_a_named_configuration_that_does_not_close(tmp_path):
    """With --project every grid point is projected, so the start need not close (it was refused, with advice
    to use --project)."""
    five_bar = Path(__file__).resolve().parents[2] / "examples" / "five_bar.yaml"
    path = tmp_path / "five_bar.yaml"
    path.write_text(five_bar.read_text() + "  open: {J1: 0.5}\n")
    argv = ["map", str(path), "--configuration", "open", "--grid", "J5=-0.1:0.1:3", "--format", "json"]
    status, out, err = run([*argv, "--project"])
    assert status == 0, err
    assert json.loads(out)["summary"]["reachable"] == 3
    status, _, err = run(argv)
    assert status == 2 and "--configuration open: the configuration does not close the loops" in err


ROBOT = Path(__file__).resolve().parents[1] / "data" / "robots" / "5bar_linkage"


def test_a_urdf_is_mapped_with_its_closures_and_warned_without_them():
    """map had no --closures: a URDF was read as a serial chain, every point 'regular', without a word."""
    urdf, closures = str(ROBOT / "robot.urdf"), str(ROBOT / "robot.yaml")
    status, out, err = run(["map", urdf, "--closures", closures, "--grid", "mot1=0:0.2:3", "--format", "json"])
    assert status == 0, err
    document = json.loads(out)
    assert document["summary"]["reachable"] == 3 and "warning" not in err
    assert [point["ranks"]["cspace"] for point in document["points"]] == [3, 3, 3]  # the closure's rows
    status, out, err = run(["map", urdf, "--grid", "mot1=0:0.2:3", "--format", "json"])
    assert status == 0 and "closedchain: warning: 5bar_linkage has no loop (a serial chain;" in err
    assert [point["ranks"]["cspace"] for point in json.loads(out)["points"]] == [0, 0, 0]


@pytest.mark.parametrize("fields, fragment", [
    ((("A", "B"), (0,), (0.0, 0.0), (1.0, 1.0), (3, 3)), "one entry per axis, got 2 names, 1 columns"),
    ((("A",), (-1,), (0.0,), (1.0,), (3,)), "columns must be distinct non-negative integers"),
    ((("A", "B"), (0, 0), (0.0, 0.0), (1.0, 1.0), (3, 3)), "columns must be distinct"),
    ((("A",), (0,), (math.nan,), (1.0,), (3,)), "starts must be finite numbers"),
    ((("A",), (0,), (0.0,), ("1",), (3,)), "stops must be finite numbers"),
    ((("A",), (0,), (0.0,), (1.0,), (2.5,)), "counts must be positive integers"),
    ((("A",), (0,), (0.0,), (1.0,), (0,)), "counts must be positive integers"),
])
def test_a_hand_built_grid_is_checked(fields, fragment):
    """zip() would drop an axis of mismatched fields, and linspace would read a count of 2.5 as 2."""
    from classify.grid_continuation import Grid

    with pytest.raises(ValueError, match=re.escape(fragment)):
        Grid(*fields)


def test_a_grid_over_a_whole_turn_does_not_depend_on_the_sign_of_the_joint_axis(tmp_path):
    """The hybrid (Chablat, Wenger & Angeles 1998 Fig. 6) over a whole turn of A, both ends given: the ends are
    one configuration twice. The grid's edge there cut a region off, reached or not by which end the seeds met
    first, so flipping A's axis (and the grid with it) changed the map (92 or 108 of 256 points, found by an
    audit). The axis is now closed on itself."""
    from mechanisms import catalogue, flip_axis, save

    mechanism = catalogue.entry("hybrid").mechanism()
    save(mechanism, tmp_path / "hybrid.yaml")
    save(flip_axis(mechanism, "A"), tmp_path / "flipped.yaml")
    turn = "3.141592653589793"
    reached = []
    for name, grid in (("hybrid", f"A=-{turn}:{turn}:8"), ("flipped", f"A={turn}:-{turn}:8")):
        status, out, err = run(["map", str(tmp_path / f"{name}.yaml"), "--grid", f"base=-{turn}:1.5707963267948966:4",
                                grid, f"B=-{turn}:{turn}:8", "--format", "json"])
        assert status == 0, err
        reached.append([point["reachable"] for point in json.loads(out)["points"]])
    assert reached[0] == reached[1] and sum(reached[0]) > 92
