"""Isoconditioning maps, global indices, contours and figures (Chablat, Caro, Wenger & Angeles 2002 §3.6,
Table 1; Chablat, Wenger & Angeles 1998 §3.4, §5)."""

import math

import numpy as np
import pytest

from classify.conditioning import singular_value_ratio
from classify.conditioning_matrices import five_bar_inverse_kinematics, five_bar_matrices
from classify.isoconditioning import (
    contours, five_bar_cartesian_map, five_bar_joint_map, hybrid_plane_map, three_prr_map,
)
from mechanisms.catalogue.three_prr import WORKING_MODES

ROOT_TWO_R = math.sqrt(2.0) * 100.0
#: Table 1 grid: cell centres of [−300, 300]² mm (60 × 60) and 60 orientations; finer grids (200 × 200 × 360)
#: move the indices by less than 0.004 (docs/conditioning.rst)
TABLE_GRID = -300.0 + 10.0 * (np.arange(60) + 0.5)
TABLE_ORIENTATIONS = np.linspace(-math.pi, math.pi, 60, endpoint=False)
#: how far a published index (3 decimals) may be from ours on that grid: the B and K̄ columns converge to the
#: published values within their rounding on fine grids (docs/conditioning.rst), and are within it here
TABLE_TOLERANCE = 0.001
#: the one column reproduced less closely: Ā of mode 2 (0.507 here, 0.506 on 200 × 200 × 360, published 0.511)
MODE_2_A_TOLERANCE = 0.005


@pytest.fixture(scope="module")
def table_maps():
    return {mode: three_prr_map(TABLE_GRID, TABLE_GRID, WORKING_MODES[mode], ROOT_TWO_R, TABLE_ORIENTATIONS,
                                mode=str(mode)) for mode in (1, 2)}


@pytest.mark.parametrize("mode,published", [(1, 0.709), (2, 0.709)])
def test_table1_kappa_B(table_maps, mode, published):
    """Chablat et al. 2002 Table 1, κ(B) column: the mean over the Cartesian workspace of 1/κ with
    κ = σ_l/σ_s (eq. 5). (The paper's √(β_max/β_min) of §3.6 gives about 0.83: it is not the one tabulated.)"""
    assert table_maps[mode].global_index("B") == pytest.approx(published, abs=TABLE_TOLERANCE)


@pytest.mark.parametrize("mode,published", [(1, 0.329), (2, 0.460)])
def test_table1_kappa_K(table_maps, mode, published):
    """Table 1, κ(K̄) column: mean over positions of the best 1/κ(K̄) over the orientation (§3.6), L = √2 r."""
    assert table_maps[mode].global_index("B-1A") == pytest.approx(published, abs=TABLE_TOLERANCE)


@pytest.mark.xfail(strict=True, reason="Table 1's κ(Ā) column (0.354, 0.511) is not the average that "
                                       "reproduces the B and K̄ columns (each matrix at its own best "
                                       "orientation): that gives 0.364 and 0.519 on this grid (0.3745 and 0.524 "
                                       "on 200 × 200 × 360), 0.02 and 0.013 above the published values")
@pytest.mark.parametrize("mode,published", [(1, 0.354), (2, 0.511)])
def test_table1_kappa_A(table_maps, mode, published):
    assert table_maps[mode].global_index("A") == pytest.approx(published, abs=MODE_2_A_TOLERANCE)


@pytest.mark.parametrize("mode,published,tolerance", [(1, 0.354, TABLE_TOLERANCE), (2, 0.511, MODE_2_A_TOLERANCE)])
def test_table1_kappa_A_at_the_orientation_of_best_K(table_maps, mode, published, tolerance):
    """Table 1, κ(Ā) column: the mean of 1/κ(Ā) at the orientation that optimises κ(K̄) at each position
    (§3.6 "the optimum conditioning according to the orientation"): 0.354 and 0.507 on this grid, 0.355 and
    0.506 on 200 × 200 × 360 — mode 1 to 0.001, mode 2 to 0.005 of the published values."""
    assert table_maps[mode].index_at_best_orientation("A") == pytest.approx(published, abs=tolerance)


def test_table1_columns_need_different_orientations(table_maps):
    """No one orientation per position gives every column: at K̄'s best orientation B's index is 0.68, not
    Table 1's 0.709 (which is B at its own best)."""
    assert table_maps[1].index_at_best_orientation("B") < 0.709 - 0.02
    assert table_maps[1].index_at_best_orientation("B-1A") == pytest.approx(table_maps[1].global_index("B-1A"),
                                                                             rel=1e-12)


def test_table1_B_identical_in_both_modes(table_maps):
    """§3.6: 'the loci of both working modes are identical' for B (only the signs of mᵢ change)."""
    np.testing.assert_array_equal(table_maps[1].inverse["B"], table_maps[2].inverse["B"])
    assert table_maps[1].global_index("B-1A") < table_maps[2].global_index("B-1A")   # mode 2 better (§3.6)


def test_partner_modes_have_equal_indices():
    """§3.5: by symmetry the opposite modes 1-5, 2-6, 3-7, 4-8 have the same conditioning, and 2, 3, 4 (6, 7, 8)
    are images by turns of 120°. The Cartesian grid (and its orientations) is symmetric under the mirror
    x → −x, which maps leg 1 to itself, swaps legs 2 and 3 and reverses every sign: mode (s₁, s₂, s₃) to
    (−s₁, −s₃, −s₂), i.e. 1 ↔ 5, 2 ↔ 6, 3 ↔ 8, 4 ↔ 7, whose global indices agree to rounding. The paper's
    pairs 3-7 and 4-8 are that mirror composed with a turn of 120°, which the grid respects only
    approximately: they agree to 1e-3, as do the six one-leg-reversed modes."""
    from classify.working_modes import three_prr_mode_pairs

    grid = -300.0 + 30.0 * (np.arange(20) + 0.5)
    orientations = np.linspace(-math.pi, math.pi, 24, endpoint=False)
    index = {mode: three_prr_map(grid, grid, WORKING_MODES[mode], ROOT_TWO_R, orientations).global_index("B-1A")
             for mode in range(1, 9)}
    by_signs = {tuple(WORKING_MODES[mode]): mode for mode in index}
    for mode, (first, second, third) in WORKING_MODES.items():
        mirrored = by_signs[(-first, -third, -second)]
        assert index[mode] == pytest.approx(index[mirrored], abs=1e-12), (mode, mirrored)
    assert {(mode, by_signs[(-signs[0], -signs[2], -signs[1])]) for mode, signs in WORKING_MODES.items()} >= \
        {(1, 5), (2, 6), (3, 8), (4, 7)}
    for first, second in three_prr_mode_pairs():
        assert index[first] == pytest.approx(index[second], abs=1e-3)
    reversed_one = [index[mode] for mode in (2, 3, 4, 6, 7, 8)]
    assert max(reversed_one) - min(reversed_one) < 1e-3
    assert min(reversed_one) > index[1] + 0.1        # mode 2 better conditioned than mode 1 (Table 1)


def test_batched_map_equals_pointwise():
    """The five-bar's vectorised map equals eq. 9 / eqs. 3b-c evaluated point by point."""
    xs, ys = np.linspace(-4.0, 12.0, 7), np.linspace(1.0, 11.0, 6)
    conditioning_map = five_bar_cartesian_map(xs, ys, (1, -1))
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            angles, reachable = five_bar_inverse_kinematics(np.array([x, y]), (1, -1))
            assert bool(reachable) == conditioning_map.reachable[i, j]
            if reachable:
                direct, _ = five_bar_matrices(angles)
                assert conditioning_map.inverse["A"][i, j] == pytest.approx(1 / singular_value_ratio(direct),
                                                                            rel=1e-12)


def test_isoconditioning_curves_are_coupler_curves():
    """Chablat, Wenger & Angeles 1998 §3.4, Fig. 5: the curves κ(A) = const are the coupler curves of the
    four-bar A-C-D-B obtained by locking the joint P (θ3 − θ4 = δ fixed). Moving that four-bar (θ1 swept, the
    triangle C-P-D rigid), κ(A) of eqs. 3b, 9 stays at its value, read back through the inverse kinematics."""
    from mechanisms.catalogue.five_bar import circle_intersection

    delta = 1.1
    chord = 2 * 5.0 * math.sin(delta / 2)
    points = []
    for theta1 in np.linspace(1.2, 2.2, 15):
        c = np.array([8.0 * math.cos(theta1), 8.0 * math.sin(theta1)])
        d = np.array(circle_intersection(tuple(c), chord, (6.0, 0.0), 8.0, -1))
        middle, unit = (c + d) / 2, (d - c) / chord
        points.append(middle + 5.0 * math.cos(delta / 2) * np.array([-unit[1], unit[0]]))
    points = np.array(points)
    values = []
    for point in points:
        for mode in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
            angles, reachable = five_bar_inverse_kinematics(point, mode)
            if reachable and abs(abs(np.angle(np.exp(1j * (angles[2] - angles[3])))) - delta) < 1e-9:
                values.append(singular_value_ratio(five_bar_matrices(angles)[0]))
                break
    assert len(values) == len(points)
    np.testing.assert_allclose(values, 1 / math.tan(delta / 2), rtol=1e-9)
    assert np.ptp(points[:, 0]) > 1.0        # a curve, not a point


def test_contours_interpolate_the_map():
    """Each vertex of an isoconditioning curve lies in a grid cell whose corner values bracket the level
    (marching squares): the curves are the map's level sets to the grid's resolution."""
    xs, ys = np.linspace(-8.0, 14.0, 45), np.linspace(0.5, 13.0, 26)
    conditioning_map = five_bar_cartesian_map(xs, ys, (1, 1))
    level = 0.5
    vertices = np.concatenate(contours(conditioning_map, "A", [level])[level])
    assert len(vertices) > 20
    values = conditioning_map.inverse["A"]
    for x, y in vertices:
        i = min(np.searchsorted(xs, x, side="right") - 1, len(xs) - 2)
        j = min(np.searchsorted(ys, y, side="right") - 1, len(ys) - 2)
        corners = values[i:i + 2, j:j + 2]
        assert np.nanmin(corners) - 1e-12 <= level <= np.nanmax(corners) + 1e-12


def test_joint_map_and_hybrid_plane_map():
    """The joint-space map (1998 Fig. 4) has κ(A) of eq. 9 at every reachable point, so κ(A) = ∞ on θ3 = θ4
    (P on the singular curve, which the grid approaches within 0.05 rad) and nowhere else; the hybrid's
    in-plane map has κ(B) = ∞ on the axis AB (d₁ = 0, eq. 30)."""
    joint_map = five_bar_joint_map(np.linspace(0.0, math.pi, 25), np.linspace(0.0, math.pi, 25), 1)
    assert joint_map.axis_names == ("θ1", "θ2")
    reachable = joint_map.reachable
    assert 0 < np.count_nonzero(reachable) < reachable.size
    # eq. 9: 1/κ(A) = |tan((θ3 − θ4)/2)|, the difference modulo π into [−π/2, π/2]: zero on θ3 = θ4 and only there
    angles = joint_map.extra["angles"][reachable]
    difference = np.angle(np.exp(2j * (angles[:, 2] - angles[:, 3]))) / 2
    np.testing.assert_allclose(joint_map.inverse["A"][reachable], np.abs(np.tan(difference / 2)), atol=1e-12)
    assert np.all(joint_map.inverse["A"][reachable] > 0) and np.abs(difference).min() < 0.05
    plane = hybrid_plane_map(np.array([0.0, 2.0, 4.0]), np.array([-3.0, 3.0, 9.0]), (1, 1))
    assert plane.reachable[0].any()
    np.testing.assert_array_equal(plane.inverse["B"][0][plane.reachable[0]], 0.0)
    assert np.all(plane.inverse["B"][1:][plane.reachable[1:]] > 0)


def test_summary_counts():
    conditioning_map = five_bar_cartesian_map(np.linspace(-10.0, 16.0, 14), np.linspace(-14.0, 14.0, 15), (1, 1))
    summary = conditioning_map.summary()
    assert summary["grid_size"] == 14 * 15
    assert summary["unreachable_share"] == pytest.approx(1 - conditioning_map.reachable.mean())
    for matrix, values in summary["matrices"].items():
        assert 0 <= values["global_index"] <= 1
        assert values["min_kappa"] >= 1


def test_isoconditioning_figure_content():
    from classify.figures.conditioning import isoconditioning_figure

    maps = [five_bar_cartesian_map(np.linspace(-8.0, 14.0, 30), np.linspace(-12.0, 12.0, 30), signs, mode=label)
            for signs, label in (((1, 1), "++"), ((-1, 1), "-+"))]
    figure = isoconditioning_figure(maps, "A", units="mm")
    axes = [axes for axes in figure.axes if axes.get_label() != "<colorbar>"]
    assert len(axes) == 2
    for panel, label in zip(axes, ("++", "-+")):
        assert panel.get_xlabel() == "x (mm)" and panel.get_ylabel() == "y (mm)"
        assert panel.get_title().startswith(f"mode {label}: 1/κ(Ā)")
        gids = {artist.get_gid() for artist in panel.get_children()}
        assert {"isoconditioning", "singularity"} <= gids
