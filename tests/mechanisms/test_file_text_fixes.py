"""What a mechanism file's text may say and how it reads back (found by an audit of the file format): explicit
YAML tags read only what the YAML 1.2 core schema reads, Unicode's other line breaks survive writing YAML, names
that are one text in two Unicode forms are refused, a mechanism without loops is warned of with its free end
links, and a named configuration that does not close is blamed on ``--configuration``, not on ``--at``."""

import dataclasses
import unicodedata

import pytest

from classify.cli import main
from mechanisms import MechanismError, Joint, Mechanism, catalogue
from mechanisms.io import loads, read, save

FOUR_BAR = """\
name: four-bar
space: planar
joints:
  - {{name: A, type: R, links: [ground, crank], point: [0, 0], actuated: {actuated}}}
  - {{name: B, type: R, links: [crank, {coupler_b}], point: [0, 1]}}
  - {{name: C, type: R, links: [{coupler_c}, rocker], point: [2, 1.5]}}
  - {{name: D, type: R, links: [rocker, ground], point: [{rocker_x}, 0]}}
"""


def four_bar(actuated="true", coupler_b="coupler", coupler_c="coupler", rocker_x="2"):
    return FOUR_BAR.format(actuated=actuated, coupler_b=coupler_b, coupler_c=coupler_c, rocker_x=rocker_x)


@pytest.mark.parametrize("field, text", [("actuated", "!!bool yes"), ("actuated", "!!bool on"),
                                         ("rocker_x", "!!int '١'"), ("rocker_x", "!!float '1_0'"),
                                         ("rocker_x", "!!int '1_0'"), ("rocker_x", "!!int 1.5")])
def test_an_explicit_tag_reads_only_what_the_core_schema_reads(field, text):
    """``actuated: yes`` and ``'١'`` are refused as plain scalars; written with a tag they were read as true and 1."""
    with pytest.raises(MechanismError, match=r"is not (a boolean|an integer|a number) .* YAML 1\.2 core schema "
                                             r"at line \d+, column \d+"):
        loads(four_bar(**{field: text}))


@pytest.mark.parametrize("field, text, read_as", [("actuated", "!!bool true", True),
                                                  ("actuated", "!!bool False", False),
                                                  ("rocker_x", "!!int 2", 2.0), ("rocker_x", "!!float 2", 2.0),
                                                  ("rocker_x", "!!int 0x2", 2.0), ("rocker_x", "!!float 2.0e0", 2.0)])
def test_an_explicit_tag_of_core_text_still_reads(field, text, read_as):
    mechanism = loads(four_bar(**{field: text})).mechanism
    joint = mechanism.joint("A") if field == "actuated" else mechanism.joint("D")
    assert (joint.actuated if field == "actuated" else joint.point[0]) == read_as


@pytest.mark.parametrize("suffix", [".yaml", ".json"])
@pytest.mark.parametrize("line_break", ["\x85", "\u2028", "\u2029"])
def test_other_line_breaks_in_names_and_description_read_back(tmp_path, suffix, line_break):
    """PyYAML wrote NEL raw in a plain or single-quoted scalar, and read it back as a space: ``'J\\x852'`` became
    ``'J 2'``."""
    mechanism = catalogue.entry("slider-crank").mechanism()
    renamed = {joint.name: f"{joint.name}{line_break}x" for joint in mechanism.joints}
    joints = [dataclasses.replace(joint, name=renamed[joint.name]) for joint in mechanism.joints]
    end_effector = mechanism.end_effector
    changed = Mechanism(f"slider{line_break}crank", mechanism.space, joints, mechanism.ground, end_effector)
    description = f"line one{line_break}line two"
    path = tmp_path / f"m{suffix}"
    save(changed, path, description=description)
    document = read(path)
    assert document.description == description
    assert document.mechanism.name == changed.name
    assert [joint.name for joint in document.mechanism.joints] == [joint.name for joint in joints]


def test_names_that_are_one_text_in_two_unicode_forms_are_refused():
    """A coupler written ``bi\\xe9lle`` in one joint and ``bie\\u0301lle`` in the other printed alike and opened
    the loop without a word (the four-bar read as a serial chain of 4 freedoms)."""
    composed = "bi\u00e9lle"
    decomposed = unicodedata.normalize("NFD", composed)
    assert loads(four_bar(coupler_b=composed, coupler_c=composed)).mechanism.loop_count == 1
    with pytest.raises(MechanismError, match=r"joint 'C': field 'links': item 0: link name 'bie\\u0301lle' and "
                                             r"'bi\\xe9lle' \(joint 'B'\) are one text in two Unicode forms"):
        loads(four_bar(coupler_b=composed, coupler_c=decomposed))


def test_joint_names_that_are_one_text_in_two_unicode_forms_are_refused():
    composed = Joint(name="\u00e93", type="R", links=("ground", "a"), point=(0.0, 0.0))
    decomposed = Joint(name="e\u03013", type="R", links=("a", "b"), point=(1.0, 0.0))
    with pytest.raises(MechanismError, match=r"field 'name': joint name 'e\\u03013' and '\\xe93' are one text"):
        Mechanism("two", "planar", [composed, decomposed], "ground")


def test_a_mechanism_without_loops_is_warned_of_with_its_free_end_links(tmp_path, capsys):
    """A one-digit typo (``distal3`` for ``distal2``) is no look-alike (serial chains number their links), so the
    five-bar opens into a chain of 5 freedoms; the warning names the two free ends that give the typo away."""
    text = """\
name: five-bar
space: planar
joints:
  - {name: J1, type: R, links: [ground, proximal1], point: [0, 0], actuated: true}
  - {name: J2, type: R, links: [proximal1, distal1], point: [0, 1]}
  - {name: J3, type: R, links: [distal1, distal2], point: [1, 1]}
  - {name: J4, type: R, links: [distal3, proximal2], point: [2, 1]}
  - {name: J5, type: R, links: [proximal2, ground], point: [2, 0], actuated: true}
"""
    path = tmp_path / "typo.yaml"
    path.write_text(text)
    status = main(["classify", str(path)])
    err = capsys.readouterr().err
    assert status == 0
    assert ("warning: five-bar has no loop (a serial chain; free end links: distal2 (joint J3), "
            "distal3 (joint J4))") in err


NOT_CLOSING = four_bar() + "configurations: {apart: {A: 0.3}}\n"


@pytest.mark.parametrize("command, extra", [("classify", []), ("draw", ["--out", "x.png"]),
                                            ("conditioning", []), ("compare", ["--outputs", "D", "--project"]),
                                            ("loci", []), ("map", ["--grid", "A=0:1:3"])])
def test_a_named_configuration_that_does_not_close_is_blamed_on_its_option(tmp_path, monkeypatch, capsys,
                                                                           command, extra):
    """``classify`` and ``draw`` said ``--at: the configuration does not close`` when no ``--at`` was given, and
    ``compare``, ``conditioning`` and ``loci`` offered ``--project``, which does not move it (or does not exist)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "m.yaml").write_text(NOT_CLOSING)
    status = main([command, "m.yaml", "--configuration", "apart", *extra])
    captured = capsys.readouterr()
    assert status == 2 and captured.err.count("\n") == 1, captured.err
    assert captured.err.startswith("closedchain: error: --configuration apart: the configuration does not close")
    # --project is offered only where it would move this configuration (compare's moves its --at ones only)
    assert ("--project" in captured.err) == (command != "conditioning" and command != "loci"), captured.err
    assert ("--at configurations only" in captured.err) == (command == "compare"), captured.err
    if command != "conditioning":
        return
    status = main([command, "m.yaml", "--configuration", "apart", "--at", '{"B": 0.1}'])
    assert status == 2
    assert capsys.readouterr().err.startswith("closedchain: error: --configuration apart with --at: the configuration")


@pytest.mark.parametrize("field", ["ground", "end_effector"])
def test_the_ground_or_end_effector_link_in_another_unicode_form_is_named_so(field):
    """The ground or the end-effector's link written ``é`` where the joints write ``e`` + U+0301 was refused as
    "not joined to any joint" / "unknown link", naming a link that prints exactly like a known one."""
    composed = "bi\u00e9lle"
    decomposed = unicodedata.normalize("NFD", composed)
    text = four_bar(coupler_b=decomposed, coupler_c=decomposed)
    if field == "ground":
        text = text.replace("ground", decomposed.replace("bi", "gr")) + f"ground: {composed.replace('bi', 'gr')}\n"
        match = r"field 'ground': link name 'gr\\xe9lle' and 'gre\\u0301lle' \(joint 'A'\) are one text"
    else:
        text += f"end_effector: {{link: {composed}, point: [1, 1]}}\n"
        match = r"end_effector: field 'link': link name 'bi\\xe9lle' and 'bie\\u0301lle' \(joint 'B'\) are one text"
    with pytest.raises(MechanismError, match=match):
        loads(text)
