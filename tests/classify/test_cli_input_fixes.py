"""Outputs that would overwrite a command's inputs, checks made before the work (a survey cache written for a
command then refused, a sweep refused after running), a FIFO named ``.xml``, and bounds on ``--title`` and on
the report's file names."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from classify.cli import main, sweep_command
from builders import command as run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
COMMAND = [sys.executable, "-m", "classify"]
OVERWRITTEN = "it would be overwritten"


def refused_once(arguments, capsys, fragment):
    """Run a command that must be refused: status 2, nothing on stdout, one line on stderr holding `fragment`."""
    status, out, err = run(arguments, capsys)
    assert status == 2 and out == "", (status, out, err)
    assert err.count("\n") == 1 and fragment in err, err
    return err


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """A folder with a mechanism file ``m.json`` and a batch file ``b.json``, made the current one."""
    monkeypatch.chdir(tmp_path)
    status = main(["convert", str(EXAMPLES / "five_bar.yaml"), "--write", "m.json"])
    assert status == 0
    (tmp_path / "b.json").write_text('[{"J1": 0}]\n')
    return tmp_path


def snapshot(folder):
    return {path.name: path.read_bytes() for path in folder.iterdir() if path.is_file()}


# ------------------------------------------------------------------------------------------------ item 1

@pytest.mark.parametrize("arguments", [
    ["classify", "m.json", "--batch", "b.json", "--out", "b.json"],
    ["classify", "m.json", "--batch", "b.json", "--out", "m.json"],
    ["classify", "m.json", "--batch", "b.json", "--out", "./sub/../m.json"],
    ["map", "m.json", "--grid", "J1=0:0.1:2", "--out", "m.json"],
    ["report", "m.json", "--output", "m.json", "--jobs", "1"],
    ["conditioning", "m.json", "--grid", "J1=0:0.1:2", "--out", "m.json"],
], ids=["classify-batch", "classify-file", "classify-dotted", "map", "report-output", "conditioning"])
def test_an_output_onto_an_input_is_refused_and_nothing_is_written(arguments, folder, capsys):
    (folder / "sub").mkdir()
    before = snapshot(folder)
    refused_once(arguments, capsys, OVERWRITTEN)
    assert snapshot(folder) == before


def test_a_hard_link_or_a_symbolic_link_to_an_input_is_refused(folder, capsys):
    os.link(folder / "m.json", folder / "hard.json")
    (folder / "soft.json").symlink_to(folder / "m.json")
    os.link(folder / "m.json", folder / "page.html")
    before = snapshot(folder)
    for target in ("hard.json", "soft.json"):
        refused_once(["map", "m.json", "--grid", "J1=0:0.1:2", "--out", target], capsys, OVERWRITTEN)
    refused_once(["report", "m.json", "--html", "page.html", "--jobs", "1"], capsys, OVERWRITTEN)
    assert snapshot(folder) == before


def test_a_report_output_onto_a_file_of_an_input_folder_is_refused(folder, capsys):
    (folder / "models").mkdir()
    (folder / "m.json").rename(folder / "models" / "m.json")
    before = (folder / "models" / "m.json").read_bytes()
    refused_once(["report", "models", "--output", "models/m.json", "--jobs", "1"], capsys, OVERWRITTEN)
    assert (folder / "models" / "m.json").read_bytes() == before


@pytest.mark.parametrize("arguments", [
    ["classify", "m.json", "--batch", "b.json", "--survey", "s.json", "--out", "s.json"],
    ["map", "m.json", "--grid", "J1=0:0.1:2", "--survey", "s.json", "--out", "s.json"],
], ids=["classify", "map"])
def test_an_output_onto_the_survey_cache_is_refused_before_the_cache_is_written(arguments, folder, capsys):
    refused_once(arguments, capsys, "--survey")
    assert not (folder / "s.json").exists()


def test_outputs_elsewhere_are_still_written(folder, capsys):
    status, _, err = run(["classify", "m.json", "--batch", "b.json", "--out", "r.json"], capsys)
    assert status == 0 and (folder / "r.json").exists(), err


# ------------------------------------------------------------------------------------------------ item 2

@pytest.mark.parametrize("arguments", [
    ["classify", "g.xml"],
    ["classify", "g.xml", "--closures", "c.yaml"],
    ["conditioning", "g.xml"],
    ["report", "g.xml", "--jobs", "1"],
    ["convert", "g.xml", "--write", "o.yaml"],
], ids=["classify", "classify-closures", "conditioning", "report", "convert"])
def test_a_fifo_named_xml_is_refused_at_once(arguments, tmp_path):
    os.mkfifo(tmp_path / "g.xml")
    (tmp_path / "c.yaml").write_text("closed_loop: []\n")
    done = subprocess.run([*COMMAND, *arguments], cwd=tmp_path, capture_output=True, text=True, timeout=20,
                          env=dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2])))
    assert done.returncode == 2 and done.stdout == "", done
    assert done.stderr.count("\n") == 1 and "it is a FIFO (named pipe), not a regular file" in done.stderr


def test_looks_like_urdf_does_not_open_a_fifo(tmp_path):
    from mechanisms.urdf import looks_like_urdf

    os.mkfifo(tmp_path / "g.xml")
    done = subprocess.run([sys.executable, "-c", "import sys; from mechanisms.urdf import looks_like_urdf; "
                           "print(looks_like_urdf(sys.argv[1]))", str(tmp_path / "g.xml")],
                          capture_output=True, text=True, timeout=20,
                          env=dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2])))
    assert done.stdout.strip() == "False", done
    (tmp_path / "leg.xml").write_text("<?xml version='1.0'?>\n<robot name='leg'><link name='a'/></robot>\n")
    assert looks_like_urdf(tmp_path / "leg.xml")


# ------------------------------------------------------------------------------------------------ item 4

@pytest.mark.parametrize("arguments", [
    ["classify", "m.json", "--batch", "b.json", "--survey", "s.json", "--out", "nodir/x.jsonl"],
    ["map", "m.json", "--grid", "J1=0:0.1:2", "--survey", "s.json", "--out", "nodir/x.csv"],
    ["classify", "m.json", "--batch", "b.json", "--survey", "s.json", "--out", "sub"],
], ids=["classify", "map", "folder"])
def test_the_survey_cache_is_not_written_when_the_output_is_refused(arguments, folder, capsys):
    (folder / "sub").mkdir()
    if arguments[-1] == "sub":
        arguments = arguments[:-1] + ["sub.json"]
        (folder / "sub.json").mkdir()
    refused_once(arguments, capsys, "--out")
    assert not (folder / "s.json").exists()


# ------------------------------------------------------------------------------------------------ item 5

@pytest.mark.parametrize("param, fragment", [
    ("base=-1", "base must be positive"),
    ("actuated=0:1:2", "actuated"),
])
def test_a_sweep_of_designs_nobody_can_build_is_refused_before_it_starts(param, fragment, capsys, monkeypatch):
    def no_cluster(arguments):
        raise AssertionError("a cluster was started for a sweep that is refused")

    monkeypatch.setattr(sweep_command, "_client", no_cluster)
    for extra in ([], ["--scheduler", "serial"]):
        err = refused_once(["sweep", "five-bar", "--param", param, "--samples", "2", *extra], capsys, fragment)
        assert "sweeping" not in err and "--param" in err


def test_a_sweep_whose_first_design_cannot_be_built_still_runs(capsys):
    status, out, err = run(["sweep", "five-bar", "--param", "base=-1:2:2", "--samples", "2", "--scheduler",
                            "serial", "--format", "json"], capsys)
    assert status == 0, err


# ------------------------------------------------------------------------------------------------ item 6

def test_a_very_long_title_is_refused_naming_the_option(tmp_path, capsys):
    refused_once(["draw", "five-bar", "--out", str(tmp_path / "t.png"), "--title", "x" * 1000], capsys, "--title")
    assert not (tmp_path / "t.png").exists()


@pytest.mark.parametrize("arguments, option", [
    (["--output", "r.png"], "--output"),
    (["--html", "r.txt"], "--html"),
    (["--output", "r.html"], "--output"),
])
def test_report_files_with_the_wrong_suffix_are_refused_before_the_work(arguments, option, tmp_path, capsys,
                                                                       monkeypatch):
    monkeypatch.chdir(tmp_path)
    refused_once(["report", "slider-crank", "--jobs", "1", *arguments], capsys, option)
    assert not list(tmp_path.iterdir())


def test_convert_warns_of_a_mechanism_without_loops(tmp_path, capsys):
    status, _, _ = run(["convert", "five-bar", "--write", str(tmp_path / "f.urdf")], capsys)
    assert status == 0
    (tmp_path / "empty.yaml").write_text("")
    status, _, err = run(["convert", str(tmp_path / "f.urdf"), "--closures", str(tmp_path / "empty.yaml"),
                          "--write", str(tmp_path / "serial.yaml")], capsys)
    assert status == 0 and "has no loop (a serial chain;" in err, err
