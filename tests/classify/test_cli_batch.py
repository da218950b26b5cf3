"""``closedchain classify --batch``: many configurations from a file, one classification call, outputs that read back.

The batch is the Park & Kim five-bar file at its home, its six named configurations (C-space, actuator
and combined singularities among them) and three configurations projected from random displacements;
the same rows are written as JSON, JSON lines, CSV and NumPy files.
"""

import csv
import importlib
import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from classify import classify_many, model_of
from classify.cli import _batch_io, main
from mechanisms import configuration, from_displacements, to_displacements
from mechanisms.io import read

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FIVE_BAR = str(EXAMPLES / "five_bar.yaml")
SLIDER_CRANK = str(EXAMPLES / "slider_crank.yaml")


def run(argv, capsys):
    out = io.StringIO()
    status = main(argv, out=out)
    return status, out.getvalue(), capsys.readouterr().err


def _random_rows(mechanism, rng, count):
    """Closing displacements near home: random joint values projected onto M."""
    rows = []
    for _ in range(count):
        asked = {joint.name: float(value) for joint, value in zip(mechanism.joints, 0.3 * rng.standard_normal(5))}
        rows.append(to_displacements(mechanism, configuration(mechanism, asked, project_onto=True).point))
    return rows


@pytest.fixture(scope="module")
def batch():
    """(mechanism, rows of displacements, their points, classify_many of those points)."""
    document = read(FIVE_BAR)
    mechanism = document.mechanism
    rows = [{}] + list(document.configurations.values()) + _random_rows(mechanism, np.random.default_rng(11), 3)
    points = np.array([from_displacements(mechanism, row) for row in rows])
    return mechanism, rows, points, classify_many(model_of(mechanism), points)


def _write(tmp_path, suffix, mechanism, rows):
    """The rows as a batch file of the format of `suffix`."""
    path = tmp_path / f"batch{suffix}"
    if suffix == ".json":
        path.write_text(json.dumps(rows))
    elif suffix == ".jsonl":
        path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    elif suffix == ".csv":
        names = mechanism.coordinate_names
        lines = [",".join(names)] + [",".join(repr(float(row.get(name, 0.0))) for name in names) for row in rows]
        path.write_text("\n".join(lines) + "\n")
    else:
        np.save(path, np.array([[row.get(name, 0.0) for name in mechanism.coordinate_names] for row in rows]))
    return str(path)


def _json_lines(text):
    return [json.loads(line) for line in text.splitlines()]


def _assert_rows_equal(found, expected):
    """Rows of classifications equal: kinds, ranks, verdicts exactly; margins and λ's to 1e-9 relative."""
    assert found.keys() >= expected.keys()
    for key, value in expected.items():
        if isinstance(value, dict):
            _assert_rows_equal(found[key], value)
        elif isinstance(value, float):
            assert found[key] == pytest.approx(value, rel=1e-9, abs=1e-300), key
        elif isinstance(value, list) and value and isinstance(value[0], float):
            assert found[key] == pytest.approx(value, rel=1e-9), key
        else:
            assert found[key] == value, key


def _assert_same_as_single(row, single):
    """A batch row against the JSON of ``closedchain classify --at`` at the same configuration."""
    assert row["kinds"] == single["kinds"] and row["dof"] == single["dof"]
    for kind in ("cspace", "actuator", "end_effector"):
        assert row["ranks"][kind] == single[kind]["rank"]
        assert row["expected_ranks"][kind] == single[kind]["expected_rank"]
        for bound in ("smallest_kept", "largest_dropped"):
            value = single[kind]["margin"][bound]
            assert row["margins"][kind][bound] == (None if value is None else pytest.approx(value, rel=1e-9))
    proper = single["manipulability"]
    assert row["eigenvalues"] == (None if proper is None else pytest.approx(proper["eigenvalues"], rel=1e-9))
    degeneracy = single["actuator"]["degeneracy"]
    assert row["degenerate"] == {"degenerate": True, "nondegenerate": False}.get(degeneracy)


# ------------------------------------------------------------------------------------------------ round trips

@pytest.mark.parametrize("suffix", [".json", ".jsonl", ".csv", ".npy"])
def test_every_format_gives_the_rows_of_classify_many(tmp_path, capsys, batch, suffix):
    mechanism, rows, points, expected = batch
    status, out, err = run(["classify", FIVE_BAR, "--batch", _write(tmp_path, suffix, mechanism, rows)], capsys)
    assert status == 0, err
    found = _json_lines(out)
    assert [row["row"] for row in found] == list(range(1, len(rows) + 1))
    for row, wanted, point in zip(found, expected.rows(), points):
        _assert_rows_equal(row, wanted)
        np.testing.assert_allclose(from_displacements(mechanism, row["displacements"]), point, rtol=0, atol=1e-15)
    kinds = {tuple(row["kinds"]) for row in found}
    assert ("actuator",) in kinds and any("cspace" in kind for kind in kinds) and () in kinds


def test_rows_equal_single_classify_at_calls(tmp_path, capsys, batch):
    mechanism, rows, _, _ = batch
    status, out, _ = run(["classify", FIVE_BAR, "--batch", _write(tmp_path, ".jsonl", mechanism, rows)], capsys)
    assert status == 0
    found = _json_lines(out)
    for index in (1, 5, 8):  # a C-space singularity, the actuator singularity of Fig. 6a, a random configuration
        status, single, _ = run(["classify", FIVE_BAR, "--at", json.dumps(rows[index]), "--format", "json"], capsys)
        assert status == 0
        _assert_same_as_single(found[index], json.loads(single))


@pytest.mark.parametrize("suffix", [".jsonl", ".json", ".csv"])
def test_out_files_read_back(tmp_path, capsys, batch, suffix):
    mechanism, rows, _, expected = batch
    out_path = tmp_path / f"out{suffix}"
    status, out, _ = run(["classify", FIVE_BAR, "--batch", _write(tmp_path, ".json", mechanism, rows),
                          "--out", str(out_path)], capsys)
    assert status == 0 and out.count("\n") == 1 and "written to" in out and f"{len(rows)} configurations" in out
    text = out_path.read_text()
    if suffix == ".jsonl":
        found = _json_lines(text)
    elif suffix == ".json":
        found = json.loads(text)
    else:
        table = list(csv.DictReader(io.StringIO(text)))
        assert len(table) == len(rows)
        for line, wanted in zip(table, expected.rows()):
            assert line["kinds"] == ";".join(wanted["kinds"])
            assert int(line["ranks_actuator"]) == wanted["ranks"]["actuator"]
            kept = wanted["margins"]["actuator"]["smallest_kept"]
            assert line["margins_actuator_smallest_kept"] == ("" if kept is None else repr(kept))
            condition = wanted["condition_number"]
            assert line["condition_number"] == ("" if condition is None else repr(condition))
        return
    for row, wanted in zip(found, expected.rows()):
        _assert_rows_equal(row, wanted)


def test_npz_holds_the_arrays_points_and_displacements(tmp_path, capsys, batch):
    mechanism, rows, points, expected = batch
    out_path = tmp_path / "out.npz"
    status, _, _ = run(["classify", FIVE_BAR, "--batch", _write(tmp_path, ".csv", mechanism, rows),
                        "--out", str(out_path)], capsys)
    assert status == 0
    with np.load(out_path) as saved:
        for name, array in expected.arrays().items():
            np.testing.assert_array_equal(saved[name], array, err_msg=name)
        np.testing.assert_array_equal(saved["points"], points)
        np.testing.assert_array_equal(saved["row"], np.arange(1, len(rows) + 1))
        assert tuple(saved["coordinate_names"]) == mechanism.coordinate_names
        for displacement, point in zip(saved["displacements"], points):
            given = dict(zip(mechanism.coordinate_names, displacement))
            np.testing.assert_array_equal(from_displacements(mechanism, given), point)


def test_text_table_has_one_line_per_row(tmp_path, capsys, batch):
    mechanism, rows, _, expected = batch
    status, out, _ = run(["classify", FIVE_BAR, "--batch", _write(tmp_path, ".json", mechanism, rows),
                          "--format", "text"], capsys)
    assert status == 0
    lines = out.splitlines()
    assert lines[0].split()[:3] == ["row", "kinds", "C-space"]
    body = lines[2:2 + len(rows)]
    for line, index in zip(body, range(len(rows))):
        assert line.split()[0] == str(index + 1)
        assert (", ".join(expected.kinds(index)) or "regular") in line
    assert lines[-1].startswith(f"classified {len(rows)} configurations")


def test_project_moves_rows_onto_m_as_at_does(tmp_path, capsys):
    """Rows off M are projected; each equals ``--at ROW --project`` (distance and classification)."""
    mechanism = read(SLIDER_CRANK).mechanism
    rows = [{"crank": 0.1}, {"crank": -0.2, "slide": 0.05}, {}]
    path = tmp_path / "off.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    status, _, err = run(["classify", SLIDER_CRANK, "--batch", str(path)], capsys)
    assert status == 2 and "row 1:" in err and "does not close the loops" in err and "--project" in err
    status, out, _ = run(["classify", SLIDER_CRANK, "--batch", str(path), "--project"], capsys)
    assert status == 0
    for row, given in zip(_json_lines(out), rows):
        status, single, _ = run(["classify", SLIDER_CRANK, "--at", json.dumps(given), "--project", "--format", "json"],
                                capsys)
        single = json.loads(single)
        assert row["projection_distance"] == pytest.approx(single["projection_distance"], rel=1e-9, abs=1e-15)
        _assert_same_as_single(row, single)
        assert from_displacements(mechanism, row["displacements"]) == pytest.approx(
            from_displacements(mechanism, single["configuration"]), abs=1e-12)
    assert _json_lines(out)[2]["projection_distance"] == 0.0


def test_catalogue_entry_rows_start_from_its_configuration(tmp_path, capsys):
    """A catalogue entry is built at its configuration: {} is that configuration (as ``classify NAME``)."""
    path = tmp_path / "rows.json"
    path.write_text("[{}]")
    status, out, _ = run(["classify", "slider-crank", "--configuration", "fig3c_dead_centre", "--batch", str(path)],
                         capsys)
    status_single, single, _ = run(["classify", "slider-crank", "--configuration", "fig3c_dead_centre",
                                    "--format", "json"], capsys)
    assert status == status_single == 0
    _assert_same_as_single(_json_lines(out)[0], json.loads(single))
    assert _json_lines(out)[0]["kinds"] == ["end_effector"]


# ------------------------------------------------------------------------------------------------ the survey

def _counting_surveys(monkeypatch):
    survey_module = importlib.import_module("classify.survey")  # the module (classify.survey is also a function)
    calls = []
    original = survey_module.survey

    def counted(*arguments, **options):
        calls.append(1)
        return original(*arguments, **options)

    monkeypatch.setattr(survey_module, "survey", counted)
    return calls


def test_survey_file_is_written_then_reused(tmp_path, capsys, monkeypatch, batch):
    mechanism, rows, _, _ = batch
    calls = _counting_surveys(monkeypatch)
    survey_path = tmp_path / "five-bar.survey.json"
    argv = ["classify", FIVE_BAR, "--batch", _write(tmp_path, ".json", mechanism, rows), "--survey", str(survey_path)]
    first = run(argv, capsys)
    assert first[0] == 0 and len(calls) == 1 and survey_path.exists()
    second = run(argv, capsys)  # a new mechanism object, read from the file again: its survey comes from the cache
    assert second[0] == 0 and len(calls) == 1
    assert second[1] == first[1]
    single = run(["classify", FIVE_BAR, "--at", json.dumps(rows[6]), "--survey", str(survey_path), "--format",
                  "json"], capsys)
    assert single[0] == 0 and len(calls) == 1
    assert json.loads(single[1])["survey"] == json.loads(survey_path.read_text())["survey"]


def test_a_survey_file_of_another_mechanism_is_refused(tmp_path, capsys):
    survey_path = tmp_path / "survey.json"
    assert run(["classify", SLIDER_CRANK, "--survey", str(survey_path)], capsys)[0] == 0
    status, _, err = run(["classify", FIVE_BAR, "--survey", str(survey_path)], capsys)
    assert status == 2 and err.count("\n") == 1
    assert err.startswith("closedchain: error: --survey:") and "another mechanism" in err


# ------------------------------------------------------------------------------------------------ malformed files

CSV_HEADER = "J1,J2,J3,J4,J5\n"
ZEROS = "0,0,0,0,0\n"

MALFORMED = [
    # (id, suffix, content, fragments the one-line message must contain)
    ("json-syntax", ".json", '[{"J1": 0}, {"J1": }]', ["row 2:", "cannot parse JSON"]),
    ("json-not-object", ".json", '[{"J1": 0}, [0.1]]', ["row 2:", "expected a JSON object", "got a list"]),
    ("json-unknown-joint", ".json", '[{}, {"J9": 0.1}]', ["row 2:", "joint 'J9'", "unknown joint"]),
    ("json-nan", ".json", '[{"J1": NaN}]', ["row 1:", "joint 'J1'", "finite"]),
    ("json-infinity", ".json", '[{}, {}, {"J2": -Infinity}]', ["row 3:", "joint 'J2'", "finite"]),
    ("json-huge", ".json", '[{"J1": 1e300}]', ["row 1:", "joint 'J1'", "out of range"]),
    ("json-list-for-number", ".json", '[{"J1": [0.1, 0.2]}]', ["row 1:", "joint 'J1'", "expected a number"]),
    ("json-string", ".json", '[{"J1": "0.1"}]', ["row 1:", "joint 'J1'", "expected a number"]),
    ("json-duplicate", ".json", '[{"J1": 0, "J1": 0}]', ["row 1:", "duplicate key 'J1'"]),
    # a nonzero number below the smallest float was read as 0 (CSV cells refused it already)
    ("json-underflow", ".json", '[{}, {"J1": 1e-400}]', ["row 2:", "1e-400 is nonzero but below the smallest"]),
    ("jsonl-underflow", ".jsonl", '{}\n{"J1": -0.5e-330}\n', ["row 2 (line 2):", "-0.5e-330 is nonzero but"]),
    ("json-not-a-list", ".json", '{"J1": 0}', ["expected a JSON list"]),
    ("json-trailing", ".json", '[{}] [{}]', ["extra data"]),
    ("json-unterminated", ".json", '[{}, {}', ["row 2:", "expected ',' or ']'"]),
    ("jsonl-syntax", ".jsonl", '{}\n{}\n{"J1" 0}\n', ["row 3 (line 3):", "cannot parse JSON"]),
    ("jsonl-two-objects", ".jsonl", '{}\n{} {}\n', ["row 2 (line 2):", "extra data"]),
    ("jsonl-blank-lines-skipped", ".jsonl", '{}\n\n{"J3": 1}\n{"J3" 1}\n', ["row 3 (line 4):", "cannot parse"]),
    ("csv-unknown-column", ".csv", "J1,J9\n0,0\n", ["header (line 1), column 2:", "unknown coordinate 'J9'"]),
    ("csv-duplicate-column", ".csv", "J1,J1\n0,0\n", ["header (line 1), column 2:", "given twice"]),
    ("csv-short-row", ".csv", CSV_HEADER + ZEROS + "0,0,0\n", ["row 2 (line 3):", "expected 5 values", "got 3"]),
    ("csv-text-cell", ".csv", CSV_HEADER + "0,abc,0,0,0\n", ["row 1 (line 2):", "column 'J2'", "expected a number"]),
    ("csv-nan", ".csv", CSV_HEADER + ZEROS + ZEROS + "0,0,0,nan,0\n", ["row 3 (line 4):", "column 'J4'", "finite"]),
    ("csv-empty-cell", ".csv", CSV_HEADER + "0,0,,0,0\n", ["row 1 (line 2):", "column 'J3'", "an empty cell"]),
    ("csv-no-header", ".csv", "\n\n", ["no header"]),
    ("empty-json", ".json", "[]", ["no configurations"]),
    ("empty-csv", ".csv", CSV_HEADER, ["no configurations"]),
    ("unknown-format", ".txt", "{}", ["unknown batch format '.txt'"]),
    ("not-utf8", ".jsonl", b"\xff\xfe{}", ["not UTF-8"]),
    ("off-manifold", ".json", '[{}, {"J1": 0.3}]', ["row 2:", "does not close the loops"]),
]


@pytest.mark.parametrize("case", MALFORMED, ids=[case[0] for case in MALFORMED])
def test_malformed_batch_files_exit_2_with_one_line_naming_the_row(tmp_path, capsys, case):
    _, suffix, content, fragments = case
    path = tmp_path / f"bad{suffix}"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    status, out, err = run(["classify", FIVE_BAR, "--batch", str(path)], capsys)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith(f"closedchain: error: --batch: {path}")
    for fragment in fragments:
        assert fragment in err, (fragment, err)


def _npy(tmp_path, array):
    path = tmp_path / "bad.npy"
    np.save(path, array)
    return path


@pytest.mark.parametrize("array, fragments", [
    (np.zeros((3, 4)), ["field 'shape'", "[n, 5]", "got shape [3, 4]"]),
    (np.zeros(5), ["field 'shape'", "got shape [5]"]),
    (np.array([[0, 0, 0, 0, 0], [0, 0, np.nan, 0, 0]], dtype=float), ["row 2:", "column 3 (J3)", "finite"]),
    (np.array([[0, 0, 0, 0, 2e12]]), ["row 1:", "column 5 (J5)", "out of range"]),
    (np.array([["a", "b", "c", "d", "e"]]), ["expected an array of real numbers"]),
    (np.zeros((0, 5)), ["no configurations"]),
    pytest.param(np.zeros((1, 5), dtype=np.longdouble), ["expected float64 or a narrower type", "would be rounded"],
                 marks=pytest.mark.skipif(np.dtype(np.longdouble).itemsize <= 8, reason="long double is float64 here")),
])
def test_malformed_npy_files(tmp_path, capsys, array, fragments):
    path = _npy(tmp_path, array)
    status, _, err = run(["classify", FIVE_BAR, "--batch", str(path)], capsys)
    assert status == 2 and err.count("\n") == 1 and err.startswith(f"closedchain: error: --batch: {path}")
    for fragment in fragments:
        assert fragment in err, (fragment, err)


def test_npy_that_is_not_an_array_file(tmp_path, capsys):
    path = tmp_path / "bad.npy"
    path.write_bytes(b"\x93NUMPY garbage")
    status, _, err = run(["classify", FIVE_BAR, "--batch", str(path)], capsys)
    assert status == 2 and err.count("\n") == 1 and "not a NumPy .npy array file" in err


@pytest.mark.parametrize("suffix", [".json", ".jsonl", ".csv", ".npy"])
def test_too_many_rows_are_refused_at_the_first_row_beyond_the_limit(tmp_path, capsys, monkeypatch, batch, suffix):
    mechanism, rows, _, _ = batch
    monkeypatch.setattr(_batch_io, "BATCH_ROW_LIMIT", 3)
    path = _write(tmp_path, suffix, mechanism, [{}] * 4)
    status, _, err = run(["classify", FIVE_BAR, "--batch", path], capsys)
    assert status == 2 and err.count("\n") == 1
    assert "row 4" in err and "too many rows (at most 3)" in err
    monkeypatch.setattr(_batch_io, "BATCH_ROW_LIMIT", 4)
    assert run(["classify", FIVE_BAR, "--batch", path], capsys)[0] == 0


def test_a_missing_or_special_file_is_refused(tmp_path, capsys):
    (tmp_path / "folder.json").mkdir()
    (tmp_path / "folder.npy").mkdir()
    for name, reason in (("missing.json", "No such file"), ("missing.npy", "No such file"),
                         ("folder.json", "directory"), ("folder.npy", "not a regular file")):
        status, _, err = run(["classify", FIVE_BAR, "--batch", str(tmp_path / name)], capsys)
        assert status == 2 and err.count("\n") == 1, err
        assert err.startswith(f"closedchain: error: --batch: {tmp_path / name}") and reason in err


@pytest.mark.parametrize("suffix", [".json", ".npy"])
def test_a_path_with_a_nul_byte_is_refused_in_the_same_words_for_every_format(tmp_path, capsys, suffix):
    status, _, err = run(["classify", FIVE_BAR, "--batch", str(tmp_path / f"a\x00b{suffix}")], capsys)
    assert status == 2 and err.count("\n") == 1, err
    assert "cannot read the file: the path has a NUL byte in it" in err


@pytest.mark.parametrize("extra, fragment", [
    (["--at", "{}"], "--at: does not apply with --batch"),
    (["--assemble"], "--assemble: does not apply with --batch"),
    (["--seed", "3"], "--seed: does not apply with --batch"),
    (["--out", "x.txt"], "--out: x.txt: expected a file ending in"),
    (["--out", "x.jsonl", "--format", "text"], "--format: applies to what is printed"),
])
def test_options_that_do_not_apply_to_a_batch(tmp_path, capsys, extra, fragment):
    path = tmp_path / "rows.json"
    path.write_text("[{}]")
    status, _, err = run(["classify", FIVE_BAR, "--batch", str(path), *extra], capsys)
    assert status == 2 and err.count("\n") == 1 and fragment in err


def test_at_refuses_a_number_below_the_smallest_float(capsys):
    status, _, err = run(["classify", FIVE_BAR, "--at", '{"J1": 1e-400}'], capsys)
    assert status == 2 and err.count("\n") == 1 and "--at: cannot parse JSON: 1e-400 is nonzero but below" in err


@pytest.mark.parametrize("option", [["--out", "x.jsonl"], ["--threads", "2"]])
def test_batch_options_without_batch_are_refused(capsys, option):
    status, _, err = run(["classify", FIVE_BAR, *option], capsys)
    assert status == 2 and f"{option[0]}: applies with --batch" in err


def test_threads_reach_classify_many_and_do_not_change_the_output(tmp_path, capsys, monkeypatch, batch):
    import classify.batch

    mechanism, rows, _, _ = batch
    path = _write(tmp_path, ".jsonl", mechanism, rows)
    asked = []
    original = classify.batch.classify_many

    def recording(*arguments, workers=1, **options):
        asked.append(workers)
        return original(*arguments, workers=workers, chunk=2, **options)  # several chunks, so threads have work

    monkeypatch.setattr(classify.batch, "classify_many", recording)
    outputs = {}
    for threads in (None, "1", "2"):
        status, outputs[threads], err = run(["classify", FIVE_BAR, "--batch", path]
                                            + ([] if threads is None else ["--threads", threads]), capsys)
        assert status == 0, err
    assert asked == [-1, 1, 2]
    assert outputs["1"] == outputs["2"] == outputs[None]


@pytest.mark.parametrize("value", ["0", "-2", "two", "1.5", "257"])
def test_bad_thread_counts_exit_2_naming_the_option(tmp_path, capsys, value):
    path = tmp_path / "rows.json"
    path.write_text("[{}]")
    status, _, err = run(["classify", FIVE_BAR, "--batch", str(path), "--threads", value], capsys)
    assert status == 2 and err.count("\n") == 1 and "--threads" in err and value in err


# ------------------------------------------------------------------------------------------------ progress

class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_only_on_a_terminal_and_after_a_second(monkeypatch):
    from classify import progress

    monkeypatch.delenv("CI", raising=False)
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert not progress.show_progress()
    bar = progress.progress_bar(10, "classifying")
    assert not hasattr(bar, "delay")
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert progress.show_progress()
    bar = progress.progress_bar(10, "classifying")
    bar.update(10)
    bar.close()
    assert bar.delay == 1.0 and terminal.getvalue() == ""  # shorter than a second: never drawn
    monkeypatch.setenv("CI", "1")
    assert not progress.show_progress()


def test_batch_modules_import_nothing_heavy_at_start_up():
    """The command modules are imported by ``closedchain --help``: no NumPy, tqdm or numerical code then."""
    import subprocess

    code = ("import sys, classify.cli.classify_command, classify.cli.map_command; "
            "print(sorted(name for name in ('numpy', 'tqdm', 'sympy', 'scipy', 'classify.batch', "
            "'classify.cli._batch_io') if name in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "[]"


def test_the_displacements_of_a_csv_out_file_are_a_batch_file_again(tmp_path, capsys):
    """The Gough–Stewart's S joints: the CSV named their columns by index (``displacements_S1[0]``), which a
    batch file does not take (its coordinates are ``S1[x]``…): the file did not read back."""
    batch_path = tmp_path / "batch.jsonl"
    batch_path.write_text('{"P1": 0.01, "P2": -0.02}\n{"P3": 0.015}\n')
    out_path = tmp_path / "out.csv"
    status, _, err = run(["classify", "gough-stewart", "--batch", str(batch_path), "--project", "--out",
                          str(out_path)], capsys)
    assert status == 0, err
    table = list(csv.DictReader(io.StringIO(out_path.read_text())))
    columns = [name for name in table[0] if name.startswith("displacements_")]
    assert "displacements_S1[x]" in columns
    again = tmp_path / "again.csv"
    with again.open("w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow([name[len("displacements_"):] for name in columns])
        writer.writerows([[line[name] for name in columns] for line in table])
    status, _, err = run(["classify", "gough-stewart", "--batch", str(again), "--out", str(tmp_path / "b.csv")],
                         capsys)
    assert status == 0, err
    second = list(csv.DictReader(io.StringIO((tmp_path / "b.csv").read_text())))
    assert [line["kinds"] for line in second] == [line["kinds"] for line in table]
    for first, back in zip(table, second):
        for name in columns:
            assert float(back[name]) == pytest.approx(float(first[name]), abs=1e-12)
