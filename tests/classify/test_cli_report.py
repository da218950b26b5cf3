"""``closedchain report``: the legend, the summary, shared surveys, parallel runs and the G–A outputs."""

import contextlib
import io
import json
from pathlib import Path

import pytest

from classify.cli import main
from classify.cli.report_command import CONFIGURATION_PARAMETERS, JOINT_OUTPUTS, _catalogue_tasks, _layout
from classify.comparison import REASONS
from mechanisms.catalogue import entries, entry
from builders import command as run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def slider_crank_json():
    """``closedchain report slider-crank --format json --jobs 1``: (status, stdout), run once for the tests
    that read it."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        status = main(["report", "slider-crank", "--format", "json", "--jobs", "1"])
    return status, out.getvalue()


def test_report_file_starts_with_a_legend_and_the_terminal_gets_a_summary(tmp_path, capsys):
    output = tmp_path / "report.txt"
    status, out, err = run(["report", "slider-crank", "--output", str(output), "--jobs", "1"], capsys)
    assert status == 0 and err == ""
    assert len(out.splitlines()) == 3 and str(output) in out
    assert ("classified 7 configurations of 1 mechanism(s): 1 regular; singular: 3 actuator, 1 cspace, "
            "4 end-effector (actuator: 1 degenerate, 2 nondegenerate)") in out
    assert "Gosselin–Angeles (derived): 6 correspond, 0 differ, 1 undefined" in out  # fig3a: a C-space singularity
    text = output.read_text(encoding="utf-8")
    legend = text[:text.index("\nsource ")]
    assert text.startswith("closedchain report:") and "Legend" in legend
    for term in ("r/e", "rank expected", "`∞`", "`-`", "degenerate", "nondegenerate", "undetermined", "idle",
                 "G–A (derived)", "I (det B", "II (det A", "[outputs …]", *REASONS):
        assert term in legend, term
    assert "== slider-crank [fig3b_actuator]" in text and "theta = 0.5236" in text


def test_the_summary_describes_a_json_report_as_json(tmp_path, capsys):
    """The summary said "legend, table, one account per configuration" of a JSON list of objects."""
    output = tmp_path / "report.json"
    status, out, _ = run(["report", "slider-crank", "--format", "json", "--output", str(output), "--jobs", "1"],
                         capsys)
    assert status == 0 and len(json.loads(output.read_text(encoding="utf-8"))) == 7
    assert f"the whole report (one JSON object per configuration) is in {output}" in out and "legend" not in out


def test_the_slider_crank_is_compared_with_its_slide_as_gosselin_angeles_do(slider_crank_json, capsys):
    """G–A 1990 eq. 9: input θ, output the slide x; driven by the slide (Park & Kim Fig. 3d), output θ."""
    status, out = slider_crank_json
    assert status == 0
    rows = {row["configuration_name"]: row for row in json.loads(out)}
    assert all(row["comparison"]["reason"] != "unequal_dimensions" for row in rows.values())
    assert rows["fig3b_actuator"]["comparison"]["outputs"] == ["slide"]
    assert rows["fig3b_actuator"]["comparison"]["gosselin_angeles"]["kinds"] == ["II"]
    assert rows["fig3c_dead_centre"]["comparison"]["gosselin_angeles"]["kinds"] == ["I"]
    assert rows["fig3d_dead_centre"]["comparison"]["outputs"] == ["crank"]
    assert rows["fig3d_dead_centre"]["comparison"]["park_kim_kinds"] == ["actuator"]
    assert all(row["comparison"]["agree"] for name, row in rows.items() if name != "fig3a_self_intersection")
    assert rows["fig3a_self_intersection"]["comparison"]["reason"] == "cspace_singularity"
    status, out, _ = run(["report", "slider-crank", "--jobs", "1"], capsys)
    assert "II [outputs slide]" in out and "Gosselin–Angeles (derived, outputs slide): II (corresponds" in out


def test_an_entry_without_a_joint_output_keeps_the_end_effector(capsys):
    status, out, _ = run(["report", "five-bar", "--format", "json", "--jobs", "1"], capsys)
    assert status == 0
    rows = json.loads(out)
    assert all(row["comparison"]["outputs"] is None for row in rows)
    assert "park_kim_kinds" not in rows[0]["comparison"]


def test_report_rows_carry_their_parameters_and_joint_values(capsys):
    status, out, _ = run(["report", "slider-crank", str(EXAMPLES / "five_bar.yaml"), "--format", "json"], capsys)
    assert status == 0
    rows = {(row["source"], row["configuration_name"]): row for row in json.loads(out)}
    crank = rows["slider-crank", "fig3b_actuator"]
    assert crank["parameters"] == entry("slider-crank").values("fig3b_actuator")
    assert crank["joint_values"] == {"crank": 0.0, "pin": 0.0, "wrist": 0.0, "slide": 0.0}
    assert crank["configuration"] == crank["joint_values"]
    named = rows[str(EXAMPLES / "five_bar.yaml"), "fig6a_distal_aligned"]
    assert "parameters" not in named and named["joint_values"]["J1"] != 0.0
    assert [name for source, name in rows if source == "slider-crank"] == \
        ["default", *entry("slider-crank").configurations]


def test_a_parallel_report_equals_the_serial_one(capsys):
    arguments = ["report", "slider-crank", "watt-six-bar", str(EXAMPLES / "slider_crank.yaml")]
    status, serial, _ = run(arguments + ["--jobs", "1"], capsys)
    assert status == 0
    status, parallel, _ = run(arguments + ["--jobs", "2"], capsys)
    assert status == 0 and parallel == serial


def test_a_shared_survey_classifies_as_one_survey_per_configuration(slider_crank_json, capsys):
    """Configurations of one design share a survey; each alone (`classify`) reaches the same verdict."""
    status, out = slider_crank_json
    assert status == 0
    for row in json.loads(out):
        arguments = ["classify", "slider-crank", "--format", "json"]
        if row["configuration_name"] != "default":
            arguments += ["--configuration", row["configuration_name"]]
        _, alone, _ = run(arguments, capsys)
        alone = json.loads(alone)
        for field in ("dof", "kinds", "architecture_singular"):
            assert row[field] == alone[field], (row["configuration_name"], field)
        for kind in ("cspace", "actuator", "end_effector"):
            assert (row[kind]["rank"], row[kind]["expected_rank"]) == \
                (alone[kind]["rank"], alone[kind]["expected_rank"]), (row["configuration_name"], kind)
        assert row["actuator"]["degeneracy"] == alone["actuator"]["degeneracy"]
        # the ranks; the samples and the margins over them differ (the shared survey walks from every start)
        assert {key: value for key, value in row["survey"].items() if key not in ("samples", "margins")} == \
            {key: value for key, value in alone["survey"].items() if key not in ("samples", "margins")}


@pytest.mark.parametrize("item", entries(), ids=lambda item: item.name)
def test_a_survey_is_shared_only_within_one_design(item):
    """The configuration parameters exist, and the configurations grouped together have equal design
    parameters and identical coordinates, actuators and end-effector."""
    placing = set(CONFIGURATION_PARAMETERS.get(item.name, ()))
    assert placing <= set(item.parameters)
    names = ["default", *item.configurations]
    tasks = _catalogue_tasks(item)
    assert sorted(name for task in tasks for name in task.names) == sorted(names)
    for task in tasks:
        values = [item.values(None if name == "default" else name) for name in task.names]
        designs = [{key: value for key, value in value.items() if key not in placing} for value in values]
        assert all(design == designs[0] for design in designs)
        layouts = {_layout(item.mechanism(None if name == "default" else name)) for name in task.names}
        assert len(layouts) == 1


def test_joint_outputs_name_joints_of_their_entries():
    for name, joints in JOINT_OUTPUTS.items():
        mechanism = entry(name).mechanism()
        assert all(mechanism.joint(joint) for joint in joints)


def test_report_jobs_must_be_positive(capsys):
    status, out, err = run(["report", "slider-crank", "--jobs", "0"], capsys)
    assert status == 2 and out == "" and "--jobs" in err and err.count("\n") == 1


@pytest.mark.parametrize("arguments, fragment", [
    ([""], "PATH: an empty path"),                    # was read as the current folder
    (["slider-crank", "--html", ""], "--html: an empty path"),  # wrote nothing
    (["slider-crank", "--output", "r.txt", "--html", "r.txt"], "--output, --html: one file for both"),
])
def test_report_paths_that_would_be_misread_are_refused(arguments, fragment, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(["report", *arguments], capsys)
    assert status == 2 and out == "" and fragment in err and err.count("\n") == 1
    assert not list(tmp_path.iterdir())


def test_a_mechanism_without_inputs_or_outputs_is_reported_with_gosselin_angeles_undefined(tmp_path, capsys):
    """No actuated joint and no end-effector: Park–Kim classifies it (classify accepts it), G–A is undefined
    (n = 0) with a listed reason — the report used to stop with an internal error in the metric of N."""
    status, _, _ = run(["catalog", "five-bar", "--write", str(tmp_path / "five.yaml")], capsys)
    assert status == 0
    text = (tmp_path / "five.yaml").read_text(encoding="utf-8")
    bare = "\n".join(line for line in text.splitlines() if "actuated:" not in line)
    bare = bare[:bare.index("end_effector:")] + "end_effector: null\n"
    (tmp_path / "bare.yaml").write_text(bare, encoding="utf-8")
    status, out, err = run(["report", str(tmp_path / "bare.yaml"), "--format", "json", "--jobs", "1"], capsys)
    assert status == 0, err
    (row,) = json.loads(out)
    assert row["comparison"]["reason"] == "unequal_dimensions" and row["comparison"]["agree"] is False
    assert "no inputs and no outputs" in row["comparison"]["note"]
