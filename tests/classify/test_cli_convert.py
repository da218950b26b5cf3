"""``closedchain classify/convert`` with URDF + closures: JSON with the import's account, contract-format files
that classify the same, URDF written back, and one-line errors (exit 2)."""

import json

import pytest

from builders import ROBOTS, robot_arguments
from builders import command as run

pytest.importorskip("yourdfpy")


def test_classify_urdf_with_closures_json(capsys):
    status, out, err = run(["classify", *robot_arguments("5bar_linkage_iso3d"), "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["mechanism"] == "5bar_linkage_iso3d" and result["dof"] == 2 and result["kinds"] == []
    assert (result["cspace"]["rank"], result["actuator"]["rank"]) == (6, 2)
    assert result["import"]["assembly_residual"] < 1e-9 and result["import"]["loops"] == 1
    assert result["source"]["closures"].endswith("robot.yaml")


def test_classify_urdf_text_states_the_fixed_base_and_the_assembly(capsys):
    status, out, _ = run(["classify", *robot_arguments("5bar_linkage")], capsys)
    assert status == 0
    assert "imported: base link 'built' fixed as the ground" in out
    assert "imported: assembled from the zero configuration: moved by" in out
    assert "dof m = 3" in out and "idle freedoms: 1" in out


def test_convert_writes_a_contract_file_that_classifies_the_same(tmp_path, capsys):
    target = tmp_path / "five.yaml"
    status, out, err = run(["convert", *robot_arguments("5bar_linkage"), "--write", str(target)], capsys)
    assert status == 0, err and "wrote" in out
    status, direct, _ = run(["classify", *robot_arguments("5bar_linkage"), "--format", "json"], capsys)
    status, converted, _ = run(["classify", str(target), "--format", "json"], capsys)
    direct, converted = json.loads(direct), json.loads(converted)
    for key in ("dof", "kinds", "singular"):
        assert direct[key] == converted[key]
    for kind in ("cspace", "actuator"):
        assert direct[kind]["rank"] == converted[kind]["rank"]
    from mechanisms.io import read

    assert "base link 'built' fixed" in read(target).description


def test_convert_catalogue_entry_to_urdf_and_back(tmp_path, capsys):
    target = tmp_path / "five.urdf"
    status, out, err = run(["convert", "five-bar", "--write", str(target)], capsys)
    assert status == 0, err
    assert (tmp_path / "five.yaml").exists()
    status, out, err = run(["classify", str(target), "--closures", str(tmp_path / "five.yaml"), "--format", "json"],
                           capsys)
    assert status == 0, err
    result = json.loads(out)
    status, catalogue, _ = run(["classify", "five-bar", "--format", "json"], capsys)
    catalogue = json.loads(catalogue)
    assert (result["dof"], result["cspace"]["rank"], result["actuator"]["rank"]) == \
        (catalogue["dof"], catalogue["cspace"]["rank"], catalogue["actuator"]["rank"])
    assert result["import"]["assembly_distance"] < 1e-9  # exported at home: the zero configuration closes


@pytest.mark.parametrize("arguments, message", [
    (["classify", str(ROBOTS / "5bar_linkage" / "robot.urdf"), "--closures",
      str(ROBOTS / "5bar_linkage_iso3d" / "robot.yaml")], "unknown frame 'closedloop3D_1B'"),
    (["classify", "five-bar", "--closures", "x.yaml"], "--closures: applies to a URDF input"),
    (["convert", "nope.urdf", "--closures", str(ROBOTS / "5bar_linkage" / "robot.yaml"), "--write", "c.yaml"],
     "nope.urdf: no such file"),  # it said --closures did not apply to nope.urdf
    (["convert", "five-bar", "--write", "out.txt"], "--write: expected"),
    (["classify", *robot_arguments("5bar_linkage"), "--param", "a=1"], "--param: does not apply"),
    (["classify", str(ROBOTS / "5bar_linkage" / "robot.urdf"), "--closures",
      str(ROBOTS.parents[2] / "examples" / "five_bar.yaml")], "five_bar.yaml: not a closures file: it has keys 'name', "),  # wrong shape
    (["classify", *robot_arguments("cannot_close")], "loop 2 ['coupler_tip', 'follower_tip']"),
    (["convert", *robot_arguments("leg_floating")[:1], "--closures", str(ROBOTS / "leg_floating" / "robot.urdf"),
      "--write", "x.yaml"], "robot.urdf: cannot parse YAML"),  # a URDF given as the closures
])
def test_bad_input_exits_2_with_one_line(arguments, message, capsys):
    status, out, err = run(arguments, capsys)
    assert status == 2
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_compare_an_imported_robot_with_joint_outputs(capsys):
    status, out, err = run(["compare", *robot_arguments("5bar_linkage_iso3d"), "--outputs", "free1,free2", "--format", "json"],
                           capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["inputs"] == ["mot1", "mot2"] and result["outputs"] == ["free1", "free2"]
    assert result["configurations"][0]["park_kim"]["kinds"] == []


def test_the_closures_end_effector_key_gives_the_robot_an_end_effector(tmp_path, capsys):
    """closedchain's own key beside the collection's: the 5-bar's 'effector' frame (a link welded by a fixed joint
    to the distal rod), its position; the robot moves in a plane, so the position's rank is 2."""
    closures = (ROBOTS / "5bar_linkage_iso3d" / "robot.yaml").read_text() + "end_effector: {frame: effector}\n"
    (tmp_path / "robot.yaml").write_text(closures)
    status, out, err = run(["classify", str(ROBOTS / "5bar_linkage_iso3d" / "robot.urdf"), "--closures",
                            str(tmp_path / "robot.yaml"), "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert (result["end_effector"]["rank"], result["end_effector"]["expected_rank"]) == (2, 2)
    assert result["kinds"] == []


def test_converting_a_mechanism_file_keeps_its_configurations_and_refuses_to_overwrite_it(tmp_path, capsys):
    """`convert FILE.yaml --write OUT.json` dropped every named configuration of the file (and with
    --configuration kept the old home with one configuration renamed 'named'); `--write FILE.urdf` wrote its
    closures file over FILE.yaml, the input."""
    import shutil
    from pathlib import Path

    from mechanisms.io import read

    source = tmp_path / "five_bar.yaml"
    shutil.copy(Path(__file__).resolve().parents[2] / "examples" / "five_bar.yaml", source)
    original = read(source)
    assert len(original.configurations) > 1
    target = tmp_path / "five_bar.json"
    status, _, err = run(["convert", str(source), "--write", str(target)], capsys)
    assert status == 0, err
    converted = read(target)
    assert converted.configurations == original.configurations and converted.description == original.description
    name = next(iter(original.configurations))
    status, _, err = run(["convert", str(source), "--configuration", name, "--write", str(target)], capsys)
    assert status == 2 and "--configuration: converting a mechanism file keeps" in err
    text = source.read_text()
    for written in ("five_bar.urdf", "five_bar.yaml"):
        status, _, err = run(["convert", str(source), "--write", str(tmp_path / written)], capsys)
        assert status == 2 and "is an input of this conversion" in err and len(err.strip().splitlines()) == 1
    assert source.read_text() == text


WEIGHTED = """name: w
space: planar
description: a five-bar with weighted motors
joints:
- {name: A, type: R, links: [ground, p1], point: [0, 0], actuated: true, weight: 0.5}
- {name: C, type: R, links: [p1, d1], point: [-1.8176167575446969, 7.790781047025561]}
- {name: P, type: R, links: [d1, d2], point: [0.5, 12.0]}
- {name: D, type: R, links: [d2, p2], point: [8.139990628996699, 7.708465483337544]}
- {name: B, type: R, links: [ground, p2], point: [6, 0], actuated: true, weight: 4.0}
end_effector: {link: d1, point: [0.5, 12.0]}
configurations: {nudge: {A: 0.0}}
"""


@pytest.mark.parametrize("output", ["json", "text"])
def test_urdf_export_says_what_the_pair_cannot_hold(tmp_path, capsys, output):
    """The weights (the λ's change with them), the named configurations and the description were dropped with
    exit 0 and "notes": []: each is now a note and a warning line on stderr, naming the joints and the
    configurations."""
    source = tmp_path / "w.yaml"
    source.write_text(WEIGHTED)
    status, out, err = run(["convert", str(source), "--write", str(tmp_path / "w_u.urdf"), "--format", output],
                           capsys)
    assert status == 0, err
    warnings = [line for line in err.splitlines() if line.startswith("closedchain: warning: ")]
    assert len(warnings) == 3 == len(err.splitlines())
    assert "weights of A (0.5), B (4)" in warnings[0] and "proper values" in warnings[0]
    assert "named configurations" in warnings[1] and "nudge" in warnings[1]
    assert "description" in warnings[2]
    notes = json.loads(out)["notes"] if output == "json" else \
        [line[len("note: "):] for line in out.splitlines() if line.startswith("note: ")]
    assert notes == [line[len("closedchain: warning: "):] for line in warnings]


def test_urdf_export_of_a_file_without_weights_configurations_or_description_says_nothing(tmp_path, capsys):
    source = tmp_path / "plain.yaml"
    source.write_text("\n".join(line for line in WEIGHTED.splitlines()
                                if not line.startswith(("description", "configurations"))).replace(", weight: 0.5", "")
                      .replace(", weight: 4.0", "") + "\n")
    status, out, err = run(["convert", str(source), "--write", str(tmp_path / "p.urdf"), "--format", "json"], capsys)
    assert status == 0 and err == "" and json.loads(out)["notes"] == []


@pytest.mark.parametrize("name, link, field", [("J\\x01", "a", "joint 'J\\x01': field 'name'"),
                                               ("J1", "a\\x1b", "joint 'J1': field 'links': link 'a\\x1b'")])
def test_a_name_xml_cannot_hold_is_refused_before_anything_is_written(tmp_path, capsys, name, link, field):
    """The name was written raw: exit 0, and the URDF could not be read back (not well-formed XML)."""
    source = tmp_path / "source.yaml"
    source.write_text(f'name: ctl\nspace: planar\njoints:\n'
                      f'- {{name: "{name}", type: R, links: [ground, "{link}"], point: [0, 0], actuated: true}}\n'
                      f'- {{name: J2, type: R, links: ["{link}", b], point: [0, 1]}}\n'
                      f'- {{name: J3, type: R, links: [b, c], point: [1, 1.5]}}\n'
                      f'- {{name: J4, type: R, links: [c, ground], point: [2, 0]}}\n')
    status, out, err = run(["convert", str(source), "--write", str(tmp_path / "ctl.urdf")], capsys)
    assert status == 2 and out == ""
    assert err.startswith(f"closedchain: error: --write: {field}: the character U+00") and "XML 1.0" in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert sorted(path.name for path in tmp_path.iterdir()) == ["source.yaml"]


@pytest.mark.parametrize("options", [[], ["--configuration", "fig6a_distal_aligned"], ["--param", "distal=6"]])
def test_convert_writes_a_catalogue_entry_with_the_description_catalog_gives_it(tmp_path, capsys, options):
    """`convert NAME --write x.yaml` wrote no description; `catalog NAME --write` records the entry, its paper and
    its parameters."""
    from mechanisms.io import mechanism_to_dict, read

    status, _, err = run(["convert", "five-bar", *options, "--write", str(tmp_path / "converted.yaml")], capsys)
    assert status == 0, err
    status, _, err = run(["catalog", "five-bar", *options, "--write", str(tmp_path / "catalog.yaml")], capsys)
    assert status == 0, err
    converted, catalogued = read(tmp_path / "converted.yaml"), read(tmp_path / "catalog.yaml")
    assert converted.description == catalogued.description and "closedchain catalogue entry five-bar" in \
        converted.description
    assert mechanism_to_dict(converted.mechanism) == mechanism_to_dict(catalogued.mechanism)


@pytest.mark.parametrize("suffix", [".YAML", ".Yml", ".JSON", ".URDF"])
def test_an_upper_case_suffix_is_accepted(tmp_path, capsys, suffix):
    """`--write X.YAML` was refused by a case-sensitive check, though mechanisms.io reads and writes it."""
    target = tmp_path / f"x{suffix}"
    status, out, err = run(["convert", "five-bar", "--write", str(target), "--format", "json"], capsys)
    assert status == 0, err
    assert target.exists() and json.loads(out)["written"][0] == str(target)
    if suffix == ".URDF":
        assert (tmp_path / "x.yaml").exists()
    else:
        from mechanisms.io import read

        assert read(target).mechanism.name == "five-bar"


def test_an_input_reached_through_a_hard_link_is_not_overwritten(tmp_path, capsys):
    """`convert in.yaml --write hard.urdf`, hard.yaml a hard link to in.yaml: the closures file was written over
    the input (resolved paths differ for hard links; found by an audit)."""
    import os

    source = tmp_path / "in.yaml"
    assert run(["convert", "five-bar", "--write", str(source)], capsys)[0] == 0
    text = source.read_text()
    os.link(source, tmp_path / "hard.yaml")
    status, _, err = run(["convert", str(source), "--write", str(tmp_path / "hard.urdf")], capsys)
    assert status == 2 and "is an input of this conversion" in err and err.count("\n") == 1
    assert source.read_text() == text


def test_a_name_too_long_for_a_file_exits_2(tmp_path, capsys):
    status, _, err = run(["convert", "five-bar", "--write", str(tmp_path / ("x" * 300 + ".yaml"))], capsys)
    assert status == 2 and err.count("\n") == 1 and "internal error" not in err


def test_a_urdf_is_not_left_without_its_closures(tmp_path, capsys):
    """The closures file could not be written (a folder there), exit 2, and the .urdf was written all the same,
    or an existing one replaced and paired with stale closures (found by an audit)."""
    (tmp_path / "out.yaml").mkdir()
    status, _, err = run(["convert", "five-bar", "--write", str(tmp_path / "out.urdf")], capsys)
    assert status == 2 and not (tmp_path / "out.urdf").exists()
    (tmp_path / "old.urdf").write_text("<robot name='old'/>\n")
    (tmp_path / "old.yaml").mkdir()
    status, _, err = run(["convert", "five-bar", "--write", str(tmp_path / "old.urdf")], capsys)
    assert status == 2 and (tmp_path / "old.urdf").read_text() == "<robot name='old'/>\n"


def test_an_upper_case_urdf_written_reads_back(tmp_path, capsys):
    target = tmp_path / "X.URDF"
    assert run(["convert", "five-bar", "--write", str(target)], capsys)[0] == 0
    status, out, err = run(["convert", str(target), "--closures", str(tmp_path / "X.yaml"), "--write",
                            str(tmp_path / "back.yaml")], capsys)
    assert status == 0, err
