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


def test_the_name_may_follow_the_grid_axes():
    """``--grid`` takes several words: a NAME after the axes is taken back from it (classify.cli._common)."""
    grid = ("X=-100:100:3", "Y=-100:100:3")
    first = run("conditioning", "3-prr", "--grid", *grid)
    assert first[0] == 0
    assert run("conditioning", "--grid", *grid, "3-prr") == first


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
    """Table 1 of Chablat et al. 2002, working mode 2: K̄ 0.460, B 0.709, Ā 0.511 (the grid of
    test_isoconditioning)."""
    step = 2 * math.pi / 60
    status, out, _ = run("conditioning", "3-prr", "--mode", "2", "--grid", "X=-295:295:60", "Y=-295:295:60",
                         f"PHI={-math.pi}:{math.pi - step}:60")
    assert status == 0
    result = json.loads(out)
    assert result["modes"][0]["global_index"] == pytest.approx(0.460, abs=0.001)
    assert result["modes"][0]["matrices"]["B"]["global_index"] == pytest.approx(0.709, abs=0.001)
    # the Ā column: Ā at the orientation of the best K̄ (test_table1_kappa_A_at_the_orientation_of_best_K; mode 2's
    # 0.507 is the one value of the table reproduced only to 0.005)
    assert result["modes"][0]["matrices"]["A"]["global_index_at_best_orientation"] == pytest.approx(0.511,
                                                                                                     abs=0.005)


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


def test_length_auto_on_a_derived_mechanism_finds_an_isotropic_posture_that_holds():
    """``--length auto`` on a mechanism with no closed form (the planar 3-RRR): κ(J̄) minimised over L and the
    posture (Chablat, Caro, Wenger & Angeles 2002 §3.2–3.4). The posture it reports, fed back with ``--at`` and
    the L found, gives that κ again; here it is isotropic (κ = 1)."""
    status, out, _ = run("conditioning", "planar-3rrr", "--length", "auto")
    assert status == 0
    found = json.loads(out)["characteristic_length"]
    assert found["method"] == "optimised" and found["value"] > 0
    isotropic = json.loads(out)["isotropic"]
    assert found["kappa"] == pytest.approx(1.0, abs=1e-6) and isotropic
    status, again, _ = run("conditioning", "planar-3rrr", "--at", json.dumps(isotropic[0]["displacements"]),
                           "--length", repr(found["value"]))
    assert status == 0
    assert json.loads(again)["kappa"]["B-1A"] == pytest.approx(found["kappa"], abs=1e-6)


def test_general_joint_grid_map():
    """Any mechanism: a grid of joint coordinates assembled on the working mode's branch, κ(J̄) and λ batched,
    the singular grid point counted (the five-bar at 1998 eq. 3c's stretched left leg, the grid's centre)."""
    from classify.isoconditioning import mechanism_map
    from mechanisms import catalogue, configuration

    status, out, _ = run("conditioning", "five-bar", "--configuration", "eq3c_left_leg_stretched", "--mode", "1",
                         "--grid", "A=-0.2:0.2:3", "B=-0.2:0.2:3", "--matrix", "lambda")
    assert status == 0
    result = json.loads(out)
    assert result["relation"] == "derived" and result["held"] == ["A", "B"]
    # the stretched left leg is a double root of its inverse kinematics: of the five-bar's four working modes
    # two remain, the right leg's two elbows (found by Gauss–Newton to ~√tolerance there, and merged)
    assert len(result["working_modes"]) == 2 and [entry["mode"] for entry in result["modes"]] == ["1"]
    entry = result["modes"][0]
    assert entry["grid_size"] == 9 and entry["unreachable_share"] == 0.0
    assert entry["classified_singular_share"] == pytest.approx(1 / 9)
    assert entry["max_kappa"] is None                       # κ = ∞ at the singular centre
    assert entry["matrices"]["A"]["global_index"] is None   # the derived A, B only with --matrix A|B
    item = catalogue.entry("five-bar")
    mechanism = item.assemble(dict(item.configurations["eq3c_left_leg_stretched"]))
    from classify.cli import _configurations as configurations
    from classify.cli._grid import parse_grid
    from classify.grid_continuation import assemble_grid, held_columns

    grid = parse_grid(["A=-0.2:0.2:3", "B=-0.2:0.2:3"], mechanism)
    start = configuration(mechanism, {}).point
    requested = np.zeros((grid.size, len(mechanism.coordinate_names)))
    requested[:, list(grid.columns)] = grid.values().reshape(grid.size, 2)
    points, reachable = assemble_grid(mechanism, start, configurations.points_of(mechanism, requested), grid.shape,
                                      held_columns(mechanism, grid))
    expected = mechanism_map(mechanism, points, reachable, grid.axes(), grid.names)
    assert entry["global_index"] == pytest.approx(expected.global_index("lambda"), rel=1e-9)


def test_hybrid_cartesian_grid_and_surfaces(tmp_path):
    """The hybrid (1998 §5) over X, Y, Z; the figure draws its isoconditioning surfaces."""
    from classify.isoconditioning import hybrid_map

    path = tmp_path / "hybrid.png"
    status, out, _ = run("conditioning", "hybrid", "--mode", "+-", "--grid", "X=-10:10:5", "Y=-4:10:5",
                         "Z=-10:10:5", "--out", str(path))
    assert status == 0 and path.stat().st_size > 0
    result = json.loads(out)
    assert [entry["mode"] for entry in result["modes"]] == ["+-"]
    axis = np.linspace(-10.0, 10.0, 5)
    expected = hybrid_map(axis, np.linspace(-4.0, 10.0, 5), axis, (1, -1))
    assert result["modes"][0]["global_index"] == pytest.approx(expected.global_index("B-1A"), rel=1e-12)


def test_general_cartesian_grid_from_a_file(tmp_path):
    """A mechanism file (no paper formula): the five-bar of Fig. 2's mode ++ over P = (x, y), its working mode
    followed by the general engine: the map of 1998 eqs. 3b-c in that mode (five_bar_cartesian_map)."""
    from classify.isoconditioning import five_bar_cartesian_map
    from mechanisms import catalogue
    from mechanisms.io import save

    item = catalogue.entry("five-bar")
    path = tmp_path / "five_bar.json"
    save(item.assemble(dict(item.configurations["fig2_working_mode_pp"])), str(path))
    status, out, _ = run("conditioning", str(path), "--mode", "1", "--grid", "X=-8:14:12", "Y=-12:12:13")
    assert status == 0
    result = json.loads(out)
    assert result["grid_kind"] == "cartesian" and result["held"] is None and len(result["working_modes"]) == 4
    expected = five_bar_cartesian_map(np.linspace(-8.0, 14.0, 12), np.linspace(-12.0, 12.0, 13), (1, 1))
    entry = result["modes"][0]
    assert entry["unreachable_share"] == pytest.approx(1.0 - np.count_nonzero(expected.reachable) / 156)
    assert entry["global_index"] == pytest.approx(expected.global_index("B-1A"), rel=1e-9)


@pytest.mark.parametrize("arguments,message", [
    (("3-prr", "--length", "-1"), "--length"),
    (("3-prr", "--grid", "X=1:2"), "--grid"),
    (("3-prr", "--grid", "X=0:1:2", "Z=0:1:2"), "--grid"),
    (("3-prr", "--grid", "X=0:1:2", "Y=0:1:2", "--mode", "9"), "--mode"),
    (("hybrid", "--grid", "X=0:1:2", "Y=0:1:2"), "--grid"),
    (("five-bar", "--grid", "A=0:0.1:2", "B=0:0.1:2", "--mode", "9"), "--mode"),
    (("five-bar", "--grid", "A=0:0.1:2", "--out", "one-axis.png"), "--out"),
    (("hybrid", "--grid", "X=0:1:2", "Y=0:1:2", "Z=0:1:2", "--length", "3"), "--length"),
    (("slider-crank",), "actuated"),
    (("five-bar", "--out", "x.txt"), "--out"),
    # a length far beyond the mechanism's size (the metric's L² overflowed: an internal error), or where no
    # characteristic length applies (it was ignored), and a working mode without maps (it was ignored)
    (("gough-stewart", "--length", "1e300"), "--length: expected a value from"),
    (("five-bar", "--length", "3"), "--length: the five-bar's outputs are positions"),
    (("five-bar", "--grid", "X=0:1:2", "Y=0:1:2", "--length", "3"), "--length: the five-bar's outputs"),
    (("spherical-3rrr", "--length", "2"), "--length: the end-effector's outputs are not positions"),
    (("five-bar", "--mode", "nan"), "--mode: applies to the maps of --grid"),
    # an orientation output: the working modes failed first, with a NumPy broadcast error as the message
    (("spherical-3rrr", "--grid", "X=0:0.1:2", "Y=0:0.1:2"), "--grid: a Cartesian grid needs a position or planar"),
])
def test_bad_input_exits_2_with_one_line(arguments, message, capsys):
    status, out, _ = run("conditioning", *arguments)
    err = capsys.readouterr().err
    assert status == 2 and out == ""
    assert message in err and err.count("\n") == 1


def test_a_cartesian_grid_that_does_not_fit_a_files_output_exits_2(tmp_path, capsys):
    """A general mechanism's Cartesian grid names exactly its output's axes: the five-bar's P is (x, y)."""
    from mechanisms import catalogue
    from mechanisms.io import save

    item = catalogue.entry("five-bar")
    path = tmp_path / "five_bar.json"
    save(item.assemble(dict(item.configurations["fig2_working_mode_pp"])), str(path))
    status, out, _ = run("conditioning", str(path), "--grid", "X=-8:14:3", "Y=-12:12:3", "Z=0:1:2")
    err = capsys.readouterr().err
    assert status == 2 and out == ""
    assert "--grid:" in err and "output is a position (x, y)" in err and err.count("\n") == 1


def test_a_param_outside_the_papers_relation_derives_it():
    """The papers' A and B are for the five-bar's own actuation (A, B) and equal legs: with another actuation
    the relation is derived from the mechanism (it used to print the paper's figures, the --param ignored)."""
    status, paper, _ = run("conditioning", "five-bar")
    assert status == 0 and json.loads(paper)["relation"] == "paper"
    status, out, _ = run("conditioning", "five-bar", "--param", "actuated=A,C")
    result = json.loads(out)
    assert status == 0 and result["relation"] == "derived"
    assert result["kappa"]["A"] != pytest.approx(json.loads(paper)["kappa"]["A"], rel=1e-3)


def test_a_serial_chain_is_conditioned_by_its_jacobian(tmp_path):
    """No loop, so DΦ has no rows (it ended in 'cannot reshape array of size 0'): a 2R arm of unit links with
    the elbow at 90° has Df = [[−1, −1], [1, 0]], whose condition number is (3 + √5)/2, and λ = κ²."""
    path = tmp_path / "serial.yaml"
    path.write_text("name: serial\nspace: planar\njoints:\n"
                    "  - {name: A, type: R, links: [ground, l1], point: [0, 0], actuated: true}\n"
                    "  - {name: B, type: R, links: [l1, l2], point: [1, 0], actuated: true}\n"
                    "end_effector: {link: l2, point: [1, 1], output: position}\n", encoding="utf-8")
    status, out, _ = run("conditioning", str(path))
    assert status == 0
    kappa = json.loads(out)["kappa"]
    assert kappa["A-1B"] == pytest.approx((3 + math.sqrt(5)) / 2, rel=1e-9)
    assert kappa["lambda"] == pytest.approx(kappa["A-1B"] ** 2, rel=1e-9)
