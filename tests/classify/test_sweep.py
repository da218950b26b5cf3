"""Design sweeps (:mod:`classify.sweep`): the grid, one design's row against one-at-a-time classification,
and rows that depend neither on the chunking nor on where the chunks run (serial or a 2-worker Dask
LocalCluster)."""

import sys

import numpy as np
import pytest

from classify import KINDS, classify, model_of, sample_configurations
from classify import sweep as sweep_module
from classify.sweep import (
    DESIGN_LIMIT, chunk_size, design_grid, design_rng, flat_row, local_cluster, sweep, sweep_chunk, sweep_design,
)
from mechanisms import MechanismError, catalogue

#: crank = 0 cannot be built (an error row); crank = coupler has a second component, the slider held at x = 0,
#: where the end-effector cannot move (Gosselin & Angeles 1990 eq. 17): end-effector singular samples
SLIDER = ["crank=0:1.5:4", "coupler=1", "theta=0.7"]
SAMPLES = 12


@pytest.fixture(scope="module")
def serial():
    return sweep("slider-crank", SLIDER, SAMPLES, seed=7, chunk=1)


@pytest.fixture(scope="module")
def cluster():
    """A 2-worker LocalCluster (one thread each), shared by the tests of this module."""
    with local_cluster(2) as local:
        yield local


def test_the_grid_is_in_c_order_with_exact_ends():
    grid = design_grid(catalogue.entry("five-bar"), ["theta2=-1:1:3", "assembly=-1:1:2", "distal=4.5",
                                                      "actuated=A,B"])
    assert grid.shape == (3, 2) and len(grid) == 6
    assert grid.order == ("distal", "theta2", "assembly", "actuated")  # the entry's order
    assert [grid.parameters(index)["theta2"] for index in range(6)] == [-1.0, -1.0, 0.0, 0.0, 1.0, 1.0]
    assert [grid.parameters(index)["assembly"] for index in range(6)] == [-1, 1, -1, 1, -1, 1]
    assert all(isinstance(grid.parameters(index)["assembly"], int) for index in range(6))
    assert grid.parameters(5) == {"distal": 4.5, "theta2": 1.0, "assembly": 1, "actuated": "A,B"}
    ends = design_grid("slider-crank", ["crank=0.1:0.7:7"]).axes[0][1]
    assert ends[0] == 0.1 and ends[-1] == 0.7 and len(ends) == 7
    assert design_grid("slider-crank", ["crank=2:2:1"]).parameters(0) == {"crank": 2.0}
    with pytest.raises(MechanismError, match="n = 1 gives one value: a and b must be equal"):  # 3 was dropped
        design_grid("slider-crank", ["crank=2:3:1"])
    with pytest.raises(MechanismError, match="expected a whole number of values"):
        design_grid("slider-crank", ["crank=2:3:1_0"])
    assert len(design_grid("slider-crank", [])) == 1 and design_grid("slider-crank", []).parameters(0) == {}
    document = grid.to_dict()
    assert document["designs"] == 6 and document["axes"]["assembly"] == [-1, 1]
    assert document["defaults"]["proximal"] == 8.0 and document["fixed"] == {"distal": 4.5, "actuated": "A,B"}
    with pytest.raises(IndexError):
        grid.parameters(6)


@pytest.mark.parametrize("specs, fragment", [
    (["length=1:2:3"], "--param length: slider-crank has no parameter 'length'"),
    (["crank=1:2:0"], "--param crank: expected at least 1 value in a:b:n, got n = 0"),
    (["crank=1:2:-4"], "--param crank: expected at least 1 value"),
    (["crank=1:inf:3"], "--param crank: expected a finite number, got 'inf'"),
    (["crank=nan:2:3"], "--param crank: expected a finite number, got 'nan'"),
    (["crank=1:2"], "--param crank: expected a:b:n"),
    (["crank=1:2:x"], "--param crank: expected a whole number of values n"),
    (["crank=1:2:3", "crank=2"], "--param crank: given twice"),
    (["branch=-1:1:4"], "--param branch: an integer parameter needs whole steps"),
    (["end_effector=true:false:2"], "--param end_effector: expected true or false"),
    (["crank=1:2:1000", "coupler=1:2:1000"], f"1000 × 1000 = 1000000 designs exceed the limit of {DESIGN_LIMIT}"),
    ([f"crank=1:2:{DESIGN_LIMIT + 1}"], f"values exceed the limit of {DESIGN_LIMIT} designs"),
    (["crank"], "--param: expected K=V or K=a:b:n"),
    (["crank=1e400:2:3"], "--param crank: expected a finite number"),
])
def test_bad_specs_are_refused_naming_the_parameter(specs, fragment):
    with pytest.raises(MechanismError) as error:
        design_grid("slider-crank", specs)
    message = str(error.value)
    assert message.startswith("--param") and fragment in message and "\n" not in message


@pytest.mark.parametrize("name, parameters, index", [
    ("five-bar", {"base": 2.0, "proximal": 1.0, "distal": 1.0, "theta1": 0.4, "theta2": 2.0}, 3),
    ("slider-crank", {"crank": 1.0, "coupler": 1.0, "theta": 0.7}, 2),  # as in SLIDER: singular samples
])
def test_a_row_agrees_with_one_at_a_time_classification(name, parameters, index):
    """The shares and smallest margins of a design, recounted from single `classify` calls at the same
    configurations (drawn with the design's own generator)."""
    entry = catalogue.entry(name)
    row = sweep_design(entry, parameters, SAMPLES, seed=7, index=index)
    model = model_of(entry.assemble(entry.values(**parameters)))
    points = sample_configurations(model, SAMPLES, design_rng(7, index))
    reports = [classify(model, point) for point in points]
    assert row["design"] == index and row["parameters"] == parameters and row["error"] is None
    assert row["samples"] == len(points) == SAMPLES
    for kind in KINDS:
        assert row["share"][kind] == sum(kind in report.kinds for report in reports) / len(reports)
        ratios = [getattr(report, kind).decision.margin[0] / getattr(report, kind).decision.tolerance
                  for report in reports if kind not in report.kinds]
        assert row["smallest_margin"][kind] == pytest.approx(min(ratios), rel=1e-9)
        assert row["smallest_margin"][kind] > 1.0  # a kept singular value lies above the cut
    assert row["share"]["regular"] == sum(not report.kinds for report in reports) / len(reports)
    assert row["architecture_singular"] is False


def test_only_the_equal_link_design_has_end_effector_singular_samples(serial):
    shares = [row["share"]["end_effector"] for row in serial.rows]
    assert shares[0] is None and shares[1] == shares[3] == 0.0
    assert 0.0 < shares[2] < 1.0 and shares[2] * SAMPLES == round(shares[2] * SAMPLES)
    assert serial.rows[2]["share"]["regular"] == 1.0 - shares[2]


def test_a_design_without_end_effector_has_no_end_effector_share():
    row = sweep_design("slider-crank", {"end_effector": False}, 3, seed=0)
    assert row["error"] is None and row["samples"] == 3
    assert row["share"]["end_effector"] is None and row["smallest_margin"]["end_effector"] is None
    assert row["share"]["actuator"] is not None


def test_a_design_that_cannot_be_built_is_a_row_with_an_error(serial):
    first = serial.rows[0]
    assert first["parameters"] == {"crank": 0.0, "coupler": 1.0, "theta": 0.7}
    assert "cannot be built" in first["error"] and "crank" in first["error"]
    assert first["samples"] == 0 and set(first["share"].values()) == {None}
    assert all(row["error"] is None and row["samples"] == SAMPLES for row in serial.rows[1:])
    summary = serial.summary()
    assert summary["designs"] == 4 and summary["errors"] == 1 and summary["configurations"] == 3 * SAMPLES


def test_rows_do_not_depend_on_the_chunking(serial):
    for chunk in (2, 4):
        assert sweep("slider-crank", SLIDER, SAMPLES, seed=7, chunk=chunk).rows == serial.rows
    by_chunks = sweep_chunk("slider-crank", [(3, serial.grid.parameters(3)), (1, serial.grid.parameters(1))],
                            SAMPLES, 7)
    assert by_chunks == [serial.rows[3], serial.rows[1]]  # a design's row depends on its index, not its chunk


def test_the_seed_changes_the_configurations(serial):
    other = sweep("slider-crank", SLIDER, SAMPLES, seed=8)
    assert [row["smallest_margin"] for row in other.rows[1:]] != [row["smallest_margin"] for row in serial.rows[1:]]


def test_a_two_worker_local_cluster_gives_the_serial_rows(serial, cluster):
    from distributed import Client

    seen = []
    with Client(cluster, set_as_default=False) as client:
        assert len(client.nthreads()) == 2
        for chunk in (None, 3):
            result = sweep("slider-crank", SLIDER, SAMPLES, seed=7, client=client, chunk=chunk, progress=seen.append)
            assert result.rows == serial.rows
            assert [row["design"] for row in result.rows] == [0, 1, 2, 3]
    assert sum(seen) == 2 * len(serial.rows)


def test_flat_rows_and_columns(serial):
    table = serial.table()
    assert list(table[1]) == serial.columns()
    assert serial.columns()[:5] == ["design", "parameters.crank", "parameters.coupler", "parameters.theta", "samples"]
    assert table[2]["share.regular"] == serial.rows[2]["share"]["regular"]
    assert flat_row(serial.rows[2])["smallest_margin.cspace"] == serial.rows[2]["smallest_margin"]["cspace"]


def test_the_summary_pools_the_configurations(serial):
    summary = serial.summary()
    done = serial.rows[1:]
    for kind in (*KINDS, "regular"):
        assert summary["share"][kind] == pytest.approx(sum(row["share"][kind] for row in done) / len(done))
    for kind in KINDS:
        smallest = min(done, key=lambda row: row["smallest_margin"][kind])
        assert summary["smallest_margin"][kind] == {"value": smallest["smallest_margin"][kind],
                                                    "design": smallest["design"]}


def test_the_automatic_chunk_size():
    assert chunk_size(1000, 1) == 1
    assert chunk_size(10, 2) == 1 and chunk_size(640, 2) == 10 and chunk_size(641, 2) == 11
    assert chunk_size(10 ** 5, 4) == 16
    assert all(1 <= chunk_size(designs, threads) <= 16 for designs in (1, 5, 40, 400, 10 ** 5) for threads in (2, 64))


def test_design_generators_are_the_children_of_the_seed():
    children = np.random.SeedSequence(5).spawn(4)
    assert design_rng(5, 3).random() == np.random.default_rng(children[3]).random()


def test_local_workers_are_forked_on_linux_unless_dask_is_told_otherwise(monkeypatch):
    monkeypatch.delenv("DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    quiet = sweep_module.QUIET_WORKER_SETTINGS
    assert sweep_module._local_settings() == {**quiet, "distributed.worker.multiprocessing-method": "fork"}
    monkeypatch.setenv("DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD", "spawn")
    assert sweep_module._local_settings() == quiet
    monkeypatch.delenv("DASK_DISTRIBUTED__WORKER__MULTIPROCESSING_METHOD")
    monkeypatch.setattr(sys, "platform", "darwin")
    assert sweep_module._local_settings() == quiet
