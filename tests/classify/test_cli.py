"""The ``closedchain`` command: contract JSON, exit codes, one-line errors."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from classify.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CONTRACT_KEYS = {"mechanism", "dof", "singular", "kinds", "cspace", "actuator", "end_effector", "manipulability"}


def run(arguments, capsys):
    status = main(arguments)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


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
