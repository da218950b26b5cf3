"""``closedchain sweep``: the summary, the output files read back, where the chunks run (in this process, a
local cluster, a running scheduler) and one-line errors naming the option."""

import csv
import json
import socket
import subprocess
import sys
import threading

import pytest

from classify.cli import sweep_command
from classify.cli._common import InputError, Parser
from classify.sweep import local_cluster, sweep
from mechanisms import ConfigurationError, MechanismError

GRID = ["slider-crank", "--param", "crank=0.5:2.5:3", "--param", "coupler=1.5"]
SAMPLES = 5


def main(arguments, out):
    """What ``closedchain`` does with a subcommand: parse, run, and turn bad input into one line and status 2."""
    parser = Parser(prog="closedchain")
    sweep_command.add_parser(parser.add_subparsers(dest="command", required=True, parser_class=Parser))
    try:
        sweep_command.run(parser.parse_args(arguments), out)
        return 0
    except (InputError, MechanismError, ConfigurationError) as error:
        print(f"closedchain: error: {' '.join(str(error).split())}", file=sys.stderr)
        return 2


def run(arguments, capfd):
    """(status, stdout, stderr) of the command; file-descriptor capture, so Dask's own output is seen too."""
    status = main(["sweep", *arguments], sys.stdout)
    captured = capfd.readouterr()
    return status, captured.out, captured.err


@pytest.fixture(scope="module")
def expected():
    return sweep("slider-crank", ["crank=0.5:2.5:3", "coupler=1.5"], SAMPLES, seed=4)


@pytest.fixture(scope="module")
def scheduler():
    """The address of a running 2-worker cluster, shared by the tests of this module."""
    with local_cluster(2) as local:
        yield local.scheduler_address


def test_text_summary_in_this_process(capfd, expected):
    status, out, err = run([*GRID, "--samples", str(SAMPLES), "--seed", "4", "--scheduler", "serial"], capfd)
    assert status == 0, err
    assert err.strip() == "sweeping 3 designs of slider-crank (5 configurations each) in this process"
    lines = out.splitlines()
    assert lines[0] == ("slider-crank: 3 designs (crank 0.5 … 2.5 in 3; coupler = 1.5), 5 configurations sampled "
                        "per design, seed 4")
    assert lines[1].split()[:5] == ["design", "crank", "coupler", "samples", "actuator"]
    assert [line.split()[:4] for line in lines[2:5]] == [["0", "0.5", "1.5", "5"], ["1", "1.5", "1.5", "5"],
                                                         ["2", "2.5", "1.5", "5"]]
    summary = expected.summary()
    margin = summary["smallest_margin"]["actuator"]
    assert f"actuator {margin['value']:.3g} (design {margin['design']})" in out
    assert "share of the 15 configurations" in out and "designs in error: 0" in out


def test_json_summary_holds_the_rows(capfd, expected):
    status, out, err = run([*GRID, "--samples", str(SAMPLES), "--seed", "4", "--workers", "0", "--format", "json"],
                           capfd)
    assert status == 0, err
    document = json.loads(out)
    assert document["rows"] == list(expected.rows)
    assert document["summary"] == json.loads(json.dumps(expected.summary()))
    assert document["grid"]["axes"] == {"crank": [0.5, 1.5, 2.5]} and document["out"] is None


def test_a_local_cluster_gives_the_serial_rows(capfd, expected):
    status, out, err = run([*GRID, "--samples", str(SAMPLES), "--seed", "4", "--workers", "2", "--chunk", "2",
                            "--format", "json"], capfd)
    assert status == 0, err
    assert err.strip() == ("sweeping 3 designs of slider-crank (5 configurations each) on a local cluster of 2 "
                           "worker processes")  # nothing else from Dask
    assert json.loads(out)["rows"] == list(expected.rows)


def test_a_running_scheduler_gives_the_serial_rows(capfd, expected, scheduler):
    status, out, err = run([*GRID, "--samples", str(SAMPLES), "--seed", "4", "--scheduler", scheduler,
                            "--format", "json"], capfd)
    assert status == 0, err
    assert json.loads(out)["rows"] == list(expected.rows)
    assert err.strip().endswith(f"on the scheduler at {scheduler}")


@pytest.fixture(scope="module")
def with_end_effector():
    return sweep("slider-crank", ["crank=0.5:2.5:3", "coupler=1.5", "end_effector=true"], SAMPLES, seed=4)


@pytest.mark.parametrize("suffix", [".csv", ".json", ".parquet"])
def test_output_files_read_back_to_the_rows(capfd, tmp_path, with_end_effector, suffix):
    if suffix == ".parquet":
        pytest.importorskip("pyarrow")
    path = tmp_path / f"sweep{suffix}"
    status, out, err = run([*GRID, "--param", "end_effector=true", "--samples", str(SAMPLES), "--seed", "4",
                            "--scheduler", "serial", "--out", str(path)], capfd)
    assert status == 0, err
    assert out.splitlines()[-1] == f"rows written to {path}" and "design  crank" not in out
    result = with_end_effector
    back = sweep_command.read_table(str(path), result)
    assert back == result.table()
    assert [list(row) for row in back] == [result.columns()] * 3
    assert back[0]["parameters.end_effector"] is True and isinstance(back[0]["samples"], int)
    assert isinstance(back[0]["smallest_margin.actuator"], float)
    if suffix == ".csv":
        with open(path, newline="", encoding="utf-8") as handle:
            assert next(csv.reader(handle)) == result.columns()
    if suffix == ".json":
        document = json.loads(path.read_text())
        assert document["grid"] == json.loads(json.dumps(result.grid.to_dict())) and document["seed"] == 4
        assert document["rows"] == list(result.rows)
    if suffix == ".parquet":
        import pyarrow.parquet

        header = json.loads(pyarrow.parquet.read_schema(path).metadata[b"closedchain.sweep"])
        assert header["grid"]["axes"] == {"crank": [0.5, 1.5, 2.5]} and header["samples"] == SAMPLES


def test_a_default_parameter_given_changes_only_the_columns(expected, with_end_effector):
    assert [{key: value for key, value in row.items() if key != "parameters.end_effector"}
            for row in with_end_effector.table()] == expected.table()


def test_error_rows_reach_the_csv_file(capfd, tmp_path):
    path = tmp_path / "sweep.csv"
    status, out, err = run(["slider-crank", "--param", "crank=0:1:2", "--samples", "2", "--scheduler", "serial",
                            "--out", str(path)], capfd)
    assert status == 0, err
    rows = sweep_command.read_table(str(path))
    assert "cannot be built" in rows[0]["error"] and rows[0]["samples"] == 0 and rows[0]["share.actuator"] is None
    assert rows[1]["error"] is None and rows[1]["samples"] == 2
    assert "designs in error: 1" in out


@pytest.mark.parametrize("arguments, fragment", [
    (["--param", "length=1:2:3"], "--param length: slider-crank has no parameter 'length'"),
    (["--param", "crank=1:2:0"], "--param crank: expected at least 1 value in a:b:n, got n = 0"),
    (["--param", "crank=-inf:2:3"], "--param crank: expected a finite number, got '-inf'"),
    (["--param", "crank=1:nan:3"], "--param crank: expected a finite number, got 'nan'"),
    (["--param", "crank=1:2:400", "--param", "coupler=1:2:400", "--param", "theta=0:1:2"],
     "--param: 400 × 400 × 2 = 320000 designs exceed the limit of 100000 per sweep"),
    (["--param", "crank=1:2"], "--param crank: expected a:b:n"),
])
def test_bad_param_exits_2_with_one_line(capfd, arguments, fragment):
    status, out, err = run(["slider-crank", *arguments, "--scheduler", "serial"], capfd)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("closedchain: error: --param") and fragment in err


@pytest.mark.parametrize("arguments, fragment", [
    (["--param", "branch=7", "--param", "crank=1:2:2"],
     "--param: no design of the sweep can be built (design 0: slider-crank with crank=1.0, branch=7: cannot be "
     "built: slider-crank: branch must be 1, -1 or 0, got 7)"),
    (["--param", "actuated=1:2:2"], "--param: no design of the sweep can be built (design 0: slider-crank with "
                                    "actuated='1:2:2': cannot be built"),
])
def test_a_fixed_value_no_design_can_have_exits_2(capfd, tmp_path, arguments, fragment):
    """Every row an error, and the sweep exited 0 (classify refuses the same value with status 2)."""
    path = tmp_path / "sweep.csv"
    status, out, err = run(["slider-crank", *arguments, "--samples", "2", "--scheduler", "serial", "--out",
                            str(path)], capfd)
    assert status == 2 and out == "" and not path.exists()
    assert err.splitlines()[-1].startswith("closedchain: error: ") and fragment in err.splitlines()[-1], err


@pytest.mark.parametrize("address, fragment", [
    ("nonsense", "missing port number"),
    ("udp://127.0.0.1:8786", "unknown address scheme 'udp'"),
    ("tcp://127.0.0.1:9", "no answer within 0.3 s"),  # nothing listens on the discard port
])
def test_bad_scheduler_exits_2_with_one_line(capfd, monkeypatch, address, fragment):
    monkeypatch.setattr(sweep_command, "SCHEDULER_TIMEOUT", 0.3)
    status, out, err = run([*GRID, "--samples", "2", "--scheduler", address], capfd)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"closedchain: error: --scheduler: cannot reach a Dask "
                                                   f"scheduler at {address}") and fragment in err


@pytest.fixture
def http_server():
    """The address of a server that answers every connection as an HTTP server would (not Dask's frames)."""
    listener = socket.create_server(("127.0.0.1", 0))
    stop = threading.Event()

    def serve():
        listener.settimeout(0.1)
        while not stop.is_set():
            try:
                connection, _ = listener.accept()
            except OSError:
                continue
            with connection:
                connection.sendall(b"HTTP/1.1 400 Bad Request\r\ncontent-length: 0\r\n\r\n")
                stop.wait(1.0)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield f"tcp://127.0.0.1:{listener.getsockname()[1]}"
    stop.set()
    thread.join()
    listener.close()


def test_another_kind_of_server_exits_2_with_one_line(capfd, monkeypatch, http_server):
    """Its answer read as Dask frames was an internal error (a MemoryError of exbibytes)."""
    monkeypatch.setattr(sweep_command, "SCHEDULER_TIMEOUT", 2.0)
    status, out, err = run([*GRID, "--samples", "2", "--scheduler", http_server], capfd)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and f"--scheduler: {http_server} answers, but not as a Dask scheduler" in err


def test_a_scheduler_without_workers_exits_2_instead_of_waiting_for_ever(capfd, monkeypatch):
    from distributed import LocalCluster

    monkeypatch.setattr(sweep_command, "WORKER_WAIT", 0.5)
    with LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        status, out, err = run([*GRID, "--samples", "2", "--scheduler", cluster.scheduler_address], capfd)
    assert status == 2 and out == ""
    lines = err.splitlines()
    assert lines[0] == f"closedchain: the scheduler at {cluster.scheduler_address} has no worker yet: waiting up to 0.5 s"
    assert lines[1:] == [f"closedchain: error: --scheduler: the scheduler at {cluster.scheduler_address} has no "
                         f"worker (none joined within 0.5 s); start workers with `dask worker "
                         f"{cluster.scheduler_address}`"], err


@pytest.mark.parametrize("arguments, fragment", [
    (["--samples", "0"], "--samples: expected a count ≥ 1 and at most 10000, got 0"),
    (["--workers", "-1"], "--workers: expected a number of processes from 0 to 64, got -1"),
    (["--workers", "2", "--scheduler", "serial"], "--workers: sizes the local cluster"),
    (["--chunk", "0"], "--chunk: expected at least 1 design per task, got 0"),
    (["--out", "sweep.txt"], "--out: expected a file ending in .csv, .json, .parquet"),
    (["--out", "no/such/folder/sweep.csv"], "--out: no/such/folder/sweep.csv: no folder"),
    (["--out", "sweep.csv/"], "--out: expected a file ending in .csv"),  # was written to sweep.csv
    (["--seed", "-3"], "argument --seed: expected an integer from 0"),
    (["--scheduler", " "], "--scheduler: expected an address"),
])
def test_bad_options_exit_2_with_one_line(capfd, arguments, fragment):
    status, out, err = run([*GRID, *arguments], capfd)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and fragment in err


def test_a_name_outside_the_catalogue_exits_2(capfd):
    status = main(["sweep", "examples/five_bar.yaml"], sys.stdout)
    out, err = capfd.readouterr()
    assert status == 2 and out == "" and err.count("\n") == 1 and "is not a catalogue entry" in err


def test_parquet_without_pyarrow_says_how_to_install_it(capfd, monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow raises ImportError
    status, out, err = run([*GRID, "--out", str(tmp_path / "sweep.parquet")], capfd)
    assert status == 2 and out == "" and not (tmp_path / "sweep.parquet").exists()
    assert err.count("\n") == 1 and "--out: writing .parquet needs pyarrow: pip install pyarrow" in err


def test_the_command_module_imports_nothing_heavy():
    code = ("import sys, classify.cli.sweep_command, classify.sweep; "
            "print(sorted(name for name in ('dask', 'distributed', 'pyarrow', 'tqdm', 'sympy', 'matplotlib') "
            "if name in sys.modules))")
    listed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert listed.strip() == "[]"


def test_the_text_table_stops_at_its_limit(capfd, monkeypatch):
    monkeypatch.setattr(sweep_command, "TABLE_LIMIT", 2)
    status, out, err = run([*GRID, "--samples", "2", "--scheduler", "serial"], capfd)
    assert status == 0, err
    lines = out.splitlines()
    assert [line.split()[0] for line in lines[2:4]] == ["0", "1"]
    assert lines[4] == "  … 1 more design: every row is in --out FILE or --format json"


def test_an_output_path_that_cannot_be_written_is_refused_before_the_sweep(capfd, tmp_path):
    """A folder in the way was found only after every design had been classified (two lines on stderr)."""
    (tmp_path / "d.json").mkdir()
    status, out, err = run([*GRID, "--samples", "2", "--scheduler", "serial", "--out", str(tmp_path / "d.json")],
                           capfd)
    assert status == 2 and out == "" and err.count("\n") == 1 and "it is a folder" in err
    assert "sweeping" not in err
