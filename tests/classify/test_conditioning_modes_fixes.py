"""Fixes of the conditioning maps' working modes and singularity curves (Chablat, Wenger & Angeles 1998 §3.3-3.4,
eqs. 3b-c, 9, 22b): a grid point or a start on a serial singularity, the merged modes' multiplicity, the red
curve 1/κ = 0 along the whole parallel-singularity locus, the hybrid's mode labels, a message."""

import io
import json

import numpy as np
import pytest

from classify.cli import main
from classify import inverse_kinematics_branches as branches
from classify.inverse_kinematics_branches import (cartesian_outputs, follow_working_mode, mechanism_working_modes,
                                                  output_targets)
from mechanisms import catalogue, configuration, link_pose


def _five_bar(name, **parameters):
    item = catalogue.entry("five-bar")
    mechanism = item.build(**dict(item.configurations[name]), **parameters)
    return mechanism, configuration(mechanism, {}).point


def _paper_patterns(mechanism, points):
    """The 1998 eq. 3c sign pattern (signs of B's diagonal: the legs' elbows) of each configuration; None
    within 0.04 of a serial singularity."""
    homogeneous = {name: np.append(mechanism.joint(name).point, 1.0) for name in "ACPDB"}

    def cross(u, v):
        return u[0] * v[1] - u[1] * v[0]

    patterns = set()
    for point in points:
        c, p, d = ((link_pose(mechanism, link, point) @ homogeneous[name])[:2]
                   for name, link in (("C", "proximal_left"), ("P", "distal_left"), ("D", "proximal_right")))
        left = cross(c - homogeneous["A"][:2], p - c)
        right = cross(d - homogeneous["B"][:2], p - d)
        if min(abs(left), abs(right)) >= 0.04:
            patterns.add(("+" if left > 0 else "-") + ("+" if right > 0 else "-"))
    return patterns


def test_a_grid_point_on_a_serial_singularity_does_not_mix_two_working_modes():
    """The docs' grid X=-8:14:45 Y=-12:12:49 puts grid points on the folds |PA|, |PB| = L1 ± L2 (e.g. P = (3, 0)),
    where det(Df T)'s sign is rounding: each map must still hold one of the paper's four modes (it held ++ and
    -+ in one map)."""
    mechanism, point = _five_bar("fig2_working_mode_pp")
    modes = mechanism_working_modes(mechanism, point)
    assert len(modes) == 4
    axes = (np.linspace(-8, 14, 45), np.linspace(-12, 12, 49))
    targets = output_targets(mechanism, cartesian_outputs(mechanism, point, ("x", "y"), axes))
    found = []
    for mode in modes:
        points, reached = follow_working_mode(mechanism, mode.point, targets, (45, 49))
        patterns = _paper_patterns(mechanism, points[reached])
        assert len(patterns) == 1, (mode.label, patterns)
        assert reached.sum() > 1200
        found.append(patterns.pop())
    assert sorted(found) == ["++", "+-", "-+", "--"]


def test_a_start_on_a_serial_singularity_maps_its_mode_whatever_the_rounding():
    """With the left leg stretched both inverse-kinematics branches are double roots (1998 §3.3: two working
    modes meet): each is reported with multiplicity 2, and each one's map starts off the singular point (one
    exactly singular reached 0 of 81 points, the other, 1.3e-8 off, 79)."""
    mechanism, point = _five_bar("eq3c_left_leg_stretched", end_effector="distal_right")
    modes = mechanism_working_modes(mechanism, point)
    assert len(modes) == 2
    axes = (np.linspace(2, 6, 9), np.linspace(8, 12, 9))
    targets = output_targets(mechanism, cartesian_outputs(mechanism, point, ("x", "y"), axes))
    for mode in modes:
        assert mode.multiplicity == 2 and mode.serial_margin <= branches.SERIAL_TOLERANCE
        assert mode.to_dict()["multiplicity"] == 2
        points, reached = follow_working_mode(mechanism, mode.point, targets, (9, 9))
        assert reached.sum() >= 70, (mode.label, reached.sum())
        assert len(_paper_patterns(mechanism, points[reached])) == 1


def test_regular_modes_have_multiplicity_one():
    mechanism, point = _five_bar("fig2_working_mode_pp")
    modes = mechanism_working_modes(mechanism, point, count=24)
    assert [mode.multiplicity for mode in modes] == [1, 1, 1, 1]
    assert all(mode.serial_margin > 1e-2 for mode in modes)


def test_cli_json_reports_the_multiplicity():
    out = io.StringIO()
    status = main(["conditioning", "five-bar", "--configuration", "eq3c_left_leg_stretched", "--param",
                   "end_effector=distal_right", "--grid", "X=2:6:5", "Y=8:12:5"], out=out)
    assert status == 0
    result = json.loads(out.getvalue())
    assert [entry["multiplicity"] for entry in result["working_modes"]] == [2, 2]
    # both modes are mapped from a regular neighbour of the singular start: most of the 25 points reached
    assert all(entry["grid_size"] == 25 and entry["unreachable_share"] < 0.5 for entry in result["modes"])


def _red_vertices(figure):
    axes = [axes for axes in figure.axes if axes.get_label() != "<colorbar>"][0]
    paths = [path.vertices for child in axes.get_children() if getattr(child, "get_gid", lambda: None)()
             == "singularity" for path in child.get_paths()]
    return np.concatenate(paths) if paths else np.zeros((0, 2))


@pytest.mark.parametrize("matrix", ["A", "B-1A"])
def test_the_singularity_curve_follows_the_parallel_singularity_locus(matrix):
    """1998 eq. 9: Ā is singular where θ3 − θ4 = kπ; the red curve must pass within one grid step of (nearly)
    every grid edge the locus crosses (a contour of 1/κ ≥ 0 at 1e-3 drew 14 of 252)."""
    from classify.figures.conditioning import isoconditioning_figure
    from classify.isoconditioning import five_bar_cartesian_map

    xs, ys = np.linspace(-8, 14, 120), np.linspace(-12, 12, 120)
    step = xs[1] - xs[0]
    conditioning_map = five_bar_cartesian_map(xs, ys, (1, -1), mode="+-")
    red = _red_vertices(isoconditioning_figure([conditioning_map], matrix))
    grid = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1)
    angles, reachable = conditioning_map.extra["angles"], conditioning_map.reachable
    side = np.sign(np.sin(angles[..., 2] - angles[..., 3]))
    middles = np.concatenate([
        ((grid[1:] + grid[:-1]) / 2)[reachable[1:] & reachable[:-1] & (side[1:] != side[:-1])],
        ((grid[:, 1:] + grid[:, :-1]) / 2)[reachable[:, 1:] & reachable[:, :-1] & (side[:, 1:] != side[:, :-1])]])
    assert len(middles) > 100
    near = [len(red) and np.min(np.hypot(*(red - middle).T)) <= step for middle in middles]
    assert np.mean(near) >= 0.9


def test_hybrid_mode_labels_are_documented_as_the_code_computes_them():
    """1998 eq. 22b: B's last two entries are L1L2 sin(θ2 − θ4), L1L2 sin(θ3 − θ5); the label (s, t) is the
    signs of sin(θ4 − θ2), sin(θ5 − θ3), their opposites."""
    from classify.conditioning_matrices import hybrid_matrices
    from classify.isoconditioning import hybrid_map

    for signs in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        angles = hybrid_map([4.0], [3.0], [0.0], signs).extra["angles"][0, 0, 0]
        inverse = hybrid_matrices(angles)[1]
        assert tuple(-np.sign(np.diagonal(inverse)[1:]).astype(int)) == signs
    text = " ".join(hybrid_map.__doc__.split())
    assert "sin(θ4 − θ2), sin(θ5 − θ3)" in text and "B's last two entries" not in text.split("opposite")[0]
    assert "sin(θ2 − θ4)" in text and "sin(θ3 − θ5)" in text


def test_a_cartesian_grid_without_end_effector_says_so():
    out, error = io.StringIO(), io.StringIO()
    import contextlib

    with contextlib.redirect_stderr(error):
        status = main(["conditioning", "hybrid", "--param", "end_effector=false", "--grid", "X=0:1:2", "Y=0:1:2",
                       "Z=0:1:2"], out=out)
    assert status == 2
    message = error.getvalue() + out.getvalue()
    assert "no end-effector" in message and "None" not in message
    assert len(message.strip().splitlines()) == 1
