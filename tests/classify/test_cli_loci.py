"""``closedchain loci``: the JSON contract, and each configuration given back as ``--at`` reproduces the verdict
through ``closedchain classify``."""

import contextlib
import io
import json

import pytest

from classify.cli import main


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(argv, out=out)
    return status, out.getvalue(), err.getvalue()


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
    status, _, err = run(["loci", "planar-3rrr"])
    assert status == 2 and "1- and 2-dof" in err
    status, _, err = run(["loci", "five-bar", "--coordinates", "Q"])
    assert status == 2 and "--coordinates" in err
    status, _, err = run(["loci", "five-bar", "--grid", "A=0:1:5"])
    assert status == 2 and "--grid" in err
    status, _, err = run(["loci", "five-bar", "--kinds", "nothing"])
    assert status == 2 and "--kinds" in err
    status, _, err = run(["loci", "five-bar", "--out", str(tmp_path / "x.csv")])
    assert status == 2 and "--out" in err
