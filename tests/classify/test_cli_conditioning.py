"""``closedchain conditioning`` (Chablat, Caro, Wenger & Angeles 2002; Chablat, Wenger & Angeles 1998)."""

import io
import json
import math

import numpy as np
import pytest

from classify.cli import main
from classify.isoconditioning import three_prr_map
from mechanisms.catalogue.three_prr import WORKING_MODES


def run(*arguments, capsys=None):
    out = io.StringIO()
    status = main(list(arguments), out=out)
    return status, out.getvalue(), ""


def test_three_prr_at_fig4a():
    """Fig. 4a (γ = π/2): every κ = 1 and L = √2 r = 141.42 mm (§3.4)."""
    status, out, _ = run("conditioning", "3-prr")
    assert status == 0
    result = json.loads(out)
    assert result["characteristic_length"]["value"] == pytest.approx(math.sqrt(2) * 100.0, rel=1e-12)
    assert result["characteristic_length"]["method"] == "closed_form"
    assert set(result["kappa"]) == {"A", "B", "A-1B", "B-1A", "lambda"}
    for value in result["kappa"].values():
        assert value == pytest.approx(1.0, abs=1e-9)


def test_three_prr_grid_eight_modes(tmp_path):
    """The grid JSON: L, the isotropic posture of Fig. 4a, eight modes whose indices are the library's."""
    grid = ("X=-285:285:20", "Y=-285:285:20", "PHI=-3.141592653589793:2.8797932657906435:12")
    status, out, _ = run("conditioning", "3-prr", "--grid", *grid, "--out", str(tmp_path / "map.npz"))
    assert status == 0
    result = json.loads(out)
    assert result["characteristic_length"]["value"] == pytest.approx(141.42135623730951, rel=1e-12)
    assert [entry["mode"] for entry in result["modes"]] == [str(mode) for mode in range(1, 9)]
    postures = [entry["posture"] for entry in result["isotropic"]]
    assert any(np.allclose(posture, [0.0, 0.0, math.pi / 3], atol=1e-6) for posture in postures)
    xs = np.linspace(-285.0, 285.0, 20)
    expected = three_prr_map(xs, xs, WORKING_MODES[2], math.sqrt(2) * 100.0,
                             np.linspace(-math.pi, 2.8797932657906435, 12), mode="2")
    assert result["modes"][1]["global_index"] == pytest.approx(expected.global_index("B-1A"), rel=1e-12)
    assert result["modes"][1]["grid_size"] == 400
    arrays = np.load(tmp_path / "map.npz")
    np.testing.assert_array_equal(arrays["reachable_2"], expected.reachable)


def test_three_prr_grid_table1_mode2():
    """Table 1 of Chablat et al. 2002, working mode 2, K̄: 0.460 (the grid of test_isoconditioning)."""
    step = 2 * math.pi / 60
    status, out, _ = run("conditioning", "3-prr", "--mode", "2", "--grid", "X=-295:295:60", "Y=-295:295:60",
                         f"PHI={-math.pi}:{math.pi - step}:60")
    assert status == 0
    result = json.loads(out)
    assert result["modes"][0]["global_index"] == pytest.approx(0.460, abs=0.005)
    assert result["modes"][0]["matrices"]["B"]["global_index"] == pytest.approx(0.709, abs=0.005)


def test_five_bar_single_and_figure(tmp_path):
    status, out, _ = run("conditioning", "five-bar", "--configuration", "fig2_working_mode_pp", "--format", "text")
    assert status == 0 and "κ(A)" in out
    path = tmp_path / "five_bar.svg"
    status, out, _ = run("conditioning", "five-bar", "--grid", "X=-8:14:12", "Y=-12:12:12", "--matrix", "A",
                         "--out", str(path))
    assert status == 0 and path.stat().st_size > 0
    assert [entry["mode"] for entry in json.loads(out)["modes"]] == ["++", "+-", "-+", "--"]


def test_derived_mechanism_reports_its_normalisation():
    status, out, _ = run("conditioning", "planar-3rrr", "--length", "0.5")
    assert status == 0
    result = json.loads(out)
    assert result["relation"] == "derived" and "orthonormal" in result["normalisation"]
    assert result["kappa"]["lambda"] == pytest.approx(result["kappa"]["A-1B"] ** 2, rel=1e-8)


@pytest.mark.parametrize("arguments,message", [
    (("3-prr", "--length", "-1"), "--length"),
    (("3-prr", "--grid", "X=1:2"), "--grid"),
    (("3-prr", "--grid", "X=0:1:2", "Z=0:1:2"), "--grid"),
    (("3-prr", "--grid", "X=0:1:2", "Y=0:1:2", "--mode", "9"), "--mode"),
    (("hybrid", "--grid", "X=0:1:2", "Y=0:1:2"), "--grid"),
    (("slider-crank",), "actuated"),
    (("five-bar", "--out", "x.txt"), "--out"),
])
def test_bad_input_exits_2_with_one_line(arguments, message, capsys):
    status, out, _ = run("conditioning", *arguments)
    err = capsys.readouterr().err
    assert status == 2 and out == ""
    assert message in err and err.count("\n") == 1
