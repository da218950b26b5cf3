"""Every further command takes ``--format json|text`` (docs/design.rst, "Further commands"); ``draw`` and
``convert`` print what they wrote as JSON too."""

import contextlib
import io
import json

import pytest

from classify.cli import main

COMMANDS = ["classify", "report", "compare", "catalog", "map", "sweep", "conditioning", "line-plane", "convert",
            "draw", "loci"]


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv, out=out)
        except SystemExit as exit:  # --help
            status = exit.code
    return status, out.getvalue(), err.getvalue()


@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_takes_format(command, capsys):
    with pytest.raises(SystemExit) as exit:
        main([command, "--help"])
    assert exit.value.code == 0
    assert "--format {json,text}" in " ".join(capsys.readouterr().out.split())


def test_draw_json_gives_the_file_and_the_classification_of_the_configuration_drawn(tmp_path):
    path = tmp_path / "five.svg"
    status, out, err = run(["draw", "five-bar", "--configuration", "eq9_distal_aligned", "--out", str(path),
                            "--format", "json"])
    assert status == 0, err
    drawn = json.loads(out)
    assert drawn["written"] == [str(path)] and path.stat().st_size > 1000
    status, out, err = run(["classify", "five-bar", "--configuration", "eq9_distal_aligned", "--format", "json"])
    assert status == 0, err
    classified = json.loads(out)
    assert drawn["kinds"] == classified["kinds"] == ["actuator"]
    for field in ("kinds", "dof", "cspace", "actuator", "end_effector", "configuration", "survey"):
        assert drawn["classification"][field] == classified[field]


@pytest.mark.parametrize("suffix, written", [(".yaml", 1), (".urdf", 2)])
def test_convert_json_lists_the_files_written(tmp_path, suffix, written):
    target = tmp_path / f"five{suffix}"
    status, out, err = run(["convert", "five-bar", "--write", str(target), "--format", "json"])
    assert status == 0, err
    result = json.loads(out)
    assert len(result["written"]) == written and all((tmp_path / name).exists() for name in result["written"])
    assert (result["mechanism"], result["joints"], result["loops"]) == ("five-bar", 5, 1)
    assert result["notes"] == []


def test_a_reader_that_stops_reading_is_no_internal_error(capsys):
    """`closedchain classify five-bar | head -1`: the write to the closed pipe raised BrokenPipeError, which the
    command printed as an internal error (exit 1)."""
    class ClosedPipe(io.StringIO):
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

    assert main(["classify", "five-bar"], out=ClosedPipe()) == 0
    assert "internal error" not in capsys.readouterr().err
