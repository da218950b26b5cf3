"""Coordinate names are unique: a joint named like another joint's coordinate (``U1[1]`` beside the U joint
``U1``) is refused when the mechanism is built or read, since text, CSV and ``--grid`` name values by coordinate
and one of the two would be silently lost."""

import json
from dataclasses import replace
from pathlib import Path

import pytest

from classify.cli import main
from mechanisms import catalogue
from mechanisms.errors import MechanismError
from mechanisms.io import read, save
from mechanisms.mechanism import Mechanism

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def gough_stewart():
    item = catalogue.entry("gough-stewart")
    return item.assemble(item.values())


def renamed(mechanism, old, new):
    """The joints of `mechanism` with joint `old` renamed `new`."""
    return tuple(replace(joint, name=new) if joint.name == old else joint for joint in mechanism.joints)


def test_a_joint_named_like_a_coordinate_of_another_is_refused_naming_both():
    mechanism = gough_stewart()
    assert "U1[1]" in mechanism.coordinate_names
    with pytest.raises(MechanismError, match=r"joint 'U1\[1\]'.*coordinate of joint 'U1'"):
        Mechanism(mechanism.name, mechanism.space, renamed(mechanism, "P1", "U1[1]"), mechanism.ground,
                  mechanism.end_effector)


def test_the_order_of_the_joints_does_not_change_the_message():
    mechanism = gough_stewart()
    joints = renamed(mechanism, "P1", "U1[2]")
    moved = tuple(sorted(joints, key=lambda joint: joint.name != "U1[2]"))  # the colliding joint first
    for order in (joints, moved):
        with pytest.raises(MechanismError, match=r"joint 'U1\[2\]'.*coordinate of joint 'U1'"):
            Mechanism(mechanism.name, mechanism.space, order, mechanism.ground, mechanism.end_effector)


def test_a_file_with_such_a_joint_is_refused_when_read_and_by_the_command(tmp_path, capsys):
    save(gough_stewart(), tmp_path / "gs.json")
    document = json.loads((tmp_path / "gs.json").read_text())
    for joint in document["joints"]:
        if joint["name"] == "P1":
            joint["name"] = "U1[1]"
    (tmp_path / "collide.json").write_text(json.dumps(document))
    with pytest.raises(MechanismError, match=r"U1\[1\]"):
        read(tmp_path / "collide.json")
    assert main(["classify", str(tmp_path / "collide.json")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'U1[1]'" in err and "'U1'" in err


def test_names_with_brackets_that_are_no_other_coordinate_are_kept():
    mechanism = gough_stewart()
    kept = Mechanism(mechanism.name, mechanism.space, renamed(mechanism, "P1", "U1[3]"), mechanism.ground,
                     mechanism.end_effector)
    assert len(set(kept.coordinate_names)) == len(kept.coordinate_names)


@pytest.mark.parametrize("name", catalogue.names())
def test_every_catalogue_entry_has_unique_coordinate_names(name):
    item = catalogue.entry(name)
    for configuration in (None, *item.configurations):
        mechanism = item.assemble(item.values(configuration))
        assert len(set(mechanism.coordinate_names)) == len(mechanism.coordinate_names)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.yaml")), ids=lambda path: path.name)
def test_the_examples_still_load(path):
    mechanism = read(path).mechanism
    assert len(set(mechanism.coordinate_names)) == len(mechanism.coordinate_names)
