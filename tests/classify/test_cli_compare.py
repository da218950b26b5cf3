"""``closedchain compare``: the JSON of the issue (per configuration ``park_kim``,
``gosselin_angeles`` with ``kinds``, ``rank_A``, ``rank_B``, ``n``, ``agree``, ``note``; a
``summary``), the text table, inputs and outputs chosen on the command line, one-line errors."""

import json
from pathlib import Path

import pytest

from builders import command as run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_compare_json_follows_the_issue(capsys):
    status, out, err = run(["compare", "slider-crank", "--configuration", "fig3b_actuator", "--outputs", "slide",
                            "--samples", "2", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    rows = result["configurations"]
    assert [row["configuration"] for row in rows][0] == "fig3b_actuator" and len(rows) == 3
    for row in rows:
        assert {"park_kim", "gosselin_angeles", "agree", "note"} <= set(row)
        assert {"kinds", "rank_A", "rank_B", "n"} <= set(row["gosselin_angeles"])
        assert set(row["gosselin_angeles"]["kinds"]) <= {"I", "II", "III"}
        assert row["park_kim"]["mechanism"] == "slider-crank"
    home = rows[0]
    assert home["park_kim"]["kinds"] == ["actuator"] and home["gosselin_angeles"]["kinds"] == ["II"]
    assert (home["gosselin_angeles"]["rank_A"], home["gosselin_angeles"]["rank_B"], home["gosselin_angeles"]["n"]) \
        == (0, 1, 1)
    assert home["agree"] is True
    assert result["summary"]["configurations"] == 3 and result["summary"]["agree"] == 3
    assert result["inputs"] == ["crank"] and result["outputs"] == ["slide"]


def test_compare_text_of_a_redundantly_actuated_five_bar(capsys):
    status, out, err = run(["compare", "five-bar", "--inputs", "A,B,D", "--samples", "1"], capsys)
    assert status == 0, err
    assert "redundant_actuation" in out and "undefined" in out
    assert "0 of 2 configurations correspond" in out


def test_compare_a_file_at_given_configurations_and_along_a_path(capsys):
    at = json.dumps({"J1": 0.1, "J5": -0.1})
    status, out, err = run(["compare", str(EXAMPLES / "five_bar.yaml"), "--at", at, "--project", "--path", "2",
                            "--samples", "0", "--format", "json"], capsys)
    assert status == 0, err
    labels = [row["configuration"] for row in json.loads(out)["configurations"]]
    assert labels[labels.index("home") - 1:labels.index("home") + 2] == ["path-1", "home", "path+1"]
    assert labels[-1] == "at1"


def test_compare_with_the_papers_relation(capsys):
    """Eq. 9 of Gosselin & Angeles at the branch point of Fig. 3, then eq. 12 there: the reasons."""
    base = ["compare", "slider-crank", "--configuration", "fig3b_actuator", "--outputs", "slide", "--samples", "0",
            "--format", "json"]
    status, out, err = run(base + ["--relation", "eq9"], capsys)
    assert status == 0, err
    result = json.loads(out, parse_constant=lambda name: pytest.fail(f"{name} is not JSON"))
    assert result["configurations"][0]["gosselin_angeles"]["B"] == [[None]]  # ∂F/∂θ infinite
    assert result["gosselin_angeles_source"].startswith("eq9")
    assert result["configurations"][0]["reason"] == "not_differentiable"
    status, out, err = run(base + ["--relation", "eq12"], capsys)
    row = json.loads(out)["configurations"][0]
    assert row["agree"] is True and row["gosselin_angeles"]["kinds"] == ["II"]


def test_the_branch_sign_of_a_relation_is_the_starts_along_a_path_too(capsys):
    """Eq. 9's ± (Gosselin & Angeles 1990) is taken at the start, not at the path's first point: from θ = 0.4
    back along the path the other branch of eq. 9 made the start and most rows 'inconsistent_relation'."""
    arguments = ["compare", "slider-crank", "--param", "theta=0.4", "--outputs", "slide", "--relation", "eq9",
                 "--format", "json"]
    status, out, err = run(arguments, capsys)
    assert status == 0, err
    alone = json.loads(out)
    status, out, err = run(arguments + ["--path", "10", "--path-step", "0.2"], capsys)
    assert status == 0, err
    along = json.loads(out)
    assert along["gosselin_angeles_source"] == alone["gosselin_angeles_source"] == "eq9[+]"
    home = next(row for row in along["configurations"] if row["configuration"] == "home")
    assert home["agree"], home


@pytest.mark.parametrize("arguments, fragment", [
    (["compare", "five-bar", "--relation", "eq9"], "--relation: no relation 'eq9' for 'five-bar'"),
    (["compare", "five-bar", "--inputs", "A,Z"], "--inputs: no joint 'Z'"),
    (["compare", "five-bar", "--outputs", "P,P"], "--outputs: joint 'P' is named twice"),
    (["compare", "five-bar", "--inputs", "A,,B"], "--inputs: expected comma-separated joint names"),
    (["compare", "five-bar", "--samples", "-1"], "--samples: expected a count ≥ 0"),
    (["compare", "spherical-six-bar"], "--outputs: 'spherical-six-bar' has no end-effector"),
    (["compare", "five-bar", "--at", "[1]"], "--at: expected a JSON object"),
    (["compare", "no-such-thing"], "no such file or catalogue entry"),
    # options that were ignored: --inputs replaced by the relation's, --path-step without a path
    (["compare", "slider-crank", "--relation", "eq9", "--inputs", "slide", "--outputs", "pin"],
     "--inputs: a --relation has the paper's inputs"),
    (["compare", "slider-crank", "--path-step", "0.1"], "--path-step: applies to a --path"),
    # the paper's relation has the crank as input: with the slide driven every row compared two problems
    (["compare", "slider-crank", "--configuration", "fig3d_dead_centre", "--relation", "eq9"],
     "--relation: eq9's inputs are the paper's, not the actuated coordinates here (slide)"),
    (["compare", "slider-crank", "--configuration", "eq17_constant_branch_slider_driven", "--relation", "eq12"],
     "--relation: eq12's inputs are the paper's"),
    # outputs other than the relation's: an internal error (more coordinates) or a false 'unexplained'
    (["compare", "slider-crank", "--relation", "eq12", "--outputs", "slide,crank"],
     "--outputs: eq12's outputs are the paper's: give --outputs slide"),
    (["compare", "slider-crank", "--configuration", "fig3c_dead_centre", "--relation", "eq9", "--outputs", "pin"],
     "--outputs: eq9's outputs are the paper's: give --outputs slide"),
    (["compare", "planar-3rrr", "--relation", "eq44", "--outputs", "wrist1,wrist2,wrist3"],
     "--outputs: eq44's outputs are the paper's: give no --outputs (the end-effector)"),
    (["compare", "slider-crank", "--param", "crank=3", "--param", "crank=4"], "--param crank: given twice"),
])
def test_compare_input_errors_exit_2_with_one_line(arguments, fragment, capsys):
    status, out, err = run(arguments, capsys)
    assert status == 2 and fragment in err and len(err.strip().splitlines()) == 1 and not out


# ---------------------------------------------------------------- rows named by their configuration, the source

def test_compare_labels_rows_by_configuration_and_samples_only_when_asked(capsys):
    path = str(EXAMPLES / "five_bar.yaml")
    arguments = ["compare", path, "--configuration", "fig6a_distal_aligned", "--at", "{}"]
    status, out, err = run(arguments + ["--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert [row["configuration"] for row in result["configurations"]] == ["fig6a_distal_aligned", "at1"]
    assert result["source"] == {"file": path, "configuration": "fig6a_distal_aligned"}
    assert result["configurations"][0]["park_kim"]["joint_values"]["J1"] != 0.0
    status, out, _ = run(arguments + ["--samples", "1", "--format", "json"], capsys)
    assert [row["configuration"] for row in json.loads(out)["configurations"]][-1] == "sample1"
    status, out, _ = run(arguments, capsys)
    assert f"source: file {path}, configuration fig6a_distal_aligned" in out
    assert "joint values (displacements from home):" in out and "\n  at1: J1 = " in out
    assert "\nfig6a_distal_aligned  actuator (nondegenerate)" in out and "\nhome " not in out


def test_compare_of_a_catalogue_entry_names_its_parameters(capsys):
    status, out, err = run(["compare", "slider-crank", "--configuration", "fig3c_dead_centre", "--outputs", "slide",
                            "--path", "1", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["source"]["catalogue"] == "slider-crank" and result["source"]["parameters"]["theta"] == 0.0
    labels = [row["configuration"] for row in result["configurations"]]
    assert "fig3c_dead_centre" in labels and "home" not in labels and not any(label.startswith("sample")
                                                                              for label in labels)


def test_ball_joints_may_be_outputs(capsys):
    """Outputs are joint coordinates (Gosselin & Angeles 1990, Section II), a ball joint's three included: they
    were checked as if actuated, and refused with 'an S joint cannot be actuated'."""
    status, out, err = run(["compare", "gough-stewart", "--outputs", "S1,S2", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["outputs"] == ["S1[x]", "S1[y]", "S1[z]", "S2[x]", "S2[y]", "S2[z]"]
    assert result["configurations"][0]["gosselin_angeles"]["n"] == 6


def test_a_path_that_cannot_leave_its_start_is_said_to(capsys):
    """At a C-space singularity (the five-bar's legs collinear, Chablat, Wenger & Angeles 1998 Fig. 1a) M is
    not continued: the path was the start alone, without a word."""
    status, out, err = run(["compare", "five-bar", "--configuration", "fig1a_collinear", "--path", "5",
                            "--format", "json"], capsys)
    assert status == 0, err
    assert len(json.loads(out)["configurations"]) == 1
    assert "--path: M could not be continued from fig1a_collinear" in err


def test_every_crossing_of_a_path_has_its_own_label(capsys):
    """Along the slider-crank's path the two actuator crossings (and the two end-effector ones) were all
    labelled 'crossing (actuator)': a JSON reader could not tell them apart. Each is named by the steps
    of the path it lies between."""
    status, out, err = run(["compare", "slider-crank", "--outputs", "slide", "--path", "200", "--path-step", "0.1",
                            "--format", "json"], capsys)
    assert status == 0, err
    labels = [row["configuration"] for row in json.loads(out)["configurations"]]
    crossings = [label for label in labels if label.startswith("crossing")]
    assert len(crossings) == 4 and len(set(labels)) == len(labels)
    for label in crossings:
        before, after = label.split()[1].split("…")
        assert int(after) == int(before) + 1
        assert labels.index(label) == labels.index(f"path{before}" if before != "+0" else "home") + 1
