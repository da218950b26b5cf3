"""What the URDF export (:mod:`mechanisms.export`) keeps and what it says it leaves out: joint values (a joint the
tree reaches from its second link keeps its values), names (a second round trip changes none), names XML cannot
hold (refused before anything is written), and weights, named configurations and descriptions (named in the
notes)."""

from pathlib import Path

import numpy as np
import pytest

from mechanisms import MechanismError, configuration, from_displacements, to_displacements
from mechanisms.catalogue import entry
from mechanisms.closures import closures_from_dict, closures_to_dict
from mechanisms.export import export_urdf, write_urdf
from mechanisms.io import mechanism_from_dict, read
from mechanisms.kinematics import closes
from mechanisms.urdf import import_tree, read_urdf, retype, tree_from_urdf

pytest.importorskip("yourdfpy")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
ROBOTS = Path(__file__).resolve().parents[1] / "data" / "robots"


def round_trip(mechanism):
    exported = export_urdf(mechanism)
    closures = closures_from_dict(closures_to_dict(exported.closures))
    return import_tree(retype(tree_from_urdf(exported.urdf, "exported"), closures), closures, mechanism.name)


def carried(original, imported, displacements):
    """The displacements of `imported` that the export says carry `displacements` of `original`: R and P under
    their names, a U's or C's values as ``<joint>_1`` and ``<joint>_2``, an S's rotation vector under its name
    (negated when it comes back with its links the other way), a chord S's as the importer's ``A--B`` joint."""
    joints = {joint.name: joint for joint in imported.joints}
    result = {}
    for joint in original.joints:
        value = displacements.get(joint.name)
        if value is None:
            continue
        if joint.type in ("U", "C"):
            result[f"{joint.name}_1"], result[f"{joint.name}_2"] = value
        elif joint.type == "S":
            name = joint.name if joint.name in joints else f"{joint.name}_A--{joint.name}_B"
            same = joints[name].links == joint.links
            assert same or joints[name].links == tuple(reversed(joint.links))
            result[name] = list(value) if same else [-item for item in value]
        else:
            result[joint.name] = value
    return result


#: a spatial loop whose U and R joints the tree reaches from their second links (listed [far, near])
BACKWARDS = {
    "name": "backwards", "space": "spatial",
    "joints": [
        {"name": "J1", "type": "U", "links": ["crank", "ground"], "point": [0, 0, 0],
         "axes": [[0, 0, 1], [1, 0.2, 0]], "actuated": True},
        {"name": "J2", "type": "S", "links": ["coupler", "crank"], "point": [1, 0, 0.2]},
        {"name": "J3", "type": "C", "links": ["rocker", "coupler"], "point": [1.5, 2, 0.5], "axis": [0.1, 1, 0.3]},
        {"name": "J4", "type": "R", "links": ["rocker", "ground"], "point": [3, 0, 0], "axis": [0.2, 0.3, 1],
         "actuated": True},
        {"name": "J5", "type": "P", "links": ["slider", "ground"], "axis": [1, 0.5, 0]},
        {"name": "J6", "type": "S", "links": ["slider", "coupler"], "point": [2, 1, 1]},
    ],
}


def closing(mechanism, seed):
    """A closed configuration near home: random displacements of every joint, projected onto the C-space."""
    rng = np.random.default_rng(seed)
    point = configuration(mechanism, {}).point
    requested = to_displacements(mechanism, point)
    for name, value in requested.items():
        requested[name] = (np.asarray(value) + 0.05 * rng.standard_normal(np.shape(value))).tolist()
    return to_displacements(mechanism, configuration(mechanism, requested, project_onto=True).point)


@pytest.mark.parametrize("source", ["five_bar.yaml", "backwards", "gough-stewart", "planar-six-bar",
                                    "spherical-3rrr", "3-prr", "5-spu"])
def test_joint_values_survive_the_round_trip(source):
    """The five-bar's J4 [distal2, proximal2] and J5 [proximal2, ground] are reached from their second links:
    they were written from it with the axis kept +z, so their values changed sign (the file's named
    configurations, given under the same names, did not close the exported robot); spatial R, P and C joints had
    their axes reversed, values kept, and a U so reached had its two angles under each other's names."""
    if source.endswith(".yaml"):
        document = read(EXAMPLES / source)
        mechanism, configurations = document.mechanism, list(document.configurations.values())
    else:
        mechanism = mechanism_from_dict(BACKWARDS) if source == "backwards" else entry(source).mechanism()
        configurations = [closing(mechanism, seed) for seed in range(2)]
    assert configurations
    imported = round_trip(mechanism).mechanism
    for displacements in configurations:
        assert closes(mechanism, from_displacements(mechanism, displacements))
        point = from_displacements(imported, carried(mechanism, imported, displacements))
        assert closes(imported, point), displacements


def test_a_planar_joint_reached_backwards_turns_about_minus_z():
    exported = export_urdf(read(EXAMPLES / "five_bar.yaml").mechanism)
    from xml.etree import ElementTree

    robot = ElementTree.fromstring(exported.urdf)
    axes = {joint.get("name"): joint.find("axis").get("xyz") for joint in robot.iter("joint")
            if joint.find("axis") is not None}
    assert axes["J1"] == "0.0 0.0 1.0" and axes["J5"] == "-0.0 -0.0 -1.0" and axes["J4"] == "-0.0 -0.0 -1.0"


def names(mechanism):
    return (sorted(joint.name for joint in mechanism.joints), sorted(mechanism.links), mechanism.ground,
            None if mechanism.end_effector is None else mechanism.end_effector.link,
            sorted(joint.name for joint in mechanism.joints if joint.actuated))


@pytest.mark.parametrize("name", ["five-bar", "slider-crank", "eclipse", "gough-stewart", "5-spu", "watt-six-bar"])
def test_a_second_round_trip_changes_no_name(name):
    """A chord S joint S2 came back as S2_A--S2_B, then S2_A--S2_B_A--S2_A--S2_B_B, growing at every trip; a
    welded chord's second link came back named after the chord's leaf (P_B, then P_B_...). Now link names survive
    the first trip (a U's or C's cross link added), and a second trip changes no name."""
    mechanism = entry(name).mechanism()
    once = round_trip(mechanism).mechanism
    twice = round_trip(once).mechanism
    assert names(twice) == names(once)
    crosses = {f"{joint.name}_cross" for joint in mechanism.joints if joint.type in ("U", "C")}  # U, C: two R/P
    assert sorted(once.links) == sorted({*mechanism.links, *crosses})
    assert once.end_effector is None or once.end_effector.link == mechanism.end_effector.link


@pytest.mark.parametrize("source", ["backwards", "rsur", "gough-stewart", "5-spu"])
def test_a_second_round_trip_keeps_every_joint_as_it_was(source):
    """The tree of a mechanism read back differs from the original's (the importer lists the closures last), so a
    ball joint that closed a loop on the first trip could be a tree joint reached from its second link on the
    second: its links came back the other way and its rotation vector negated, and a configuration of A' did not
    close A'' (found by an audit). Ball joints now close the loops wherever they can."""
    from builders import rsur

    mechanism = {"backwards": lambda: mechanism_from_dict(BACKWARDS), "rsur": rsur}.get(
        source, lambda: entry(source).mechanism())()
    once = round_trip(mechanism).mechanism
    twice = round_trip(once).mechanism
    assert {joint.name: (joint.type, joint.links) for joint in twice.joints} == \
        {joint.name: (joint.type, joint.links) for joint in once.joints}
    displacements = closing(once, 0)
    assert closes(twice, from_displacements(twice, displacements))


@pytest.mark.parametrize("robot", ["5bar_linkage_iso3d", "leg_floating", "legacy_walker"])
def test_a_robot_read_from_the_collection_exports_with_stable_names(robot):
    mechanism = read_urdf(ROBOTS / robot / "robot.urdf", ROBOTS / robot / "robot.yaml").mechanism
    once = round_trip(mechanism).mechanism
    assert names(round_trip(once).mechanism) == names(once)


def four_bar(joint="J1", link="a", name="four"):
    return mechanism_from_dict({"name": name, "space": "planar", "joints": [
        {"name": joint, "type": "R", "links": ["ground", link], "point": [0, 0], "actuated": True},
        {"name": "J2", "type": "R", "links": [link, "b"], "point": [0, 1]},
        {"name": "J3", "type": "R", "links": ["b", "c"], "point": [1, 1.5]},
        {"name": "J4", "type": "R", "links": ["c", "ground"], "point": [2, 0]}]})


@pytest.mark.parametrize("fields, message", [
    ({"joint": "J\x01"}, r"joint 'J\\x01': field 'name': the character U\+0001 cannot be written in a URDF \(XML 1.0"),
    ({"link": "a\x1b[31m"}, r"joint 'J1': field 'links': link 'a\\x1b\[31m': the character U\+001B .*rename the link"),
    ({"name": "four\x00"}, r"field 'name': 'four\\x00': the character U\+0000 .*rename the mechanism"),
    ({"joint": "J\ufffe"}, r"joint 'J\\ufffe': field 'name': the character U\+FFFE"),
])
def test_a_name_xml_cannot_hold_is_refused_before_writing(tmp_path, fields, message):
    """Such a name was written raw: the URDF written (exit 0) could not be read back ("not well-formed XML")."""
    with pytest.raises(MechanismError, match=message):
        write_urdf(four_bar(**fields), tmp_path / "x.urdf", tmp_path / "x.yaml")
    assert list(tmp_path.iterdir()) == []


def test_names_with_tabs_newlines_and_other_characters_xml_holds_come_back(tmp_path):
    mechanism = four_bar(joint="J\t1", link="a\nb\x7f\x85", name="four\r")
    write_urdf(mechanism, tmp_path / "x.urdf", tmp_path / "x.yaml")
    again = read_urdf(tmp_path / "x.urdf", tmp_path / "x.yaml").mechanism
    assert sorted(again.links) == sorted(mechanism.links)
    assert [joint.name for joint in again.joints if joint.actuated] == ["J\t1"]


def test_what_the_pair_cannot_hold_is_named_in_the_notes():
    """Weights, named configurations and the description were dropped without a word."""
    document = read(EXAMPLES / "five_bar.yaml")
    assert export_urdf(document.mechanism).notes == ()
    notes = export_urdf(document.mechanism, document.configurations, document.description).notes
    assert len(notes) == 2
    assert "named configurations" in notes[0] and "fig1a_collinear" in notes[0] and "description" in notes[1]
    data = {**BACKWARDS, "joints": [dict(joint) for joint in BACKWARDS["joints"]]}
    data["joints"][0]["weight"], data["joints"][3]["weight"] = 0.5, 4
    (note,) = export_urdf(mechanism_from_dict(data)).notes
    assert "weights of J1 (0.5), J4 (4)" in note and "proper values" in note
