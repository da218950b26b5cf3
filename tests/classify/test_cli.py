"""The ``closedchain`` command: contract JSON, exit codes, one-line errors."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from classify.cli import InputError
from classify.cli._common import write_output
from builders import command as run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CONTRACT_KEYS = {"mechanism", "dof", "singular", "kinds", "cspace", "actuator", "end_effector", "manipulability"}


def configuration(file, name):
    return yaml.safe_load((EXAMPLES / file).read_text())["configurations"][name]


def test_classify_json_follows_the_contract(capsys):
    at = json.dumps(configuration("five_bar.yaml", "fig6a_distal_aligned"))
    status, out, err = run(["classify", str(EXAMPLES / "five_bar.yaml"), "--at", at, "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert CONTRACT_KEYS <= set(result)
    assert result["mechanism"] == "park-kim five-bar" and result["dof"] == 2
    assert result["singular"] is True and result["kinds"] == ["actuator"]
    cspace = result["cspace"]
    assert (cspace["singular"], cspace["rank"], cspace["expected_rank"]) == (False, 3, 3)
    actuator = result["actuator"]
    assert (actuator["singular"], actuator["rank"], actuator["expected_rank"], actuator["degeneracy"]) == \
        (True, 1, 2, "nondegenerate")
    assert result["end_effector"]["singular"] is False
    assert result["manipulability"] is None


def test_classify_home_json_has_manipulability(capsys):
    status, out, _ = run(["classify", str(EXAMPLES / "five_bar.yaml"), "--format", "json"], capsys)
    result = json.loads(out)
    assert status == 0 and result["kinds"] == [] and result["actuator"]["degeneracy"] is None
    assert set(result["manipulability"]) >= {"eigenvalues", "condition_number", "volume"}
    assert len(result["manipulability"]["eigenvalues"]) == 2


def test_at_from_a_file_and_text_output(tmp_path, capsys):
    at = tmp_path / "at.json"
    at.write_text(json.dumps(configuration("slider_crank_slider_driven.yaml", "constant_branch")))
    status, out, _ = run(["classify", str(EXAMPLES / "slider_crank_slider_driven.yaml"), "--at", f"@{at}"], capsys)
    assert status == 0
    assert "degenerate" in out and "self-motion" in out and "σ" in out


def test_configuration_that_does_not_close_needs_project(capsys):
    file = str(EXAMPLES / "five_bar.yaml")
    status, out, err = run(["classify", file, "--at", '{"J1": 0.1}'], capsys)
    assert status == 2 and out == "" and err.count("\n") == 1 and "--project" in err
    status, out, err = run(["classify", file, "--at", '{"J1": 0.1}', "--project", "--format", "json"], capsys)
    assert status == 0
    assert json.loads(out)["projection_distance"] > 0


@pytest.mark.parametrize("arguments, fragment", [
    (["classify", "missing.yaml"], "missing.yaml"),
    (["classify", "{five}", "--at", "{not json"], "--at"),
    (["classify", "{five}", "--at", "[1, 2]"], "--at"),
    (["classify", "{five}", "--at", '{"J9": 0.1}'], "J9"),
    (["classify", "{five}", "--at", '{"J1": "0.1"}'], "J1"),
    (["classify", "{five}", "--at", "@/nonexistent/at.json"], "--at"),
    (["classify", "{five}", "--format", "xml"], "--format"),
    (["classify", "{five}", "--length-scale", "-1"], "--length-scale"),
    (["frobnicate"], "frobnicate"),
    (["report", "/nonexistent/folder"], "/nonexistent/folder"),
])
def test_bad_command_lines_exit_2_with_one_line(arguments, fragment, capsys):
    arguments = [a.replace("{five}", str(EXAMPLES / "five_bar.yaml")) for a in arguments]
    status, out, err = run(arguments, capsys)
    assert status == 2
    assert err.count("\n") == 1 and err.startswith("closedchain: error:") and fragment in err
    assert "Traceback" not in err


def test_every_malformed_file_exits_2_with_one_line(malformed_case, tmp_path, capsys):
    case_id, text, suffix, fragment = malformed_case
    path = tmp_path / f"mechanism{suffix}"
    path.write_text(text)
    status, out, err = run(["classify", str(path)], capsys)
    assert status == 2, err
    assert err.count("\n") == 1 and err.startswith("closedchain: error:")
    assert fragment in err and "Traceback" not in err


def test_installed_command_runs_as_a_process(tmp_path):
    """The console script is wired: a subprocess gets exit 2 and no traceback on bad input."""
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nspace: conformal\njoints: []\n")
    process = subprocess.run([sys.executable, "-m", "classify", "classify", str(bad)],
                             capture_output=True, text=True)
    assert process.returncode == 2 and "Traceback" not in process.stderr
    assert len(process.stderr.strip().splitlines()) == 1


def test_report_classifies_every_example(tmp_path, capsys):
    output = tmp_path / "report.txt"
    status, out, _ = run(["report", str(EXAMPLES), "--output", str(output)], capsys)
    assert status == 0
    text = output.read_text()
    for row in ("fig1a_collinear", "fig6a_distal_aligned", "fig6b_elbows_coincide", "fig3a_self_intersection",
                "fig3b_actuator", "fig3c_dead_centre", "fig3d_dead_centre", "constant_branch"):
        assert row in text
    assert "nondegenerate" in text and "degenerate" in text


# ---------------------------------------------------------------- the catalogue

def test_catalog_lists_every_entry(capsys):
    from mechanisms.catalogue import names
    status, out, _ = run(["catalog"], capsys)
    assert status == 0
    assert all(name in out for name in names())
    status, out, _ = run(["catalog", "--format", "json"], capsys)
    listed = json.loads(out)
    assert [item["name"] for item in listed] == list(names())
    assert listed[0]["parameters"]["crank"] == 2.0


def test_catalog_describes_an_entry_with_its_values(capsys):
    status, out, _ = run(["catalog", "slider-crank", "--configuration", "fig3c_dead_centre",
                          "--param", "crank=3"], capsys)
    assert status == 0
    assert "crank = 3.0  (default 2.0)" in out and "theta = 0.0" in out and "fig3b_actuator" in out


def test_catalog_writes_a_mechanism_file_that_classifies_like_the_entry(tmp_path, capsys):
    path = tmp_path / "dead_centre.yaml"
    status, _, err = run(["catalog", "slider-crank", "--configuration", "fig3c_dead_centre",
                          "--write", str(path)], capsys)
    assert status == 0, err
    _, from_file, _ = run(["classify", str(path), "--format", "json"], capsys)
    _, from_entry, _ = run(["classify", "slider-crank", "--configuration", "fig3c_dead_centre",
                            "--format", "json"], capsys)
    assert json.loads(from_file)["kinds"] == json.loads(from_entry)["kinds"] == ["end_effector"]
    assert "fig3c_dead_centre" in yaml.safe_load(path.read_text())["description"]


def test_classify_a_catalogue_entry_with_parameters_and_at(capsys):
    status, out, _ = run(["classify", "slider-crank", "--param", "theta=0.5235987755982988",
                          "--format", "json"], capsys)
    assert status == 0 and json.loads(out)["kinds"] == ["actuator"]
    status, _, err = run(["classify", "slider-crank", "--at", '{"crank": 0.2}'], capsys)
    assert status == 2 and "does not close" in err


def test_a_files_named_configuration_is_classified(capsys):
    status, out, _ = run(["classify", str(EXAMPLES / "five_bar.yaml"), "--configuration",
                          "fig6a_distal_aligned", "--format", "json"], capsys)
    assert status == 0 and json.loads(out)["kinds"] == ["actuator"]


@pytest.mark.parametrize("arguments, message", [
    (["classify", "slider-crank", "--param", "theta=1.2"], "theta = 1.2: the coupler cannot reach"),
    (["classify", "slider-crank", "--param", "theta=pi"], "--param theta: expected a number"),
    (["classify", "slider-crank", "--configuration", "fig9"], "unknown configuration 'fig9'"),
    (["classify", "no-such-linkage"], "no-such-linkage: no such file or catalogue entry"),
    (["classify", str(EXAMPLES / "five_bar.yaml"), "--param", "theta=1"], "--param: applies to catalogue"),
    (["classify", str(EXAMPLES / "five_bar.yaml"), "--configuration", "fig9"], "has no configuration 'fig9'"),
    (["catalog", "no-such-linkage"], "no catalogue entry 'no-such-linkage'"),
    (["catalog", "--write", "x.yaml"], "need a catalogue NAME"),
    (["catalog", "slider-crank", "--write", "x.txt"], "x.txt"),
])
def test_catalogue_input_errors_exit_2_with_one_line(arguments, message, capsys):
    status, out, err = run(arguments, capsys)
    assert status == 2 and out == ""
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_report_of_catalogue_entries_and_files(capsys):
    status, out, err = run(["report", "slider-crank", str(EXAMPLES / "slider_crank.yaml"),
                            "--format", "json"], capsys)
    assert status == 0
    rows = json.loads(out)
    sources = {row["source"] for row in rows}
    assert sources == {"slider-crank", str(EXAMPLES / "slider_crank.yaml")}
    named = {row["configuration_name"]: row["kinds"] for row in rows if row["source"] == "slider-crank"}
    assert named["default"] == [] and named["fig3b_actuator"] == ["actuator"]
    assert err == ""  # no per-row lines; the progress bar shows only on a terminal


def test_report_puts_the_derived_gosselin_angeles_kinds_next_to_park_kim(capsys):
    """An additive column and JSON field: the five-bar's Fig. 6a is kind II and corresponds."""
    status, out, _ = run(["report", "five-bar", "--format", "json"], capsys)
    assert status == 0
    rows = {row["configuration_name"]: row for row in json.loads(out)}
    comparison = rows["fig6a_distal_aligned"]["comparison"]
    assert comparison["gosselin_angeles"]["kinds"] == ["II"] and comparison["agree"] is True
    assert rows["fig1a_collinear"]["comparison"]["reason"] == "cspace_singularity"
    status, out, _ = run(["report", "five-bar"], capsys)
    header = next(line for line in out.splitlines() if line.startswith("source "))
    assert "G–A (derived)" in header and "undefined (cspace_singularity)" in out


# ---------------------------------------------------------------- outputs that show their inputs

def test_classify_names_the_catalogue_source_its_parameters_and_joint_values(capsys):
    arguments = ["classify", "slider-crank", "--configuration", "fig3b_actuator", "--param", "coupler=1.5"]
    status, out, err = run(arguments + ["--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    parameters = {"crank": 2.0, "coupler": 1.5, "theta": 0.5235987755982989, "branch": 1, "actuated": "crank",
                  "end_effector": True}
    assert result["source"] == {"catalogue": "slider-crank", "parameters": parameters,
                                "configuration": "fig3b_actuator"}
    assert result["joint_values"] == {"crank": 0.0, "pin": 0.0, "wrist": 0.0, "slide": 0.0}
    assert result["configuration"] == {"crank": 0.0, "pin": 0.0, "wrist": 0.0, "slide": 0.0}  # kept
    status, out, _ = run(arguments, capsys)
    assert "source: catalogue entry slider-crank, configuration fig3b_actuator" in out
    assert "coupler = 1.5" in out and "theta = 0.5236" in out
    assert "joint values" in out and "crank = 0, pin = 0, wrist = 0, slide = 0" in out


def test_classify_names_the_file_source_and_its_joint_values(capsys):
    path = str(EXAMPLES / "five_bar.yaml")
    named = configuration("five_bar.yaml", "fig6a_distal_aligned")
    arguments = ["classify", path, "--configuration", "fig6a_distal_aligned"]
    status, out, err = run(arguments + ["--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["source"] == {"file": path, "configuration": "fig6a_distal_aligned"}
    assert result["joint_values"] == pytest.approx(named)
    status, out, _ = run(arguments, capsys)
    assert f"source: file {path}, configuration fig6a_distal_aligned" in out
    assert f"J1 = {named['J1']:.4g}" in out
    status, out, _ = run(["classify", path, "--at", json.dumps(named), "--format", "json"], capsys)
    assert json.loads(out)["source"] == {"file": path, "configuration": None, "at": named}


def _has_raw_control(text):
    """Whether the text holds a non-printable character other than the line breaks between its lines."""
    return any(not line.isprintable() for line in text.split("\n"))


def test_text_output_escapes_control_characters_in_names():
    """An ESC sequence or a newline in a name is printed escaped; JSON keeps the exact name."""
    from dataclasses import replace

    import numpy as np

    from classify import classify, compare
    from classify.cli.report_command import ReportRow, report_table
    from classify.comparison import comparison_row
    from classify.model import model_of
    from classify.report import printable
    from mechanisms import EndEffector, Joint, Mechanism, home

    colour, forged = "J\u001b[31m", "J\nclosedchain: error: forged"
    mechanism = Mechanism("five\u0000bar", "planar", [
        Joint("J1", "R", ("ground", "proximal1"), point=(0, 0), actuated=True),
        Joint(colour, "R", ("proximal1", "distal1"), point=(0, 1)),
        Joint(forged, "R", ("distal1", "distal2"), point=(1, 1)),
        Joint("J4", "R", ("distal2", "proximal2"), point=(2, 1)),
        Joint("J5", "R", ("proximal2", "ground"), point=(2, 0), actuated=True),
    ], end_effector=EndEffector("distal1", (1, 1), "position"))
    point = home(mechanism)
    report = classify(mechanism, point, rng=np.random.default_rng(0))
    report = replace(report, source={"file": "a\u001b]0;title\u0007.yaml", "configuration": "x\ny"})
    text = report.to_text()
    assert "lost direction" in text and not _has_raw_control(text)
    assert printable(colour) in text and printable(forged) in text and "\\x00" in text
    assert not any(line.startswith("closedchain: error") for line in text.splitlines())
    comparison = compare(mechanism, [point], labels=["home\u001b[2J"], rng=np.random.default_rng(0))
    assert not _has_raw_control(comparison.to_text(source=report.source))
    row = ReportRow("a\u001b[31m.yaml", "x\ny", report, comparison_row(model_of(mechanism), point, report, "x\ny"))
    assert not _has_raw_control(report_table([row]))
    exact = json.loads(json.dumps(report.to_dict()))
    assert exact["mechanism"] == "five\u0000bar"
    assert colour in exact["joint_values"] and forged in exact["configuration"]


# ------------------------------------------- option refusals found by fuzzing (issue 10)

def refused(arguments, capsys):
    """The one stderr line of a refused command, without its "closedchain: error: " prefix."""
    status, out, err = run(arguments, capsys)
    assert status == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("closedchain: error: ")
    return err[len("closedchain: error: "):].rstrip("\n")


@pytest.mark.parametrize("arguments, message", [
    (["classify", "five-bar", "--seed", "-1"], "argument --seed: expected an integer from 0 to 2**64 - 1, got -1"),
    (["classify", "five-bar", "--seed", str(2 ** 64)],
     "argument --seed: expected an integer from 0 to 2**64 - 1, got 18446744073709551616"),
    (["classify", "five-bar", "--length-scale", "nan"], "argument --length-scale: expected a positive finite number, "
                                                         "got nan"),
    (["classify", "five-bar", "--length-scale", "1e300"],
     "--length-scale: expected a value from 8e-06 to 8e+06 (within a factor 1e+06 of the characteristic length 8 of "
     "the mechanism), got 1e+300"),
    (["compare", "five-bar", "--samples", "1000000000"],
     "--samples: expected a count ≥ 0 and at most 10000, got 1000000000"),
    (["compare", "five-bar", "--path", "10001"], "--path: expected a count ≥ 0 and at most 10000, got 10001"),
    (["compare", "five-bar", "--path-step", "1e300"],
     "--path-step: expected a step from 1e-09 to 1 (joint coordinates: radians, and lengths in units of the "
     "mechanism's characteristic length), got 1e+300"),
    (["classify", "five-bar", "--param", "base=1e308"],
     "--param base: 1e+308 is out of range (at most 1e+12 in absolute value)"),
    (["classify", "five-bar", "--param", "actuated=\udcff"], "--param actuated: not valid text: lone surrogate "
                                                              "U+DCFF at position 0"),
    (["classify", "five-bar", "--at", '{"A": ' + "9" * 5000 + "}"],
     "--at: cannot parse JSON: an integer of 5000 digits is out of range (at most 400)"),
    (["classify", "five-bar", "--at", "[" * 100_000], "--at: cannot parse JSON: the document nests deeper than 20 "
                                                      "levels"),
    (["classify", "five-bar", "--at", '{"A": NaN}'], "--at: joint 'A': expected a finite number, got nan"),
    (["classify", "five-bar", "--at", '{"A": 1e13}'], "--at: joint 'A': 1e+13 is out of range (displacements are "
                                                      "at most 1e+12 in absolute value)"),
])
def test_absurd_option_values_are_refused_with_one_line(arguments, message, capsys):
    assert refused(arguments, capsys) == message


def test_param_that_makes_no_mechanism_names_the_parameter(capsys):
    message = refused(["classify", "five-bar", "--param", "base=1e11"], capsys)
    assert message.startswith("five-bar with base=100000000000.0: cannot be built: ")


def test_at_file_that_is_binary_or_special_is_refused(tmp_path, capsys):
    binary = tmp_path / "at.json"
    binary.write_bytes(bytes(range(256)))
    assert refused(["classify", "five-bar", "--at", f"@{binary}"], capsys).startswith(
        f"--at: {binary}: cannot read the file: not UTF-8 text")
    assert refused(["classify", "five-bar", "--at", f"@{tmp_path}"], capsys) == (
        f"--at: {tmp_path}: cannot read the file: it is a directory, not a regular file")
    if os.path.exists("/dev/zero"):
        assert refused(["classify", "five-bar", "--at", "@/dev/zero"], capsys) == (
            "--at: /dev/zero: cannot read the file: it is a character device, not a regular file")


@pytest.mark.parametrize("target, reason", [
    ("missing/five_bar.yaml", "No such file or directory"),
    ("folder.yaml", "Is a directory"),
    ("full.yaml", "No space left on device"),
])
def test_catalog_write_reports_why_it_cannot_write(target, reason, tmp_path, capsys):
    (tmp_path / "folder.yaml").mkdir()
    if target == "full.yaml":
        if not os.path.exists("/dev/full"):
            pytest.skip("no /dev/full on this platform")
        (tmp_path / "full.yaml").symlink_to("/dev/full")
    path = tmp_path / target
    assert refused(["catalog", "five-bar", "--write", str(path)], capsys) == (
        f"--write: {path}: cannot write the file: {reason}")


def test_write_output_raises_an_input_error_naming_the_option(tmp_path):
    write_output(str(tmp_path / "report.txt"), "text\n", "--output")
    assert (tmp_path / "report.txt").read_text() == "text\n"
    with pytest.raises(InputError, match=r"^--output: .*missing/report.txt: cannot write the file: No such file"):
        write_output(str(tmp_path / "missing" / "report.txt"), "text\n", "--output")


@pytest.mark.parametrize("name", ["a\x00b.yaml", "x" * 5000 + ".yaml"])
def test_file_names_no_file_can_have_are_input_errors(name, capsys):
    message = refused(["classify", name], capsys)
    assert "\x00" not in message and "cannot read the file" in message


def test_error_line_escapes_control_characters_and_surrogates(capsys):
    message = refused(["classify", "five-bar", "--configuration", "\x1b]0;x\x07\udcff"], capsys)
    assert "'\\x1b]0;x\\x07\\udcff'" in message


def test_the_source_line_says_whether_the_parameters_are_the_defaults(capsys):
    """It said 'at its default parameters' with a --param given too."""
    status, out, _ = run(["classify", "slider-crank", "--format", "text"], capsys)
    assert status == 0 and "source: catalogue entry slider-crank at its default parameters" in out
    status, out, _ = run(["classify", "slider-crank", "--param", "crank=3", "--format", "text"], capsys)
    assert status == 0 and "source: catalogue entry slider-crank with the parameters below" in out
    assert "crank = 3" in out
    status, _, err = run(["catalog", "five-bar", "--param", "base=5", "--param", "base=6"], capsys)
    assert status == 2 and "--param base: given twice" in err and err.count("\n") == 1


@pytest.mark.parametrize("arguments, fragment", [
    (["report", "--jobs", "\u0663"], "argument --jobs: expected an integer, got '\u0663'"),
    (["classify", "five-bar", "--seed", "1_0"], "argument --seed: expected an integer ≥ 0, got '1_0'"),
    (["compare", "five-bar", "--path", "1", "--path-step", "1e-400"], "below the smallest float"),
    (["loci", "five-bar", "--branches", "2.0"], "argument --branches: expected an integer"),
])
def test_numeric_options_are_read_as_written(arguments, fragment, capsys):
    """int() and float() read other scripts' digits and underscores, and 1e-400 as 0."""
    status, out, err = run(arguments, capsys)
    assert status == 2 and out == "" and fragment in err and err.count("\n") == 1
