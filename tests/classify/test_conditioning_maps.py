"""Conditioning maps of any mechanism over joint grids, general working modes, the general characteristic
length, and the hybrid's 3-D map (Chablat, Caro, Wenger & Angeles 2002; Chablat, Wenger & Angeles 1998)."""

import math
import re

import numpy as np
import pytest

from classify.characteristic_length import mechanism_optimal_length, three_prr_kappa, three_prr_leg_angles
from classify.conditioning import mechanism_condition_numbers
from classify.conditioning_matrices import three_prr_pose_of
from classify.isoconditioning import (cartesian_grid_maps, hybrid_map, hybrid_plane_map, joint_grid_maps,
                                      mechanism_map)
from classify.inverse_kinematics_branches import mechanism_working_modes
from classify.working_modes import five_bar_working_modes, three_prr_working_modes
from mechanisms import catalogue, configuration, end_effector, to_displacements


def _entry_mechanism(name, configuration_name=None, **parameters):
    item = catalogue.entry(name)
    values = dict(item.configurations[configuration_name]) if configuration_name else {}
    mechanism = item.assemble({**values, **parameters})
    return mechanism, configuration(mechanism, {}).point


def _assembled_grid(mechanism, start, names, starts, stops, counts):
    """The grid of ``closedchain map`` (continuation on the start's branch), as the command assembles it."""
    from classify.grid_continuation import Grid, assemble_grid, grid_targets, held_columns

    columns = tuple(mechanism.coordinate_names.index(name) for name in names)
    grid = Grid(tuple(names), columns, tuple(starts), tuple(stops), tuple(counts))
    points, reachable = assemble_grid(mechanism, start, grid_targets(mechanism, grid, start), grid.shape,
                                      held_columns(mechanism, grid))
    return grid, points, reachable


@pytest.fixture(scope="module")
def stretched_map():
    """The five-bar at a serial singularity of 1998 eq. 3c (left leg stretched), a 5 × 5 grid of the actuated
    angles around it: the centre is the singular configuration itself."""
    mechanism, start = _entry_mechanism("five-bar", "eq3c_left_leg_stretched")
    grid, points, reachable = _assembled_grid(mechanism, start, ("A", "B"), (-0.2, -0.2), (0.2, 0.2), (5, 5))
    return mechanism, points, reachable, mechanism_map(mechanism, points, reachable, grid.axes(), grid.names,
                                                       derived=True)


def test_batched_map_equals_pointwise(stretched_map):
    """The batched map (J̄ of the batched Jacobians, λ of classify_many) equals one configuration at a time."""
    mechanism, points, reachable, conditioning_map = stretched_map
    assert reachable.all()
    for flat in (0, 7, 13, 24):
        index = np.unravel_index(flat, conditioning_map.shape)
        single = mechanism_condition_numbers(mechanism, points[flat][None])
        for matrix in ("A", "B", "A-1B", "lambda"):
            expected = 1.0 / single.values[matrix][0]
            assert conditioning_map.inverse[matrix][index] == pytest.approx(expected, rel=1e-9, abs=1e-12), matrix
    # unit actuator weights, position output (H = 1): Park & Kim's λ's are J̄'s squared singular values
    regular = ~conditioning_map.extra["singular"]
    np.testing.assert_allclose(conditioning_map.inverse["lambda"][regular],
                               conditioning_map.inverse["A-1B"][regular] ** 2, rtol=1e-8)


def test_map_marks_the_singular_configuration(stretched_map):
    """The grid point at the stretched leg: 1/κ = 0 and the batched classification calls it singular;
    every other point is regular."""
    _, _, _, conditioning_map = stretched_map
    singular = conditioning_map.extra["singular"]
    assert singular[2, 2] and np.count_nonzero(singular) == 1
    for matrix in ("B", "A-1B", "lambda"):
        assert conditioning_map.inverse[matrix][2, 2] <= 1e-8
        assert np.all(conditioning_map.inverse[matrix][~singular] > 1e-4)
    summary = conditioning_map.summary()
    assert summary["classified_singular_share"] == pytest.approx(1 / 25)
    assert summary["unreachable_share"] == 0.0


def test_unreachable_grid_points_are_nan():
    """Beyond the inputs' reach on the branch (the five-bar's legs cannot close): NaN, not counted."""
    mechanism, start = _entry_mechanism("five-bar", "fig2_working_mode_pp")
    grid, points, reachable = _assembled_grid(mechanism, start, ("A",), (0.0,), (math.pi,), (7,))
    assert reachable[0] and not reachable.all()
    conditioning_map = mechanism_map(mechanism, points, reachable, grid.axes(), grid.names)
    assert np.all(np.isnan(conditioning_map.inverse["A-1B"][~reachable]))
    assert np.all(np.isfinite(conditioning_map.inverse["A-1B"][reachable]))
    assert np.isnan(conditioning_map.inverse["A"]).all()      # derived A, B not asked for
    assert conditioning_map.summary()["matrices"]["A"]["global_index"] is None


@pytest.mark.parametrize("pose", [(0.0, 0.0, math.pi / 3), (20.0, -30.0, 1.2), (-40.0, 10.0, 0.7)])
def test_general_jacobian_agrees_with_the_papers_three_prr(pose):
    """κ(J̄) of the batched engine on the catalogue's 3-PRR equals κ(K̄) of 2002 eqs. 4a-b, 7 at the same L:
    the general J̄ is the paper's up to an orthogonal change of the output frame."""
    mechanism, point = _entry_mechanism("3-prr", x=pose[0], y=pose[1], phi=pose[2])
    length = math.sqrt(2) * 100.0
    general = mechanism_condition_numbers(mechanism, point[None], length).values["A-1B"][0]
    read_pose, signs = three_prr_pose_of(mechanism, point)
    assert general == pytest.approx(float(three_prr_kappa(length, read_pose, signs)), rel=1e-8)


def test_five_bar_working_modes_from_the_inverse_kinematics_branches():
    """1998 §3.3: four working modes at a pose; the general search finds the four of the closed form."""
    mechanism, point = _entry_mechanism("five-bar", "fig2_working_mode_pp")
    modes = mechanism_working_modes(mechanism, point, count=24)
    assert len(modes) == 4
    target = end_effector(mechanism, point[None])[0]
    home = np.array([to_displacements(mechanism, point)[name] for name in ("A", "B")])
    for mode in modes:
        assert np.allclose(end_effector(mechanism, mode.point[None])[0], target, atol=1e-9)
    # the closed-form modes' actuated angles θ1, θ2 as changes from mode ++ (this home); the catalogue's joint
    # B may turn the other way round, so the changes are compared in size
    closed = five_bar_working_modes(target)
    reference = np.array([mode for mode in closed if mode.label == "++"][0].angles[:2])
    expected = sorted(tuple(np.round(np.abs(np.angle(np.exp(1j * (np.array(mode.angles[:2]) - reference)))), 6))
                      for mode in closed)
    found = sorted(tuple(np.round(np.abs(np.array(mode.angles) - home), 6)) for mode in modes)
    np.testing.assert_allclose(found, expected, atol=1e-6)


@pytest.mark.parametrize("seed", range(4))
def test_a_serial_singular_pose_has_its_merged_modes_whatever_the_starts(seed):
    """At a serial singularity two working modes meet (1998 §3.3): with the left leg stretched the five-bar's
    pose has two inverse-kinematics branches, the right leg's two elbows. Gauss–Newton reaches the double
    root only to ~√tolerance, so the count must not depend on the starts (it did, at a 1e-6 separation)."""
    mechanism, point = _entry_mechanism("five-bar", "eq3c_left_leg_stretched")
    modes = mechanism_working_modes(mechanism, point, rng=np.random.default_rng(seed), count=24)
    assert len(modes) == 2
    assert abs(modes[1].angles[1] - modes[0].angles[1]) > 0.1   # the right elbow flipped, the left leg not
    assert abs(modes[1].angles[0] - modes[0].angles[0]) < 1e-4


def test_three_prr_eight_working_modes_from_the_branches():
    """2002 §3.5: eight working modes at the pose of Fig. 4a; each is one sign pattern of B's diagonal."""
    mechanism, point = _entry_mechanism("3-prr", "fig4a_isotropic")
    modes = mechanism_working_modes(mechanism, point, count=16)
    assert len(modes) == 8
    patterns = {tuple(three_prr_pose_of(mechanism, mode.point)[1].astype(int)) for mode in modes}
    assert patterns == {mode.signs for mode in three_prr_working_modes(three_prr_pose_of(mechanism, point)[0])}


def test_optimal_length_of_the_three_prr_is_the_closed_form_at_its_posture():
    """--length auto for a general mechanism: κ(J̄) minimised over L and posture reaches κ = 1, and L is
    √2 r sin γ at the posture found (2002 §3.4)."""
    mechanism, point = _entry_mechanism("3-prr", x=10.0, y=-5.0, phi=1.0)
    found, isotropic = mechanism_optimal_length(mechanism, point, restarts=0, max_evaluations=250)
    assert found.method == "optimised" and found.kappa == pytest.approx(1.0, abs=1e-6)
    assert isotropic and isotropic[0][1] <= 1e-6
    optimum, _ = _entry_mechanism("3-prr", x=10.0, y=-5.0, phi=1.0)
    from mechanisms import from_displacements

    posture = from_displacements(optimum, isotropic[0][0])
    pose, signs = three_prr_pose_of(optimum, posture)
    gamma = three_prr_leg_angles(pose, signs)
    np.testing.assert_allclose(gamma, gamma[0], atol=1e-4)     # the isotropy conditions: equal γᵢ (10a-d)
    assert found.value == pytest.approx(math.sqrt(2) * 100.0 * math.sin(gamma[0]), rel=1e-5)


def test_hybrid_conditioning_surfaces_are_surfaces_of_revolution():
    """1998 §5.1: κ at points turned about AB is the same, and the 3-D map on the plane z = 0 is the
    in-plane map."""
    distance, along, turns = 6.0, 3.0, np.linspace(-math.pi, math.pi, 9)
    values = [hybrid_map([distance * math.cos(angle)], [along], [-distance * math.sin(angle)], (1, -1))
              for angle in turns]
    plane = hybrid_plane_map([distance], [along], (1, -1))
    for conditioning_map in values:
        assert conditioning_map.reachable.all()
        for matrix in ("A", "B", "B-1A"):
            assert conditioning_map.inverse[matrix].item() == pytest.approx(plane.inverse[matrix].item(), rel=1e-12)
    np.testing.assert_allclose([conditioning_map.extra["theta1"].item() for conditioning_map in values[1:-1]],
                               turns[1:-1], atol=1e-12)


def test_hybrid_general_conditioning_is_independent_of_the_base_turn():
    """The catalogue's hybrid, general engine (no paper formula): κ(J̄) and λ do not change with θ1."""
    reference = None
    for turn in (0.4, 1.7, -2.5):
        mechanism, point = _entry_mechanism("hybrid", "regular", theta1=turn)
        numbers = mechanism_condition_numbers(mechanism, point[None])
        current = (numbers.values["A-1B"][0], numbers.values["lambda"][0])
        if reference is None:
            reference = current
        assert current == pytest.approx(reference, rel=1e-9)


def test_surface_figure_content():
    from classify.figures.conditioning import isoconditioning_surface_figure

    plane = hybrid_plane_map(np.linspace(0.0, 12.0, 25), np.linspace(-6.0, 12.0, 25), (1, 1), mode="++")
    figure = isoconditioning_surface_figure([plane], "B-1A", levels=(0.3, 0.6), turns=8)
    axes = figure.axes[0]
    surfaces = [artist for artist in axes.collections if artist.get_gid() == "isoconditioning_surface"]
    assert surfaces and {surface.get_label() for surface in surfaces} == {"1/κ = 0.3", "1/κ = 0.6"}
    assert (axes.get_xlabel(), axes.get_ylabel(), axes.get_zlabel()) == ("x", "y (along AB)", "z")


def test_general_figure_marks_singular_points(stretched_map):
    from classify.figures.conditioning import isoconditioning_figure

    _, _, _, conditioning_map = stretched_map
    figure = isoconditioning_figure([conditioning_map], "A-1B", equal_aspect=False)
    axes = figure.axes[0]
    marks = [artist for artist in axes.collections if artist.get_gid() == "singular_points"]
    assert len(marks) == 1 and np.allclose(marks[0].get_offsets(), [[0.0, 0.0]])
    assert (axes.get_xlabel(), axes.get_ylabel()) == ("A", "B")


@pytest.fixture(scope="module")
def five_bar_cartesian_maps():
    """The catalogue's five-bar mapped by the general engine over P = (x, y), one map per working mode found
    (its inverse-kinematics branches, each followed over the grid without crossing a serial singularity)."""
    mechanism, point = _entry_mechanism("five-bar", "fig2_working_mode_pp")
    xs, ys = np.linspace(-8.0, 14.0, 12), np.linspace(-12.0, 12.0, 13)
    modes = mechanism_working_modes(mechanism, point, count=24)
    return xs, ys, cartesian_grid_maps(mechanism, modes, ("x", "y"), (xs, ys), point)


def test_general_cartesian_maps_are_the_papers_working_modes(five_bar_cartesian_maps):
    """1998 §3.3-3.4, Fig. 5: each working mode the general engine follows over (x, y) is one of the paper's
    four (signs of B's diagonal, eq. 3c), with its κ(K̄) of eqs. 3b-c, and the four are different."""
    from classify.isoconditioning import five_bar_cartesian_map

    xs, ys, maps = five_bar_cartesian_maps
    paper = {label: five_bar_cartesian_map(xs, ys, (1 if label[0] == "+" else -1, 1 if label[1] == "+" else -1))
             for label in ("++", "+-", "-+", "--")}
    matched = []
    for conditioning_map in maps:
        for label, reference in paper.items():
            both = conditioning_map.reachable & reference.reachable
            if np.allclose(conditioning_map.inverse["A-1B"][both], reference.inverse["B-1A"][both], atol=1e-6):
                matched.append(label)
                # the continuation covers the mode's region (up to cells cut off by a singularity)
                assert np.count_nonzero(conditioning_map.reachable & ~reference.reachable) == 0
                assert np.count_nonzero(both) >= 0.8 * np.count_nonzero(reference.reachable)
                break
    assert sorted(matched) == ["++", "+-", "-+", "--"]


def test_joint_grid_maps_follow_each_working_mode():
    """One map per working mode of the five-bar's Fig. 2 pose (1998 §3.3), each over a grid of the actuated
    angles centred on the mode's own: the centre is the mode's configuration, with its κ, and the mode's label."""
    from classify.grid_continuation import Grid

    mechanism, point = _entry_mechanism("five-bar", "fig2_working_mode_pp")
    modes = mechanism_working_modes(mechanism, point, count=24)
    columns = tuple(mechanism.coordinate_names.index(name) for name in ("A", "B"))
    for index, mode in enumerate(modes):
        centre = np.array([to_displacements(mechanism, mode.point)[name] for name in ("A", "B")])
        grid = Grid(("A", "B"), columns, tuple(centre - 0.1), tuple(centre + 0.1), (3, 3))
        conditioning_map = joint_grid_maps(mechanism, modes, grid)[index]
        assert conditioning_map.mode == mode.label and conditioning_map.reachable[1, 1]
        np.testing.assert_allclose(conditioning_map.extra["points"][1, 1], mode.point, atol=1e-9)
        single = mechanism_condition_numbers(mechanism, mode.point[None])
        assert conditioning_map.inverse["A-1B"][1, 1] == pytest.approx(1.0 / single.values["A-1B"][0], rel=1e-9)


@pytest.mark.parametrize("name, axes, message", [
    ("five-bar", ("x", "y", "z"), "five-bar's output is a position (x, y)"),
    ("3-prr", ("x", "y", "z"), "over x, y and φ, not z"),
    ("gough-stewart", ("x", "y"), "a Cartesian grid needs a position or planar pose output"),
])
def test_cartesian_outputs_refuse_axes_that_do_not_fit_the_output(name, axes, message):
    from classify.inverse_kinematics_branches import cartesian_outputs

    mechanism, point = _entry_mechanism(name)
    with pytest.raises(ValueError, match=re.escape(message)):
        cartesian_outputs(mechanism, point, axes, [np.linspace(0.0, 1.0, 2)] * len(axes))


def test_cartesian_outputs_of_a_planar_pose_keep_the_configurations_turn():
    """φ off the grid is the configuration's own rotation of the end-effector's link."""
    from classify.inverse_kinematics_branches import cartesian_outputs

    mechanism, point = _entry_mechanism("3-prr")
    frame = end_effector(mechanism, point[None])[0]
    values = cartesian_outputs(mechanism, point, ("x", "y"), (np.linspace(0.0, 1.0, 2), np.linspace(0.0, 2.0, 3)))
    assert values.shape == (6, 3)
    np.testing.assert_allclose(values[:, 2], math.atan2(frame[1, 0], frame[0, 0]))
    np.testing.assert_allclose(values[:, :2], [[0, 0], [0, 1], [0, 2], [1, 0], [1, 1], [1, 2]])


def test_working_modes_of_an_orientation_output():
    """An orientation output is the rotation matrix itself (SO(3)), not a homogeneous matrix: its residual took
    the 2×2 corner and the working modes of the spherical 3-RRR failed with a NumPy broadcast error (also
    printed by ``closedchain conditioning spherical-3rrr --grid X=… Y=…``). Every mode keeps the gripper's
    orientation; mode 1 is the configuration's own."""
    mechanism, point = _entry_mechanism("spherical-3rrr")
    modes = mechanism_working_modes(mechanism, point)
    assert modes and np.allclose(modes[0].point, point, atol=1e-9)
    reference = end_effector(mechanism, point)
    for mode in modes:
        np.testing.assert_allclose(end_effector(mechanism, mode.point), reference, atol=1e-9)
