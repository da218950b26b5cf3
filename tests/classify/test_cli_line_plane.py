"""``closedchain line-plane``: the JSON of the issue (``family``, ``cofactors``, ``B``, ``B_inf``,
``assembly_modes``), a rearrangement, a mechanism file and the catalogue entry, one-line errors (exit 2)."""

import json

import numpy as np
import pytest

from builders import command as run

QUARTIC_BASE = "0.1,0.2 1.3,-0.4 -0.7,1.1 0.9,1.6 -1.2,-0.8"
QUARTIC_PLATFORM = "0.3 -1.1 0.6 1.4 -0.2"
QUADRATIC_BASE = "0,0 2,1 -1,2 1.5,-1.5 -2,-1"
QUADRATIC_PLATFORM = "0 1 -0.5 0.75 -1"


def test_json_of_a_quartic_design_with_assembly_modes(capsys):
    status, out, err = run(["line-plane", "--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM,
                            "--legs", "2.1,2.6,2.3,2.2,2.8", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["family"] == "quartic" and len(result["cofactors"]) == 6
    assert max(abs(value) for value in result["cofactors"]) == pytest.approx(1.0)
    assert len(result["B"]) == 2 and len(result["B_inf"]) == 3
    modes = result["assembly_modes"]
    assert len(modes) == 8
    flags = [mode["real"] for mode in modes]
    assert flags == sorted(flags, reverse=True) and result["real_modes"] == sum(flags)
    for mode in modes:
        if mode["real"]:
            assert mode["residual"] < 1e-9 and len(mode["p"]) == 3
        else:
            assert set(mode["p"]) == {"real", "imag"}


def test_quadratic_design_has_b_and_b_inf_at_infinity_and_framework_agrees(capsys):
    status, out, err = run(["line-plane", "--base", QUADRATIC_BASE, "--platform", QUADRATIC_PLATFORM,
                            "--legs", "2.5495,3.831,3.4427,3.6277,2.7268", "--framework", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["family"] == "quadratic" and result["B"] is None and result["B_inf"] is None
    assert result["cofactors"][:2] == pytest.approx([1.0, -0.5]) and np.allclose(result["cofactors"][2:], 0)
    assert len(result["assembly_modes"]) == 4
    assert result["real_modes"] == 4 and result["routes_agree"] is True
    assert len(result["framework_modes"]) == 4


def test_move_base_keeps_the_cofactors_and_text_output(capsys):
    status, out, err = run(["line-plane", "--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM,
                            "--move-base", "2:0.5", "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    moved = result["rearranged"]
    assert moved["move"]["leg"] == 2 and moved["family"] == "quartic"
    sign = np.sign(moved["cofactors"][0] * result["cofactors"][0])
    assert np.allclose(sign * np.array(moved["cofactors"]), result["cofactors"], atol=1e-9)
    assert np.allclose(moved["B"], result["B"], atol=1e-9)
    status, out, err = run(["line-plane", "--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM,
                            "--move-base", "2:0.5"], capsys)
    assert status == 0 and "family    quartic" in out and "rearranged" in out


def test_catalogue_entry_and_mechanism_file(capsys, tmp_path):
    status, out, err = run(["line-plane", "5-spu", "--configuration", "eq35_vertical_tool", "--format", "json"],
                           capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["family"] == "quadratic" and result["singularity"]["singular"] is True
    path = tmp_path / "five_spu.yaml"
    status, _, err = run(["catalog", "5-spu", "--write", str(path)], capsys)
    assert status == 0, err
    status, out, err = run(["line-plane", str(path), "--format", "json"], capsys)
    assert status == 0, err
    result = json.loads(out)
    assert result["family"] == "quadratic" and result["singularity"]["singular"] is False


@pytest.mark.parametrize("arguments, option", [
    (["--base", "0,0 1,0 2,1 3,3", "--platform", "1 2 3 4"], "--base"),
    (["--base", QUARTIC_BASE, "--platform", "1 2 3 4"], "--platform"),
    (["--base", "0,0 1,1 0,0 2,0 0,2", "--platform", "1 2 1 3 4"], "--base"),
    (["--base", QUARTIC_BASE, "--platform", "0 1 inf 2 3"], "--platform"),
    (["--base", "0,0 1,nan 2,1 3,3 0,1", "--platform", "1 2 3 4 5"], "--base"),
    (["--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM, "--legs", "1,2,3"], "--legs"),
    (["--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM, "--move-platform", "1:2"], "--move-platform"),
    (["--base", QUARTIC_BASE, "--platform", QUARTIC_PLATFORM, "--move-base", "7:1"], "--move-base"),
    (["slider-crank"], "slider-crank"),
    # beyond ±1e12 (as in a mechanism file): a leg of 1e300 ended in an internal error, a base of 1e155 in
    # overflow warnings and a message blaming coinciding legs
    (["5-spu", "--legs", "1e300,2,2,2,2"], "--legs: expected numbers at most"),
    (["5-spu", "--move-base", "1:1e300"], "--move-base: expected numbers at most"),
    (["--base", "1e155,0.2 1.3,-0.4 -0.7,1.1 0.9,1.6 -1.2,-0.8", "--platform", QUARTIC_PLATFORM],
     "--base: expected numbers at most"),
])
def test_bad_input_exits_2_with_one_line_naming_the_option(arguments, option, capsys):
    status, out, err = run(["line-plane", *arguments], capsys)
    assert status == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and option in lines[0] and "Traceback" not in err
