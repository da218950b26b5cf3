"""Tests of mechanisms.io: the mechanism file format (docs/design.rst, "Mechanism file")."""

import json
import os
import re

import pytest
import yaml

from mechanisms import catalogue
from mechanisms.errors import MechanismError
from mechanisms.io import (
    FILE_SIZE_LIMIT, MechanismDocument, load, loads, mechanism_from_dict, mechanism_to_dict, read,
    read_text_file, save, write_text_file,
)
from mechanisms.mechanism import DENSE_MEMORY_LIMIT, dense_memory_estimate
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


# ------------------------------------------- refusals found by fuzzing (issue 10)

FOUR_BAR_YAML = """\
name: four-bar
space: planar
joints:
  - {name: A, type: R, links: [ground, crank], point: [0, 0], actuated: true}
  - {name: B, type: R, links: [crank, coupler], point: [0, 1]}
  - {name: C, type: R, links: [coupler, rocker], point: [2, 1.5]}
  - {name: D, type: R, links: [rocker, ground], point: [2, 0]}
end_effector: {link: coupler, point: [1, 1]}
"""


def refusal(text, file_format="yaml"):
    """The one-line message with which `text` is refused."""
    with pytest.raises(MechanismError) as caught:
        loads(text, file_format)
    message = str(caught.value)
    assert len(message.splitlines()) == 1
    return message


def test_misspelt_link_is_refused_naming_the_joint_and_the_likely_name():
    message = refusal(FOUR_BAR_YAML.replace("links: [coupler, rocker]", "links: [copuler, rocker]"))
    assert message == ("mechanism text: joint 'C': field 'links': item 0: link 'copuler' appears in no other "
                       "joint and is neither the ground nor the end-effector's link: probably a misspelling of "
                       "'coupler' (known links: ground, crank, coupler, rocker)")


def test_misspelt_ground_is_refused():
    message = refusal(FOUR_BAR_YAML.replace("[rocker, ground]", "[rocker, grund]"))
    assert "joint 'D': field 'links': item 1: link 'grund'" in message
    assert "probably a misspelling of 'ground'" in message


def test_two_dangling_look_alike_links_are_refused_together():
    text = FOUR_BAR_YAML.replace("links: [coupler, rocker]", "links: [copuler, rocker]").replace(
        "end_effector: {link: coupler, point: [1, 1]}\n", "")
    message = refusal(text)
    assert "links 'coupler' and 'copuler' (joint 'C') each appear in one joint only" in message
    assert "one is probably a misspelling of the other" in message


def test_dangling_link_in_a_mechanism_with_loops_is_refused():
    text = FOUR_BAR_YAML.replace("joints:\n", "joints:\n  - {name: E, type: R, links: [crank, flag], "
                                               "point: [0, 0.5]}\n")
    assert "joint 'E': field 'links': item 1: link 'flag' appears in no other joint" in refusal(text)
    assert "probably a misspelt name (known links: ground, crank, coupler, rocker)" in refusal(text)


def test_serial_chain_and_tree_with_distinct_names_are_accepted_without_loops():
    serial = loads("name: arm\nspace: planar\njoints:\n"
                   "  - {name: shoulder, type: R, links: [ground, upper_arm], point: [0, 0], actuated: true}\n"
                   "  - {name: elbow, type: R, links: [upper_arm, forearm], point: [1, 0], actuated: true}\n"
                   "end_effector: {link: forearm, point: [2, 0]}\n").mechanism
    assert serial.loop_count == 0
    tree = loads("name: tree\nspace: planar\njoints:\n"
                 "  - {name: A, type: R, links: [ground, arm], point: [0, 0]}\n"
                 "  - {name: B, type: R, links: [arm, hand_left], point: [0, 1]}\n"
                 "  - {name: C, type: R, links: [arm, hand_right], point: [0, 1]}\n"
                 "  - {name: D, type: R, links: [arm, finger1], point: [0, 1]}\n"
                 "  - {name: E, type: R, links: [arm, finger2], point: [0, 1]}\n").mechanism
    assert tree.loop_count == 0


@pytest.mark.parametrize("where, document", [
    ("field 'joints': item 0: field 'name'", {"joints": [{"name": "J\ud800"}]}),
    ("joint 'A': field 'links': item 1", {"joints": [{"links": ["ground", "\udfff"]}]}),
    ("field 'name'", {"name": "four\ud83d"}),
    ("field 'description'", {"description": "text \udc80"}),
])
def test_lone_surrogates_are_refused_as_invalid_text(where, document):
    data = yaml.safe_load(FOUR_BAR_YAML)
    for key, value in document.items():
        if key == "joints":
            data["joints"][0].update(value[0])
        else:
            data[key] = value
    message = refusal(json.dumps(data), "json")
    assert f"{where}: not valid text: lone surrogate U+" in message


def test_configuration_name_with_a_surrogate_is_refused():
    message = refusal(json.dumps({**yaml.safe_load(FOUR_BAR_YAML), "configurations": {"c\ud800": {"A": 0}}}),
                      "json")
    assert "not valid text: lone surrogate U+D800 at position 1" in message


def test_long_names_are_refused():
    message = refusal(FOUR_BAR_YAML.replace("name: A,", f"name: {'A' * 300},"))
    assert "field 'name': expected a name of at most 256 characters, got 300" in message


@pytest.mark.parametrize("old, new, fragment", [
    ("point: [2, 1.5]", "point: [2e13, 1.5]", "joint 'C': field 'point': item 0: 2e+13 is out of range"),
    ("point: [2, 1.5]", "point: [2, -1e200]", "joint 'C': field 'point': item 1: -1e+200 is out of range"),
    ("point: [1, 1]}", "point: [1, 1e300]}", "end_effector: field 'point': item 1: 1e+300 is out of range"),
    ("actuated: true}", "actuated: true, weight: 1e300}", "joint 'A': field 'weight': expected a weight between"),
    ("actuated: true}", "actuated: true, weight: 1e-300}", "joint 'A': field 'weight': expected a weight between"),
])
def test_coordinates_and_weights_beyond_the_sane_range_are_refused(old, new, fragment):
    assert fragment in refusal(FOUR_BAR_YAML.replace(old, new))


def test_axis_beyond_the_sane_range_is_refused():
    text = "name: s\nspace: planar\njoints: [{name: S, type: P, links: [ground, b], axis: [1e15, 0]}]\n"
    assert "joint 'S': field 'axis': item 0: 1e+15 is out of range" in refusal(text)


def test_displacement_beyond_the_sane_range_is_refused():
    message = refusal(FOUR_BAR_YAML + "configurations: {far: {A: 1.0e+13}}\n")
    assert "configurations['far']: joint 'A': 1e+13 is out of range" in message


def scaled(data, factor):
    """A mechanism file's data with every point multiplied by `factor`."""
    data = json.loads(json.dumps(data))
    for entry in data["joints"] + ([data["end_effector"]] if data.get("end_effector") else []):
        if "point" in entry:
            entry["point"] = [factor * value for value in entry["point"]]
    return data


def test_geometry_too_small_for_the_tolerances_is_refused():
    message = refusal(json.dumps(scaled(yaml.safe_load(FOUR_BAR_YAML), 1e-150)), "json")
    assert message == ("mechanism text: field 'joints': the geometry is too small: the largest distance between two "
                       "points of one link is 2.06e-150, below 1e-09; describe the mechanism in a smaller unit "
                       "of length")


@pytest.mark.parametrize("name", catalogue.names())
@pytest.mark.parametrize("factor", [1e-6, 1e6])
def test_catalogue_in_micrometres_or_kilometres_is_accepted(name, factor):
    mechanism = catalogue.entry(name).mechanism()
    document = loads(json.dumps(scaled(mechanism_to_dict(mechanism), factor)), "json")
    expected = mechanism.characteristic_length * (1 if mechanism.space == "spherical" else factor)
    assert document.mechanism.characteristic_length == pytest.approx(expected)


# ---------------------------------------------------------------- files

def test_file_over_the_size_limit_is_refused_with_its_size(tmp_path):
    path = tmp_path / "big.yaml"
    path.write_text("#" * (FILE_SIZE_LIMIT + 10) + "\n")
    with pytest.raises(MechanismError) as caught:
        read(path)
    assert str(caught.value) == (f"{path}: the file is too large: {FILE_SIZE_LIMIT + 11} bytes "
                                 f"(the limit is {FILE_SIZE_LIMIT} bytes)")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this platform")
def test_fifo_is_refused_without_blocking(tmp_path):
    path = tmp_path / "pipe.yaml"
    os.mkfifo(path)
    with pytest.raises(MechanismError, match="cannot read the file: it is a FIFO \\(named pipe\\), not a regular file"):
        read(path)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero on this platform")
def test_device_is_refused_without_reading_it(tmp_path):
    path = tmp_path / "zero.yaml"
    path.symlink_to("/dev/zero")
    with pytest.raises(MechanismError, match="cannot read the file: it is a character device, not a regular file"):
        read(path)


def test_binary_file_is_refused_as_not_utf8(tmp_path):
    path = tmp_path / "binary.json"
    path.write_bytes(b"\x7fELF\x02\x01\x01\x00\xff\xfe")
    with pytest.raises(MechanismError, match="not UTF-8 text"):
        read_text_file(path)


def test_path_with_a_nul_byte_is_refused(tmp_path):
    with pytest.raises(MechanismError, match="cannot read the file: the path has a NUL byte in it"):
        read(str(tmp_path / "a\x00b.yaml"))


@pytest.mark.parametrize("name, reason", [
    ("missing/five_bar.yaml", "No such file or directory"),
    ("folder.yaml", "Is a directory"),
])
def test_write_text_file_reports_the_operating_system_reason(name, reason, tmp_path):
    (tmp_path / "folder.yaml").mkdir()
    with pytest.raises(MechanismError) as caught:
        write_text_file(tmp_path / name, "text")
    assert str(caught.value) == f"{tmp_path / name}: cannot write the file: {reason}"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this platform")
def test_write_text_file_reports_a_full_device_on_flush(tmp_path):
    path = tmp_path / "full.yaml"
    path.symlink_to("/dev/full")
    with pytest.raises(MechanismError, match="cannot write the file: No space left on device"):
        save(five_bar(), path)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this platform")
def test_write_text_file_refuses_a_fifo_nobody_reads(tmp_path):
    path = tmp_path / "pipe.yaml"
    os.mkfifo(path)
    with pytest.raises(MechanismError, match="cannot write the file: it is a FIFO that no process is reading"):
        save(five_bar(), path)


# ------------------------------------------------------- YAML and JSON limits

@pytest.mark.parametrize("text, fragment", [
    ("name: &a five\nspace: *a\n", "found an anchor &a: anchors and aliases are not allowed"),
    ("name: x\nspace: *a\n", "found an alias *a: anchors and aliases are not allowed"),
    ("name: x\n<<: {space: planar}\n", "found a merge key '<<': merge keys are not allowed"),
    ("name: !!binary aGVsbG8=\n", "found the tag '!!binary': a mechanism file holds plain data"),
    ("name: !!python/name:os.system\n", "found the tag '!!python/name:os.system'"),
    ("name: !local x\n", "found the tag '!local'"),
    ("name: " + "[" * 50 + "]" * 50 + "\n", "the document nests deeper than 20 levels"),
    ("name: x\nspace: planar\njoints: [{point: [" + "9" * 500 + "]}]\n",
     "an integer of 500 digits is out of range (at most 400)"),
    ("name: x\nspace: planar\njoints: [{point: [1e-400, 0]}]\n",  # was read as 0
     "1e-400 is nonzero but below the smallest float (it would read as 0) at line 3"),
])
def test_yaml_features_a_mechanism_file_does_not_need_are_refused(text, fragment):
    message = refusal(text)
    assert message.startswith("mechanism text: cannot parse YAML: ") and fragment in message


def test_plain_tags_are_accepted():
    document = loads(FOUR_BAR_YAML.replace("name: four-bar", "name: !!str four-bar"))
    assert document.mechanism.name == "four-bar"


@pytest.mark.parametrize("text, fragment", [
    ("[" * 100_000 + "]" * 100_000, "the document nests deeper than 20 levels"),
    ('{"name": ' + "[" * 30 + "]" * 30 + "}", "the document nests deeper than 20 levels"),
    ('{"name": ' + "9" * 5000 + "}", "an integer of 5000 digits is out of range (at most 400)"),
    ('{"name": 1.5e-400}', "1.5e-400 is nonzero but below the smallest float (it would read as 0)"),
])
def test_pathological_json_is_refused(text, fragment):
    assert refusal(text, "json") == f"mechanism text: cannot parse JSON: {fragment}"


def test_billion_laughs_is_refused_at_once():
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    lines += [f"a{level}: &a{level} [{', '.join([f'*a{level - 1}'] * 9)}]" for level in range(1, 10)]
    assert "anchors and aliases are not allowed" in refusal("\n".join(lines))


# ---------------------------------------------------------- size of the mechanism

def ladder(loops):
    """A planar ladder of `loops` four-bar loops stacked on the ground: 4 joints per loop."""
    joints = []
    for index in range(1, loops + 1):
        below, above = ("ground" if index == 1 else f"rung{index - 1}"), f"rung{index}"
        joints += [Joint(f"A{index}", "R", (below, f"left{index}"), point=(0.0, index - 1.0)),
                   Joint(f"B{index}", "R", (f"left{index}", above), point=(0.1, float(index))),
                   Joint(f"C{index}", "R", (below, f"right{index}"), point=(1.0, index - 1.0)),
                   Joint(f"D{index}", "R", (f"right{index}", above), point=(1.1, float(index)))]
    return Mechanism(f"ladder of {loops}", "planar", joints,
                     end_effector=EndEffector(f"rung{loops}", point=(0.5, float(loops))))


def test_hundred_loop_ladder_is_within_the_dense_memory_limit():
    mechanism = ladder(100)
    assert (len(mechanism.joints), mechanism.loop_count, mechanism.ambient_dimension) == (400, 100, 400)
    assert mechanism.dense_memory_estimate == dense_memory_estimate(400, 300) < DENSE_MEMORY_LIMIT


def test_every_catalogue_entry_is_far_within_the_dense_memory_limit():
    for item in catalogue.entries():
        assert item.mechanism().dense_memory_estimate < DENSE_MEMORY_LIMIT / 100


def test_mechanism_too_large_for_the_dense_algorithms_is_refused_with_its_size():
    lines = ["name: pendulums", "space: planar", "joints:"]
    lines += [f"  - {{name: P{index}, type: R, links: [ground, pendulum{index}], point: [{index}.0, 0.0]}}"
              for index in range(6000)]
    message = refusal("\n".join(lines))
    assert message == ("mechanism text: field 'joints': the mechanism is too large for the dense algorithms: 6000 "
                       "joint coordinates and 0 constraint rows need at least 1.07 GiB (8·(c·k + 4·k·(k − c)) "
                       "bytes: DΦ and the tangent bases of M), more than the limit of 1 GiB")


def test_a_mechanism_just_over_the_dense_memory_limit_is_refused_with_a_size_that_reads_above_it():
    """32·5793² = 1,073,883,168 bytes against 2³⁰: to 3 digits both read ``1 GiB`` ("needs 1 GiB, more than the
    limit of 1 GiB"); the size is shown to the digits that tell them apart."""
    joints = [Joint(f"J{index}", "R", ("ground" if index == 0 else f"l{index - 1}", f"l{index}"),
                    point=(float(index), 0.0)) for index in range(5793)]
    with pytest.raises(MechanismError, match=r"need at least 1\.0001 GiB .* more than the limit of 1 GiB$"):
        Mechanism("chain", "planar", joints)
