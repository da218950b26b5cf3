"""``closedchain map`` and the batch outputs: fixes found by an audit.

A grid axis over a whole turn is closed on itself both ways (the continuation walks across its ends, and the two
ends, one configuration, get one verdict), and the CSV of a map or a batch has one set of columns per list field
(``eigenvalues[i]``), a null list being empty cells there, not a column of its own.
"""

import contextlib
import csv
import io
import json

import numpy as np
import pytest

from classify.cli import main
from classify.cli._outputs import csv_text
from classify.grid_continuation import _wrapped, grid_neighbours

#: the equal-link slider-crank (crank = coupler = 1; its home crank angle is 0.3): one whole turn of the crank,
#: from −180° to +180° in steps of 15°, both ends given
SLIDER = ["slider-crank", "--param", "crank=1", "--param", "coupler=1"]
TURN = "crank=-3.4415926535897932:2.8415926535897932:25"
TURN_REVERSED = "crank=2.8415926535897932:-3.4415926535897932:25"


def run(argv):
    """(status, stdout, stderr) of ``closedchain ARGV``."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(argv, out=out)
    return status, out.getvalue(), err.getvalue()


def _map(grid):
    status, out, err = run(["map", *SLIDER, "--grid", grid, "--format", "json"])
    assert status == 0, err
    return json.loads(out)["points"]


# ------------------------------------------------------------------------------------------------ closed axes

@pytest.mark.parametrize("shape, axes", [((25,), [0]), ((5, 6), [1]), ((4, 7), [0, 1]), ((3,), [0])])
def test_a_closed_axis_links_its_ends_both_ways(shape, axes):
    """Neighbours are symmetric (j lists i when i lists j), the two ends of a closed axis list each other, and
    the points next to one end are neighbours of the other (the links were one-sided: 0 listed 23 of 25, but 23
    did not list 0, so a front never crossed the ends)."""
    neighbours = _wrapped(grid_neighbours(shape), axes, shape)
    pairs = {(int(index), int(other)) for index, row in enumerate(neighbours) for other in row if other >= 0}
    assert all((other, index) in pairs for index, other in pairs)
    flat = np.arange(int(np.prod(shape))).reshape(shape)
    for axis in axes:
        size = shape[axis]
        for first, last, after_first, before_last in zip(*(np.take(flat, index, axis=axis).ravel()
                                                           for index in (0, size - 1, 1, size - 2))):
            assert {(first, last), (last, first), (after_first, last), (before_last, first)} <= pairs
    assert np.array_equal(_wrapped(grid_neighbours(shape), [], shape), grid_neighbours(shape))


def test_continuation_walks_across_the_ends_of_a_whole_turn():
    """The audit's map: ``xxxxxxC.....E.....C.....E``: −180° to −105° unreachable though a finer grid (73
    points) reaches every point of the same branch, and +180° reached while −180°, the same configuration, was
    not. The wrap is walked now: every point is reached, and the ends get one verdict."""
    points = _map(TURN)
    assert all(point["reachable"] for point in points)
    assert points[0]["kinds"] == points[-1]["kinds"] == ["end_effector"]
    first, last = points[0]["displacements"], points[-1]["displacements"]
    assert first["slide"] == pytest.approx(last["slide"], abs=1e-9)
    for name in ("crank", "pin", "wrist"):  # angles: one configuration, whole turns apart
        turns = (last[name] - first[name]) / (2 * np.pi)
        assert turns == pytest.approx(round(turns), abs=1e-9)
    fine = _map("crank=-3.4415926535897932:2.8415926535897932:73")
    assert all(point["reachable"] for point in fine)
    assert [point["kinds"] for point in points] == [point["kinds"] for point in fine[::3]]


def test_a_whole_turn_does_not_depend_on_which_end_is_called_which():
    points, reversed_points = _map(TURN), _map(TURN_REVERSED)[::-1]
    assert [point["reachable"] for point in points] == [point["reachable"] for point in reversed_points]
    assert [point["kinds"] for point in points] == [point["kinds"] for point in reversed_points]
    for point, other in zip(points, reversed_points):
        np.testing.assert_allclose(point["displacements"]["slide"], other["displacements"]["slide"], atol=1e-9)


# ------------------------------------------------------------------------------------------------ CSV columns

def test_a_null_list_is_empty_cells_of_its_numbered_columns():
    rows = [{"row": 1, "eigenvalues": None, "margins": None, "kinds": []},
            {"row": 2, "eigenvalues": [1.5, 0.25], "margins": {"cspace": 0.5}, "kinds": ["actuator"]},
            {"row": 3, "eigenvalues": [], "margins": {"cspace": None}, "kinds": []}]
    table = list(csv.DictReader(io.StringIO(csv_text(rows))))
    # in the order of the fields, as when the first row has the lists
    assert list(table[0]) == ["row", "eigenvalues[0]", "eigenvalues[1]", "margins_cspace", "kinds"]
    assert [line["eigenvalues[0]"] for line in table] == ["", "1.5", ""]
    assert [line["margins_cspace"] for line in table] == ["", "0.5", ""]
    assert [line["kinds"] for line in table] == ["", "actuator", ""]
    # a scalar column that is null everywhere and no list or group elsewhere stays a column
    assert list(csv.DictReader(io.StringIO(csv_text([{"a": None}, {"a": None}]))))[0] == {"a": ""}


def _eigenvalue_columns_read_back(text, rows):
    """The CSV's ``eigenvalues[i]`` cells against the JSON rows' lists (null: every cell empty)."""
    table = list(csv.DictReader(io.StringIO(text)))
    columns = [name for name in table[0] if name.startswith("eigenvalues")]
    assert "eigenvalues" not in columns and columns == [f"eigenvalues[{index}]" for index in range(len(columns))]
    assert len(table) == len(rows)
    for line, row in zip(table, rows):
        values = row.get("eigenvalues")
        cells = [line[name] for name in columns]
        if values is None:
            assert cells == [""] * len(columns)
        else:
            assert [float(cell) for cell in cells[:len(values)]] == values and not any(cells[len(values):])
    return table


def test_map_csv_has_one_set_of_eigenvalue_columns(tmp_path):
    """The audit's map (73 points over a whole turn: two end-effector singularities with no λ's) wrote a column
    ``eigenvalues``, always empty, beside ``eigenvalues[0]``."""
    grid = "crank=-3.4415926535897932:2.8415926535897932:73"
    status, out, err = run(["map", *SLIDER, "--grid", grid, "--out", str(tmp_path / "map.csv")])
    assert status == 0, err
    points = _map(grid)
    assert any(point.get("eigenvalues") is None for point in points if point["reachable"])
    _eigenvalue_columns_read_back((tmp_path / "map.csv").read_text(), points)


def test_batch_csv_has_one_set_of_eigenvalue_columns_and_reads_back(tmp_path):
    """``classify --batch`` writes the same CSV; its displacements still read back as a batch file."""
    batch = tmp_path / "batch.jsonl"
    batch.write_text(  # a C-space singularity (no λ's), a regular configuration, an end-effector singularity
        '{"crank": -1.8707963267948968, "pin": 3.741592243788516, "wrist": -1.870795916993619, '
        '"slide": -1.9106725684499346}\n{"crank": 0.0}\n{"crank": 2.8415926535897933, "pin": -5.683185307179587, '
        '"wrist": 2.8415926535897933, "slide": -3.9106729782512124}\n')
    status, out, err = run(["classify", *SLIDER, "--batch", str(batch), "--format", "json"])
    assert status == 0, err
    rows = [json.loads(line) for line in out.splitlines()]
    assert any(row["eigenvalues"] is None for row in rows) and any(row["eigenvalues"] for row in rows)
    status, _, err = run(["classify", *SLIDER, "--batch", str(batch), "--out", str(tmp_path / "out.csv")])
    assert status == 0, err
    table = _eigenvalue_columns_read_back((tmp_path / "out.csv").read_text(), rows)
    columns = [name for name in table[0] if name.startswith("displacements_")]
    again = tmp_path / "again.csv"
    with again.open("w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow([name[len("displacements_"):] for name in columns])
        writer.writerows([[line[name] for name in columns] for line in table])
    status, out, err = run(["classify", *SLIDER, "--batch", str(again), "--format", "json"])
    assert status == 0, err
    assert [json.loads(line)["kinds"] for line in out.splitlines()] == [row["kinds"] for row in rows]
