"""``closedchain loci``: the JSON contract, and each configuration given back as ``--at`` reproduces the verdict
through ``closedchain classify``."""

import json
import re

import pytest

from builders import command_streams as run


@pytest.fixture(scope="module")
def five_bar_loci(tmp_path_factory):
    path = tmp_path_factory.mktemp("loci") / "map.png"
    status, out, err = run(["loci", "five-bar", "--grid", "A=-3.1:3.1:7", "B=-3.1:3.1:7",
                            "--coordinates", "end-effector", "--format", "json", "--out", str(path)])
    assert status == 0, err
    return json.loads(out), path


def test_json_contract(five_bar_loci):
    document, path = five_bar_loci
    assert path.stat().st_size > 1000
    assert document["coordinates"] == ["x", "y"]
    kinds = {piece["kind"] for piece in document["pieces"]}
    assert {"actuator", "end_effector"} <= kinds
    for piece in document["pieces"]:
        assert len(piece["configurations"]) == len(piece["coordinates"])
        assert set(piece["configurations"][0]) == {"A", "C", "P", "D", "B"}
    coverage = document["coverage"]
    assert coverage["grid"]["A"][2] == 7 and coverage["pieces"]["actuator"] >= 1


def test_configurations_reproduce_the_verdict_through_classify(five_bar_loci):
    document, _ = five_bar_loci
    for piece in document["pieces"][:3]:
        for configuration in (piece["configurations"][0], piece["configurations"][len(piece["configurations"]) // 2]):
            status, out, err = run(["classify", "five-bar", "--at", json.dumps(configuration), "--format", "json"])
            assert status == 0, err
            assert piece["kind"] in json.loads(out)["kinds"]


def test_slider_crank_text_and_branches():
    status, out, err = run(["loci", "slider-crank", "--configuration", "fig3a_self_intersection"])
    assert status == 0, err
    assert "branches of M: 2 (2 closed)" in out and "cspace: 2 piece(s)" in out


def test_loci_refuses_bad_input(tmp_path):
    status, _, err = run(["loci", "gough-stewart"])
    assert status == 2 and "1-, 2- and 3-dof" in err
    status, _, err = run(["loci", "five-bar", "--section", "A=0:1:3"])
    assert status == 2 and "--section" in err and "3-dof" in err
    status, _, err = run(["loci", "hybrid", "--grid", "A=0:1:5", "B=0:1:5", "--section", "A=0:1:3"])
    assert status == 2 and "--section" in err
    status, _, err = run(["loci", "hybrid", "--section", "base=0:1:1"])
    assert status == 2 and "--section 'base=0:1:1': n = 1" in err
    status, _, err = run(["loci", "five-bar", "--coordinates", "Q"])
    assert status == 2 and "--coordinates" in err
    status, _, err = run(["loci", "five-bar", "--grid", "A=0:1:5"])
    assert status == 2 and "--grid" in err
    status, _, err = run(["loci", "--grid", "A=0:1:5", "B=0:1:5"])
    assert status == 2 and "required: FILE|NAME" in err
    status, _, err = run(["loci", "five-bar", "--kinds", "nothing"])
    assert status == 2 and "--kinds" in err
    status, _, err = run(["loci", "five-bar", "--out", str(tmp_path / "x.csv")])
    assert status == 2 and "--out" in err
    status, _, err = run(["loci", "slider-crank", "--branches", "3"])  # was ignored on 1 dof
    assert status == 2 and "--branches: applies to a 2-dof mechanism's grid; slider-crank has 1 dof" in err


@pytest.fixture(scope="module")
def hybrid_loci(tmp_path_factory):
    path = tmp_path_factory.mktemp("loci") / "sections.svg"
    status, out, err = run(["loci", "hybrid", "--grid", "A=-3.1:3.1:8", "B=-3.1:3.1:8", "--section", "base=0.5:0.5:1",
                            "--kinds", "actuator,end_effector", "--format", "json", "--out", str(path)])
    assert status == 0, err
    return json.loads(out), path


def test_three_dof_json_has_sections(hybrid_loci):
    document, path = hybrid_loci
    assert path.stat().st_size > 1000
    assert document["coordinates"] == ["A", "B", "base"]
    assert document["coverage"]["section"] == {"base": [0.5, 0.5, 1]}
    assert [entry["value"] for entry in document["coverage"]["sections"]] == [0.5]
    assert {piece["kind"] for piece in document["pieces"]} == {"actuator", "end_effector"}
    for piece in document["pieces"]:
        assert piece["section"] == 0.5
        assert all(abs(configuration["base"] - 0.5) < 1e-9 for configuration in piece["configurations"])
        assert all(abs(values[2] - 0.5) < 1e-9 for values in piece["coordinates"])


def test_three_dof_configurations_are_singular_through_classify(hybrid_loci):
    """Chablat, Wenger & Angeles 1998: the hybrid's loci (eqs. 24, 30) given back as --at are singular."""
    document, _ = hybrid_loci
    for kind in ("actuator", "end_effector"):
        piece = next(piece for piece in document["pieces"] if piece["kind"] == kind)
        status, out, err = run(["classify", "hybrid", "--at", json.dumps(piece["configurations"][0]),
                                "--format", "json"])
        assert status == 0, err
        verdict = json.loads(out)
        assert verdict["singular"] and kind in verdict["kinds"]


def test_three_dof_text_names_the_sections():
    status, out, err = run(["loci", "hybrid", "--grid", "A=-3.1:3.1:5", "B=-3.1:3.1:5", "--section", "base=0:1:2",
                            "--kinds", "actuator"])
    assert status == 0, err
    assert "(3 dof)" in out and "in 2 section(s) base from 0 to 1" in out and "actuator:" in out


def test_whole_branch_in_json_and_text():
    """Park & Kim 1999 Fig. 3a (crank = coupler): the branch with the slider at the crank's pivot is one
    end-effector piece marked whole_branch, with its margin in the coverage and the text."""
    status, out, err = run(["loci", "slider-crank", "--configuration", "fig3a_self_intersection",
                            "--kinds", "actuator,end_effector", "--format", "json"])
    assert status == 0, err
    document = json.loads(out)
    whole = [piece for piece in document["pieces"] if piece["whole_branch"]]
    assert len(whole) == 1 and whole[0]["kind"] == "end_effector" and whole[0]["closed"]
    (record,) = document["coverage"]["whole_branch"]
    assert record["largest"] < record["tolerance"]
    status, out, err = run(["loci", "slider-crank", "--configuration", "fig3a_self_intersection",
                            "--kinds", "actuator,end_effector"])
    assert status == 0 and "1 a whole branch of M" in out and "singular along the whole branch" in out
    # the text counts branches from 1, the JSON from 0: the line says which of the JSON's it is
    number = re.search(r"singular along the whole branch (\d+) \(the JSON's branches\[(\d+)\]", out).groups()
    assert int(number[0]) == record["branch"] + 1 and int(number[1]) == record["branch"]


def test_singular_start_and_assembly_branches_in_the_text():
    """From the five-bar's actuator singularity (Chablat, Wenger & Angeles 1998 eq. 9) the text says the grid was
    continued from a regular neighbour; --branches 2 assembles a second branch; --branches 0 is refused."""
    status, out, err = run(["loci", "five-bar", "--configuration", "eq9_distal_aligned", "--grid", "A=-3:3:5",
                            "B=-3:3:5", "--kinds", "actuator", "--branches", "2"])
    assert status == 0, err
    assert "continued from a regular neighbour on M" in out
    assert "assembly branches of the grid: 2 (of at most 2)" in out
    status, _, err = run(["loci", "five-bar", "--branches", "0"])
    assert status == 2 and "--branches" in err


def test_a_sparse_grid_suggests_a_finer_one_or_more_branches():
    """The degenerate five-bar of Chablat, Wenger & Angeles 1998 Fig. 6a (base = proximal + distal): its
    5 × 3 grid over a turn of each actuator reaches 1 point on the start's assembly branch (6 × 6: 12,
    10 × 10: 39, from the start's regular neighbour), so the text says how to seed more; a dense enough grid
    says nothing."""
    grid = ["--grid", "A=-3.14159:3.14159:5", "B=-3.14159:3.14159:3"]
    status, out, err = run(["loci", "five-bar", "--configuration", "fig6a_distal_aligned", *grid,
                            "--kinds", "actuator"])
    assert status == 0, err
    assert "1 of 15 points reached" in out and "a finer --grid or --branches 2 may seed more loci" in out
    status, out, err = run(["loci", "five-bar", "--configuration", "fig6a_distal_aligned", "--kinds", "actuator"])
    assert status == 0, err
    assert "points reached" in out and "may seed more loci" not in out


def test_the_command_labels_its_axes_with_units(monkeypatch, tmp_path):
    """The report's loci pictures said ``A − A₀ (rad)``; the command's own figure said ``A``."""
    import classify.cli.draw_command as draw_command

    drawn = []
    monkeypatch.setattr(draw_command, "write_figure", lambda figure, path: drawn.append(figure))
    status, _, err = run(["loci", "five-bar", "--grid", "A=-3.1:3.1:7", "B=-3.1:3.1:7", "--format", "json",
                          "--out", str(tmp_path / "loci.png")])
    assert status == 0, err
    axes = drawn[0].axes[0]
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("A − A₀ (rad)", "B − B₀ (rad)")
