"""Fixes from a new-user audit: the default grid and sections of a locus over slide coordinates, the hint of a
sparse grid, the message for a misspelt link and the ``--at`` message for a configuration that does not close."""

import json

import numpy as np
import pytest

from builders import command_streams as run

#: the audit's planar 3-RPR (P joints actuated): base A_i, platform points B_i about O turned 0.5 rad; legs ~1.9
#: long, characteristic length ~4.3
_BASE = np.array([[0.0, 0.0], [4.0, 0.0], [1.5, 3.5]])
_CENTRE = np.array([2.0, 1.3])


def _three_rpr_text():
    turn = np.array([[np.cos(0.5), -np.sin(0.5)], [np.sin(0.5), np.cos(0.5)]])
    joints, platform = [], []
    for index, base in enumerate(_BASE, start=1):
        ray = (base - _CENTRE) / np.linalg.norm(base - _CENTRE)
        point = _CENTRE + turn @ (0.6 * ray)
        platform.append(point)
        joints += [{"name": f"A{index}", "type": "R", "links": ["ground", f"leg{index}a"], "point": base.tolist()},
                   {"name": f"P{index}", "type": "P", "links": [f"leg{index}a", f"leg{index}b"],
                    "axis": (point - base).tolist(), "actuated": True},
                   {"name": f"B{index}", "type": "R", "links": [f"leg{index}b", "platform"], "point": point.tolist()}]
    document = {"name": "3-RPR regular", "space": "planar", "joints": joints,
                "end_effector": {"link": "platform", "point": np.mean(platform, axis=0).tolist(), "output": "pose"}}
    return json.dumps(document)


FOUR_BAR = """name: four-bar
space: planar
joints:
  - {name: A, type: R, links: [ground, crank], point: [0, 0], actuated: true}
  - {name: B, type: R, links: [crank, coupler], point: [0, 1]}
  - {name: C, type: R, links: [coupler, rocker], point: [2, 1.5]}
  - {name: D, type: R, links: [rocker, ground], point: [2.5, 0]}
"""


@pytest.fixture(scope="module")
def three_rpr(tmp_path_factory):
    from mechanisms import configuration
    from mechanisms.io import read

    path = tmp_path_factory.mktemp("rpr") / "rpr_regular.json"
    path.write_text(_three_rpr_text())
    mechanism = read(str(path)).mechanism
    return path, mechanism, configuration(mechanism, {}).point


def test_default_sections_over_a_slide_include_the_start(three_rpr):
    """The default sections of P1 were ±2.87 and ±8.60 (±2 characteristic lengths in 4 values): none at the
    start's value 0, so the continuation from the start reached 1 of 2304 grid points."""
    from classify.loci_grids import _grid_arguments

    _, mechanism, start = three_rpr
    columns, ranges, counts = _grid_arguments(mechanism, start, None, None, (24, 24), 3)
    assert [mechanism.coordinate_names[column] for column in columns] == ["P2", "P3", "P1"]
    sections = np.linspace(ranges[2][0], ranges[2][1], counts[2])
    assert np.min(np.abs(sections)) < 1e-12  # the start's value (a displacement of 0 from the home)
    length = mechanism.characteristic_length
    for low, high in ranges:  # a span of one characteristic length around the start: legs are ~1.9 long
        assert -0.5 * length - 1e-12 <= low < 0 < high <= 0.5 * length + 1e-12


@pytest.mark.parametrize("count, expected", [(2, [-np.pi, 0.0]), (4, [-np.pi, -np.pi / 2, 0.0, np.pi / 2]),
                                             (5, [-0.8 * np.pi, -0.4 * np.pi, 0.0, 0.4 * np.pi, 0.8 * np.pi])])
def test_default_angle_sections_include_the_start(count, expected):
    """Angle sections evenly around a turn, the start's value among them for any count (an odd count missed it:
    5 sections were at −π, −3π/5, −π/5, π/5, 3π/5)."""
    from classify.loci_grids import _grid_arguments
    from mechanisms import configuration
    from tests.builders import catalogue_mechanism

    mechanism = catalogue_mechanism("hybrid", "regular")
    start = configuration(mechanism, {}).point
    columns, ranges, counts = _grid_arguments(mechanism, start, None, None, (6, 6, count), 3)
    home = configuration(mechanism, {}).point
    assert np.allclose(start, home)
    np.testing.assert_allclose(np.linspace(ranges[2][0], ranges[2][1], counts[2]), expected, atol=1e-12)


def test_default_grid_of_a_slide_actuated_mechanism_is_reached(three_rpr):
    """``closedchain loci rpr_regular.yaml``: 1 of 2304 grid points reached with the old defaults; the default grid
    (as ``closedchain loci`` assembles it) now reaches a fair share of its points, and of the start's section's
    (the section P1 = −½ characteristic length, the leg 1.9 long shortened by 2.15, reaches none)."""
    from classify.loci_grids import _assembled_grid, _grid_arguments

    _, mechanism, start = three_rpr
    columns, ranges, counts = _grid_arguments(mechanism, start, None, None, (24, 24), 3)
    _, reached, _, _ = _assembled_grid(mechanism, start, columns[2:] + columns[:2], ranges[2:] + ranges[:2],
                                       counts[2:] + counts[:2])
    per_section = reached[0].reshape(counts[2], -1).sum(axis=1)
    assert reached[0].sum() >= 0.1 * reached[0].size and per_section[counts[2] // 2] >= 0.1 * 24 * 24
    assert (per_section[1:] > 0).all()


def test_sparse_hint_says_a_slide_range_may_be_too_wide(three_rpr):
    """A grid over slides wider than the mechanism reaches: the hint said only "a finer --grid or --branches 2"
    (finer does not help, and --branches applies to 2 dof only); it now says the range may be too wide."""
    path, _, _ = three_rpr
    status, out, err = run(["loci", str(path), "--kinds", "actuator", "--grid", "P2=-8:8:6", "P3=-8:8:6",
                            "--section", "P1=0:0:1"])
    assert status == 0, err
    assert "the range of P2, P3 may be wider than the mechanism reaches" in out and "narrower" in out
    assert "--branches" not in out  # 3 dof


def test_misspelt_link_message_names_both_links(tmp_path):
    """``rockr`` in joint D, ``rocker`` in joint C: the known links listed left out ``rocker``."""
    path = tmp_path / "e8.yaml"
    path.write_text(FOUR_BAR.replace("[rocker, ground]", "[rockr, ground]"))
    status, out, err = run(["classify", str(path)])
    assert status == 2 and "Traceback" not in err
    assert "'rocker'" in err and "'rockr'" in err
    known = err.split("known links:")[1]
    assert "rocker" in known.replace("rockr", "") and "rockr" in known


def test_at_that_does_not_close_points_to_assemble(tmp_path):
    """``--at '{"A": 0.2}'`` does not close: the message offered only --project (which moves A); --assemble holds
    the value given."""
    path = tmp_path / "four_bar.yaml"
    path.write_text(FOUR_BAR)
    status, out, err = run(["classify", str(path), "--at", '{"A": 0.2}'])
    assert status == 2 and "does not close the loops" in err
    assert "--assemble" in err and "--project" in err
    status, out, err = run(["classify", str(path), "--at", '{"A": 0.2}', "--assemble", "--format", "json"])
    assert status == 0, err
    assert json.loads(out)["assembly"]["held"] == {"A": 0.2}


def test_a_half_turn_is_named_not_called_a_residual_above_the_tolerance(capsys):
    """A review found ``closedchain classify slider_crank.yaml --at '{"crank": π}'`` refused with "does not
    close the loops (|Φ| = 1.22e-16 > 1e-09)": the residual below the tolerance it was said to exceed. The loop
    closes there only at a half-turn (Φ's rotation rows vanish at π too), and the message says so."""
    import math
    from pathlib import Path

    from classify.cli import main

    example = str(Path(__file__).resolve().parents[2] / "examples" / "slider_crank.yaml")
    status = main(["classify", example, "--at", json.dumps({"crank": math.pi})])
    err = capsys.readouterr().err
    assert status == 2 and "a loop closes only at a half-turn" in err and "> 1e-09" not in err
    assert len(err.strip().splitlines()) == 1


def test_a_loop_merely_turned_far_is_no_half_turn():
    """A review found every non-closing point whose loop turns past about 90° called a half-turn ("Φ's rotation
    rows vanish there too") with ‖Φ‖ = 0.6: a half-turn is Φ = 0 at a loop turned by π, nothing else."""
    import math
    from pathlib import Path

    from mechanisms import from_displacements, load
    from mechanisms.kinematics import closure_failure

    mechanism = load(str(Path(__file__).resolve().parents[2] / "examples" / "slider_crank.yaml"))
    for crank in (0.3, 1.6, 2.5, 3.0):
        kind, text = closure_failure(mechanism, from_displacements(mechanism, {"crank": crank}, "--at"))
        assert kind == "residual" and "does not close the loops" in text, crank
    assert closure_failure(mechanism, from_displacements(mechanism, {"crank": math.pi}, "--at"))[0] == "half-turn"
