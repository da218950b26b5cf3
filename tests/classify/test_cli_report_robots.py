"""``closedchain report`` on robot files: a URDF with its ``--closures``, an MJCF file, a folder in the layout of
the example-parallel-robots collection (``robot.urdf`` beside ``robot.yaml``), the HTML page, and one-line errors;
one place builds each configuration for the rows and the pictures."""

import json
import shutil
from pathlib import Path

import pytest

from classify.cli.report_command import _configurations, _Task
from builders import ROBOTS, robot_arguments
from builders import command as run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

pytest.importorskip("yourdfpy")


def test_report_on_a_urdf_with_closures_gives_one_row_at_the_closed_configuration(capsys):
    status, out, err = run(["report", *robot_arguments("5bar_linkage_iso3d"), "--format", "json", "--jobs", "1"], capsys)
    assert status == 0, err
    (row,) = json.loads(out)
    assert row["source"] == str(ROBOTS / "5bar_linkage_iso3d" / "robot.urdf") and row["configuration_name"] == "home"
    assert row["closures"] == str(ROBOTS / "5bar_linkage_iso3d" / "robot.yaml")
    assert row["import"]["assembly_residual"] < 1e-9 and row["import"]["loops"] == 1
    assert (row["dof"], row["kinds"], row["cspace"]["rank"], row["actuator"]["rank"]) == (2, [], 6, 2)


def test_report_text_on_a_urdf_states_the_import(capsys):
    status, out, err = run(["report", *robot_arguments("5bar_linkage"), "--jobs", "1"], capsys)
    assert status == 0, err
    assert "  closures: " + str(ROBOTS / "5bar_linkage" / "robot.yaml") in out
    assert "  imported: base link 'built' fixed as the ground" in out
    assert "  imported: assembled from the zero configuration: moved by" in out
    assert "2/2 +1 idle" in out  # the spin of the two welded leaf joints


def test_report_on_an_mjcf_file_classifies_as_the_catalogue_five_bar(capsys):
    pytest.importorskip("mujoco")
    status, out, err = run(["report", str(ROBOTS / "five_bar_mjcf" / "model.xml"), "five-bar", "--format", "json",
                            "--jobs", "1"], capsys)
    assert status == 0, err
    rows = {(row["source"], row["configuration_name"]): row for row in json.loads(out)}
    imported, catalogue = rows[str(ROBOTS / "five_bar_mjcf" / "model.xml"), "home"], rows["five-bar", "default"]
    assert imported["mechanism"] == "five_bar_mjcf" and "closures" not in imported
    assert imported["dof"] == catalogue["dof"] == 2 and imported["kinds"] == catalogue["kinds"] == []
    assert imported["actuator"]["rank"] == catalogue["actuator"]["rank"] == 2


def test_a_folder_pairs_each_urdf_with_the_yaml_of_its_stem(tmp_path, capsys):
    for name in ("5bar_linkage_iso3d",):
        shutil.copytree(ROBOTS / name, tmp_path / name)
    shutil.copy(EXAMPLES / "slider_crank.yaml", tmp_path / "slider_crank.yaml")
    status, out, err = run(["report", str(tmp_path), "--format", "json", "--jobs", "1"], capsys)
    assert status == 0, err
    rows = json.loads(out)
    sources = {Path(row["source"]).relative_to(tmp_path).as_posix() for row in rows}
    assert sources == {"5bar_linkage_iso3d/robot.urdf", "slider_crank.yaml"}  # robot.yaml: its closures
    (robot_row,) = [row for row in rows if row["source"].endswith(".urdf")]
    assert robot_row["closures"] == str(tmp_path / "5bar_linkage_iso3d" / "robot.yaml") and robot_row["dof"] == 2


def test_report_html_draws_the_imported_robot(tmp_path, capsys):
    page = tmp_path / "report.html"
    status, out, err = run(["report", *robot_arguments("5bar_linkage"), "--jobs", "1", "--html", str(page),
                            "--output", str(tmp_path / "report.txt")], capsys)
    assert status == 0, err
    document = page.read_text(encoding="utf-8")
    # the configuration drawn, and the C-space in sections (3 dof, one the welded leaf joints' idle spin: the
    # sections are over a coordinate that moves it)
    assert document.count('src="data:image/png;base64,') == 2
    assert "robot.urdf: home" in document


@pytest.mark.parametrize("arguments, message", [
    ([str(ROBOTS / "5bar_linkage" / "robot.urdf"), str(ROBOTS / "5bar_linkage_iso3d" / "robot.urdf"),
      "--closures", str(ROBOTS / "5bar_linkage" / "robot.yaml")], "--closures: applies to one URDF file"),
    (["five-bar", "--closures", "x.yaml"], "--closures: applies to a URDF file named on the command line, got none"),
    ([str(ROBOTS / "5bar_linkage" / "robot.urdf"), "--closures", str(ROBOTS / "5bar_linkage_iso3d" / "robot.yaml")],
     "unknown frame 'closedloop3D_1B'"),
])
def test_bad_robot_input_exits_2_with_one_line(arguments, message, capsys):
    status, out, err = run(["report", *arguments, "--jobs", "1"], capsys)
    assert status == 2 and out == ""
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_one_place_builds_each_configuration():
    """The rows and the pictures read a task's configurations from :func:`_configurations`: a catalogue entry's
    mechanism built at each configuration, a file's named configurations on its one mechanism, a robot at its
    assembled home."""
    import numpy as np

    from mechanisms import home
    from mechanisms.catalogue import entry

    catalogue = _configurations(_Task("five-bar", ("default", "fig6a_distal_aligned")))
    item = entry("five-bar")
    assert [entry.name for entry in catalogue] == ["default", "fig6a_distal_aligned"]
    built = item.mechanism("fig6a_distal_aligned")
    assert np.allclose(catalogue[1].point, home(built))
    assert catalogue[1].source == {"catalogue": "five-bar", "parameters": item.values("fig6a_distal_aligned"),
                                   "configuration": "fig6a_distal_aligned"}
    path = str(EXAMPLES / "five_bar.yaml")
    from mechanisms.io import read

    names = ("home", *read(path).configurations)
    files = _configurations(_Task(path, names, is_file=True))
    assert [entry.name for entry in files] == list(names)
    assert all(entry.mechanism is files[0].mechanism for entry in files)
    urdf = str(ROBOTS / "5bar_linkage" / "robot.urdf")
    (imported,) = _configurations(_Task(urdf, ("home",), is_file=True, closures=urdf[:-4] + "yaml"))
    assert imported.source["import"]["assembly_residual"] < 1e-9 and imported.source["closures"].endswith(".yaml")
