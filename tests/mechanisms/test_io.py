"""Tests of mechanisms.io: the mechanism file format (docs/design.rst, "Mechanism file")."""

import json
import re

import pytest
import yaml

from mechanisms.errors import MechanismError
from mechanisms.io import (
    MechanismDocument, load, loads, mechanism_from_dict, mechanism_to_dict, read, save,
)
from mechanisms.joints import EndEffector, Joint
from mechanisms.mechanism import Mechanism

SUFFIXES = [".yaml", ".yml", ".json"]


def mechanism_fields(mechanism):
    """Everything a mechanism file describes (Mechanism compares by identity)."""
    return (mechanism.name, mechanism.space, mechanism.ground, mechanism.joints,
            mechanism.end_effector)


def five_bar():
    return Mechanism("five-bar", "planar", [
        Joint("J1", "R", ("ground", "proximal1"), point=(0, 0), actuated=True),
        Joint("J2", "R", ("proximal1", "distal1"), point=(0.0, 1.0)),
        Joint("J3", "R", ("distal1", "distal2"), point=(1.0, 2.0)),
        Joint("J4", "R", ("distal2", "proximal2"), point=(2.0, 1.0)),
        Joint("J5", "R", ("proximal2", "ground"), point=(2.0, 0.0), actuated=True, weight=0.5),
    ], end_effector=EndEffector("distal1", point=(1.0, 2.0)))


def spherical_four_bar():
    return Mechanism("spherical four-bar", "spherical", [
        Joint("A", "R", ("ground", "crank"), axis=(0, 0, 1), actuated=True),
        Joint("B", "R", ("crank", "coupler"), axis=(0.3, 0.1, 0.9)),
        Joint("C", "R", ("coupler", "rocker"), axis=(0.1, 0.7, 0.7)),
        Joint("D", "R", ("rocker", "ground"), axis=(0, 1, 0)),
    ], end_effector=EndEffector("coupler", output="orientation"))


def spatial_chain():
    """A single loop through R, P, U, S and C joints, grounded on a link called "base"."""
    return Mechanism("spatial chain", "spatial", [
        Joint("R1", "R", ("base", "a"), point=(0, 0, 0), axis=(0, 0, 1), actuated=True),
        Joint("P1", "P", ("a", "b"), axis=(1, 0, 0), actuated=True, weight=2.5),
        Joint("U1", "U", ("b", "c"), point=(1, 0, 0), axes=((0, 0, 1), (0, 1, 0))),
        Joint("S1", "S", ("c", "d"), point=(1, 1, 0)),
        Joint("C1", "C", ("d", "base"), point=(0, 1, 0), axis=(0, 0, 1)),
    ], ground="base", end_effector=EndEffector("c", point=(1, 0.5, 0.1 + 0.2), output="pose"))


MECHANISMS = [five_bar, spherical_four_bar, spatial_chain]


# ------------------------------------------------------------- malformed files

def test_malformed_case_is_refused_with_a_one_line_message(malformed_case, tmp_path):
    case_id, text, suffix, fragment = malformed_case
    path = tmp_path / f"mechanism{suffix}"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(MechanismError) as caught:
        read(path)
    message = str(caught.value)
    assert fragment in message
    assert len(message.splitlines()) == 1
    assert message.startswith(f"{path}: ")
    assert not re.match(r"\w*(Error|Exception)\(", message[len(f"{path}: "):])
    assert "Traceback" not in message


def test_malformed_case_is_refused_by_load_as_well(malformed_case, tmp_path):
    _, text, suffix, fragment = malformed_case
    path = tmp_path / f"mechanism{suffix}"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(MechanismError, match=re.escape(fragment)):
        load(path)


def test_malformed_cases_are_many_and_have_unique_ids(malformed_cases):
    ids = [case[0] for case in malformed_cases]
    assert len(ids) >= 25
    assert len(ids) == len(set(ids))
    assert all(len(case) == 4 and case[2] in (".yaml", ".yml", ".json", ".txt")
               for case in malformed_cases)


def test_valid_files_read(valid_file, tmp_path):
    name, text, suffix = valid_file
    path = tmp_path / f"{name}{suffix}"
    path.write_text(text, encoding="utf-8")
    assert read(path).mechanism.name == name


def test_missing_file_is_named(tmp_path):
    path = tmp_path / "absent.yaml"
    with pytest.raises(MechanismError, match=r"absent\.yaml: cannot read the file: No such file"):
        read(path)


def test_directory_is_refused(tmp_path):
    path = tmp_path / "folder.json"
    path.mkdir()
    with pytest.raises(MechanismError, match=r"folder\.json: cannot read the file"):
        read(path)


def test_binary_file_is_refused(tmp_path):
    path = tmp_path / "binary.yaml"
    path.write_bytes(b"name: \xff\xfe\x00five-bar\n")
    with pytest.raises(MechanismError, match=r"binary\.yaml: cannot read the file: not UTF-8"):
        read(path)


def test_path_of_wrong_type_is_refused():
    with pytest.raises(MechanismError, match="expected a file path"):
        read(3)


def test_unknown_text_format_is_refused():
    with pytest.raises(MechanismError, match="unknown format 'toml'"):
        loads("name = 'x'", format="toml")


@pytest.mark.parametrize("data, fragment", [
    (["five-bar"], "top level: expected a mapping"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": "ground-a", "point": [0, 0]}]},
     "joint 'J1': field 'links': expected two link names"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", ["a"]], "point": [0, 0]}]},
     "joint 'J1': field 'links'"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": "12"}]},
     "joint 'J1': field 'point': expected a list of numbers"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": [10 ** 400, 0]}]},
     "joint 'J1': field 'point': item 0: expected a finite number"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": [0, 0], "weight": True}]},
     "joint 'J1': field 'weight': expected a number, got true"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "", "type": "R", "links": ["ground", "a"], "point": [0, 0]}]},
     "field 'joints': item 0: field 'name': expected a non-empty string"),
    ({"name": "x", "space": ["planar"], "joints": []}, "field 'space': expected a non-empty string"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": [0, 0],
         "actuated": 10 ** 5000}]},
     "joint 'J1': field 'actuated': expected true or false, got a very large integer"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": [0, 0]}],
      "configurations": {1: {"J1": 0.0}}},
     "field 'configurations': expected configuration names to be non-empty strings, got 1"),
    ({"name": "x", "space": "planar", "joints": [
        {"name": "J1", "type": "R", "links": ["ground", "a"], "point": [0, 0]}],
      "configurations": {"c": {7: 0.0}}},
     "configurations['c']: joint 7: unknown joint"),
])
def test_dicts_built_in_python_are_checked_too(data, fragment):
    with pytest.raises(MechanismError) as caught:
        mechanism_from_dict(data, source="catalogue")
    assert fragment in str(caught.value)
    assert str(caught.value).startswith("catalogue: ")


# ----------------------------------------------------------------- round trips

@pytest.mark.parametrize("build", MECHANISMS)
def test_dict_round_trip(build):
    mechanism = build()
    data = mechanism_to_dict(mechanism)
    assert mechanism_fields(mechanism_from_dict(data)) == mechanism_fields(mechanism)
    assert json.loads(json.dumps(data)) == data


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("build", MECHANISMS)
def test_file_round_trip(build, suffix, tmp_path):
    mechanism = build()
    path = tmp_path / f"mechanism{suffix}"
    save(mechanism, path)
    assert mechanism_fields(load(path)) == mechanism_fields(mechanism)
    document = read(path)
    assert document.configurations == {} and document.description is None
    path_again = tmp_path / f"again{suffix}"
    save(document.mechanism, path_again)
    assert path_again.read_text() == path.read_text()


def test_written_files_are_plain_yaml_and_json(tmp_path):
    mechanism = spatial_chain()
    save(mechanism, tmp_path / "chain.yaml")
    save(mechanism, tmp_path / "chain.json")
    expected = mechanism_to_dict(mechanism)
    assert yaml.safe_load((tmp_path / "chain.yaml").read_text()) == expected
    assert json.loads((tmp_path / "chain.json").read_text()) == expected


def test_defaults_are_left_out():
    data = mechanism_to_dict(five_bar())
    assert "ground" not in data
    joints = {entry["name"]: entry for entry in data["joints"]}
    assert "actuated" not in joints["J2"] and "weight" not in joints["J2"]
    assert joints["J1"]["actuated"] is True and "weight" not in joints["J1"]
    assert joints["J5"]["weight"] == 0.5
    assert data["end_effector"] == {"link": "distal1", "point": [1.0, 2.0]}
    spatial = mechanism_to_dict(spatial_chain())
    assert spatial["ground"] == "base"
    assert spatial["end_effector"]["output"] == "pose"
    assert "point" not in mechanism_to_dict(spherical_four_bar())["end_effector"]


def test_values_are_kept_exactly():
    text = ("name: exact\nspace: planar\njoints:\n"
            "  - {name: J1, type: R, links: [ground, a], point: [0.1, 1e-3], weight: 3, actuated: true}\n"
            "  - {name: J2, type: P, links: [a, b], axis: [0x10, -2.5E+2]}\n")
    joints = loads(text).mechanism.joints
    assert joints[0].point == (0.1, 0.001) and joints[0].weight == 3.0
    assert joints[1].axis == (16.0, -250.0)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_configurations_and_description_round_trip(suffix, tmp_path):
    mechanism = spatial_chain()
    configurations = {
        "home": {},
        "bent": {"R1": 0.1, "P1": -0.25, "U1": [0.2, -0.1], "S1": [0.0, 0.0, 0.3],
                 "C1": [0.05, 0.01]},
        "yes": {"R1": 1e-17},
    }
    description = "A test chain.\nIt has: R, P, U, S and C joints — and a colon."
    path = tmp_path / f"chain{suffix}"
    save(mechanism, path, configurations=configurations, description=description)
    document = read(path)
    assert document.configurations == configurations
    assert document.description == description
    assert mechanism_fields(document.mechanism) == mechanism_fields(mechanism)
    assert document == MechanismDocument(mechanism, configurations, description)
    assert document != MechanismDocument(mechanism, {}, description)


def test_configuration_values_are_floats_and_lists():
    text = ("name: x\nspace: spatial\njoints:\n"
            "  - {name: S1, type: S, links: [ground, a], point: [0, 0, 0]}\n"
            "  - {name: P1, type: P, links: [a, b], axis: [0, 0, 1]}\n"
            "configurations: {c: {S1: [0, 1, 0], P1: 2}}\n")
    configuration = loads(text).configurations["c"]
    assert configuration == {"S1": [0.0, 1.0, 0.0], "P1": 2.0}
    assert all(type(value) is float for value in configuration["S1"] + [configuration["P1"]])


def test_save_refuses_bad_configurations_and_writes_nothing(tmp_path):
    path = tmp_path / "five_bar.yaml"
    with pytest.raises(MechanismError, match=r"configurations\['fig6a'\]: joint 'J9': unknown joint"):
        save(five_bar(), path, configurations={"fig6a": {"J9": 0.1}})
    assert not path.exists()


def test_save_refuses_unknown_extension(tmp_path):
    with pytest.raises(MechanismError, match=r"five_bar\.txt: unknown file format"):
        save(five_bar(), tmp_path / "five_bar.txt")


def test_save_reports_an_unwritable_path(tmp_path):
    with pytest.raises(MechanismError, match="cannot write the file"):
        save(five_bar(), tmp_path / "missing-folder" / "five_bar.json")


def test_strings_that_look_like_other_types_round_trip(tmp_path):
    mechanism = Mechanism("yes", "planar", [
        Joint("on", "R", ("ground", "1e3"), point=(0, 0), actuated=True),
        Joint("0o17", "R", ("1e3", "null"), point=(1, 0)),
        Joint("1:30", "P", ("null", "true"), axis=(1, 0)),
    ], end_effector=EndEffector("true", point=(1, 0)))
    for suffix in SUFFIXES:
        path = tmp_path / f"tricky{suffix}"
        save(mechanism, path, configurations={"no": {"on": 0.5}}, description="off")
        document = read(path)
        assert mechanism_fields(document.mechanism) == mechanism_fields(mechanism)
        assert document.configurations == {"no": {"on": 0.5}}
        assert document.description == "off"


# --------------------------------------------------------------- the contract

DESIGN_EXAMPLE = """\
name: five-bar
space: planar            # planar | spherical | spatial
ground: ground           # optional, default "ground"
joints:
  - {name: J1, type: R, links: [ground, proximal1], point: [0, 0], actuated: true}
  - {name: S1, type: P, links: [ground, slider], axis: [1, 0]}
end_effector:            # optional
  link: distal1
  point: [1.0, 1.0]      # planar/spatial; not for spherical
  output: position       # position | orientation | pose
"""


def test_design_example_parses_once_its_end_effector_is_on_one_of_its_links():
    document = loads(DESIGN_EXAMPLE.replace("link: distal1", "link: proximal1"))
    mechanism = document.mechanism
    assert (mechanism.name, mechanism.space, mechanism.ground) == ("five-bar", "planar", "ground")
    assert mechanism.joints == (
        Joint("J1", "R", ("ground", "proximal1"), point=(0.0, 0.0), actuated=True),
        Joint("S1", "P", ("ground", "slider"), axis=(1.0, 0.0)),
    )
    assert mechanism.end_effector == EndEffector("proximal1", point=(1.0, 1.0), output="position")
    assert document.configurations == {} and document.description is None


def test_design_example_verbatim_names_its_unknown_end_effector_link():
    # The example in docs/design.rst puts the end-effector on "distal1", which none
    # of its two joints joins; the loader says so instead of guessing.
    with pytest.raises(MechanismError, match="end_effector: field 'link': unknown link 'distal1'"):
        loads(DESIGN_EXAMPLE)


def test_design_example_as_json():
    data = yaml.safe_load(DESIGN_EXAMPLE.replace("link: distal1", "link: proximal1"))
    document = loads(json.dumps(data), format="json")
    assert mechanism_fields(document.mechanism) == mechanism_fields(
        loads(DESIGN_EXAMPLE.replace("link: distal1", "link: proximal1")).mechanism)


def test_null_optional_sections_mean_none():
    text = ("name: x\nspace: planar\njoints: [{name: J1, type: R, links: [ground, a], "
            "point: [0, 0]}]\nend_effector:\ndescription:\nconfigurations:\n")
    document = loads(text)
    assert document.mechanism.end_effector is None
    assert document.configurations == {} and document.description is None
