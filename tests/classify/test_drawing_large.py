"""Drawings of large mechanisms: the places and their velocities along every lost direction in one pass over the
spanning tree (:func:`mechanisms.kinematics.link_poses`), and the ball blocks of :func:`rotation_blocks` found
without a search of the point's slices per part.

The cost is measured by counting, not timing: the element positions :func:`mechanisms._chains.element_matrices`
evaluates (chains × elements per call, whatever the number of configurations stacked). Before, every joint's place
was the product of its whole path from the ground (:func:`mechanisms.link_pose`), once per lost direction: about
depth × joints × directions element positions; now each tree joint's elements once per stack of configurations.
"""

import types

import numpy as np
import pytest

from classify.figures.drawing import draw_mechanism, joint_places, place_velocities
from mechanisms import EndEffector, Joint, Mechanism, configuration
from mechanisms import _chains as chains
from mechanisms import kinematics
from tests.builders import catalogue_mechanism, ladder, rsur, spatial_mix, spherical_four_bar


def _rsur_stack(loops):
    """A stack of spatial RSUR four-bars (:func:`tests.builders.rsur`), loop i on the coupler of loop i − 1: four
    joints a loop, the end-effector the top coupler's pose. Redundant (one actuator a loop, a six-dimensional
    output), so that its end-effector map loses many directions at once (10 with 15 loops)."""
    joints = []
    for index in range(1, loops + 1):
        below = "ground" if index == 1 else f"coupler{index - 1}"
        height, tilt = 2.0 * (index - 1), 0.05 * (index % 7)
        joints += [Joint(f"A{index}", "R", (below, f"crank{index}"), point=(0.0, 0.0, height), axis=(tilt, 0.0, 1.0),
                         actuated=True),
                   Joint(f"B{index}", "S", (f"crank{index}", f"coupler{index}"), point=(1.0, 0.1 + tilt, height + 0.3)),
                   Joint(f"C{index}", "U", (f"coupler{index}", f"rocker{index}"), point=(1.6, 1.3, height + 0.7),
                         axes=((0.2, 1.0, 0.1), (1.0, -0.1, 0.3))),
                   Joint(f"D{index}", "R", (f"rocker{index}", below), point=(0.4, 1.5, height + 0.1),
                         axis=(1.0, 0.2 + tilt, 0.1))]
    return Mechanism(f"RSUR stack {loops}", "spatial", joints,
                     end_effector=EndEffector(f"coupler{loops}", (1.2, 0.8, 2.0 * loops - 1.4), "pose"))


@pytest.fixture(scope="module")
def stack():
    """The 15-loop RSUR stack (60 joints, 105 coordinates) at home, and its end-effector kernel [105, m]."""
    from classify import classify

    mechanism = _rsur_stack(15)
    point = configuration(mechanism, {}).point
    report = classify(mechanism, point)
    assert "end_effector" in report.kinds
    kernel = np.asarray(report.end_effector.kernel)
    assert kernel.shape[1] >= 8  # many lost directions
    return mechanism, point, report, kernel


@pytest.fixture
def counted(monkeypatch):
    """A list that collects, per call of :func:`mechanisms._chains.element_matrices`, its chains × elements."""
    calls = []
    original = chains.element_matrices

    def counting(space, group, point):
        calls.append(group.values.shape[0] * group.length)
        return original(space, group, point)

    monkeypatch.setattr(chains, "element_matrices", counting)
    return calls


def _element_count(mechanism):
    """How many elements (1-dof factors and balls) the joints of `mechanism` have."""
    compiled = kinematics.kinematics_of(mechanism)
    return sum(len(chains.elements_of_joint(mechanism, joint, compiled.point_parts[joint.name], 0))
               for joint in mechanism.joints)


def test_drawing_every_lost_direction_evaluates_each_joint_a_bounded_number_of_times(stack, counted):
    """Two passes over the tree (the places, then the displaced configurations of every direction), however many
    lost directions: before, 2 · 10⁴ element positions here (a full path per joint and direction), now at most
    twice the 120 elements."""
    mechanism, point, report, kernel = stack
    figure = draw_mechanism(mechanism, point, report)
    quivers = [artist for artist in figure.axes[0].get_children() if artist.get_gid() == "lost:end_effector"]
    assert len(quivers) == kernel.shape[1]
    assert sum(counted) <= 2 * _element_count(mechanism)


def test_one_call_gives_every_directions_velocities_from_one_pass(stack, counted):
    mechanism, point, _, kernel = stack
    places, velocities = place_velocities(mechanism, point, kernel)
    assert sum(counted) <= _element_count(mechanism)
    assert all(value.shape == (kernel.shape[1], 3) for value in velocities.values())
    assert set(places) == set(velocities) and "end-effector" in places
    single_places, single_velocities = place_velocities(mechanism, point, kernel[:, 3])
    for name in places:
        np.testing.assert_array_equal(single_places[name], places[name])
        np.testing.assert_array_equal(single_velocities[name], velocities[name][3])


@pytest.mark.parametrize("build", [lambda: _rsur_stack(15), lambda: ladder(20, 10), spatial_mix, spherical_four_bar],
                         ids=["rsur-stack", "ladder", "spatial-mix", "spherical-four-bar"])
def test_link_poses_are_link_pose_for_every_link(build):
    """At a random configuration off M (the poses depend on the tree's paths there): the same arrays."""
    mechanism = build()
    ambient = kinematics.kinematics_of(mechanism).ambient
    random = np.random.default_rng(7)
    points = ambient.retract(configuration(mechanism, {}).point, random.standard_normal((3, ambient.dim)))
    poses = kinematics.link_poses(mechanism, points)
    assert set(poses) == set(mechanism.links)
    for link, pose in poses.items():
        np.testing.assert_array_equal(pose, kinematics.link_pose(mechanism, link, points))


@pytest.mark.parametrize("build", [lambda: _rsur_stack(15), lambda: ladder(20, 10), spatial_mix, spherical_four_bar],
                         ids=["rsur-stack", "ladder", "spatial-mix", "spherical-four-bar"])
def test_place_velocities_are_the_derivative_of_the_places(build):
    """Taylor test at a random configuration (off M) and random directions: the central difference
    ``(x(p ⊕ t v) − x(p ⊕ −t v)) / 2t`` of the joint places differs from the velocities by O(t²) — the error falls
    about fourfold each time t is halved — and is within 1e-3 relative at the smallest t."""
    mechanism = build()
    ambient = kinematics.kinematics_of(mechanism).ambient
    random = np.random.default_rng(11)
    point = ambient.retract(configuration(mechanism, {}).point, 0.3 * random.standard_normal(ambient.dim))
    directions = random.standard_normal((ambient.dim, 3)) * ambient.tangent_scales[:, None]
    places, velocities = place_velocities(mechanism, point, directions)
    names = list(joint_places(mechanism, point))
    exact = np.array([velocities[name] for name in names])                                   # [joints, 3, d]
    size = np.max(np.linalg.norm(exact, axis=-1))
    for number in range(directions.shape[1]):
        errors = []
        for step in 0.02 * 0.5 ** np.arange(4) / np.linalg.norm(directions[:, number] / ambient.tangent_scales):
            ahead = joint_places(mechanism, ambient.retract(point, step * directions[:, number]))
            behind = joint_places(mechanism, ambient.retract(point, -step * directions[:, number]))
            difference = np.array([(ahead[name][0] - behind[name][0]) / (2 * step) for name in names])
            errors.append(np.max(np.abs(difference - exact[:, number])))
        errors = np.array(errors)
        assert errors[-1] < 1e-3 * size
        assert np.all(errors[:-1] / errors[1:] > 3.0), errors  # O(t²): ×4 per halving


def _rotation_blocks_by_search(mechanism, point):
    """The former :func:`mechanisms.kinematics.rotation_blocks`' choice of the ball blocks: the factor of each part
    found by ``tuple.index`` in the point's slices (O(k²))."""
    compiled = kinematics.kinematics_of(mechanism)
    ambient = compiled.ambient
    return tuple(name for name, slices in compiled.point_parts.items() for part in slices
                 if ambient.factors[ambient.point_slices.index(part)] == "SO3")


@pytest.mark.parametrize("build", [lambda: catalogue_mechanism("gough-stewart"), lambda: catalogue_mechanism("5-spu"),
                                   lambda: catalogue_mechanism("five-bar"), spatial_mix, rsur,
                                   lambda: _rsur_stack(6)],
                         ids=["gough-stewart", "5-spu", "five-bar", "spatial-mix", "rsur", "rsur-stack"])
def test_rotation_blocks_are_the_ball_joints_found_by_the_search(build):
    mechanism = build()
    point = configuration(mechanism, {}).point
    names, rotations = kinematics.rotation_blocks(mechanism, np.stack([point, 1.5 * point]))
    assert names == _rotation_blocks_by_search(mechanism, point)
    assert names == tuple(joint.name for joint in mechanism.joints if joint.type == "S")
    assert rotations.shape == (2, len(names)) and np.all(rotations[0])
    assert not np.any(rotations[1]) or not names


def test_a_zero_direction_among_several_is_refused(stack):
    mechanism, point, _, kernel = stack
    directions = kernel[:, :3].copy()
    directions[:, 1] = 0.0
    with pytest.raises(ValueError, match="zero"):
        place_velocities(mechanism, point, directions)


def test_the_report_stub_draws_one_quiver_per_direction_of_each_kind():
    """Lost directions of two kinds in one stack: each kind's quivers keep their gid and order."""
    mechanism = ladder(4, 2)
    point = configuration(mechanism, {}).point
    dimension = kinematics.kinematics_of(mechanism).ambient.dim
    random = np.random.default_rng(3)
    result = lambda count: types.SimpleNamespace(singular=True, kernel=random.standard_normal((dimension, count)))
    report = types.SimpleNamespace(kinds=("actuator", "end_effector"), actuator=result(2), end_effector=result(3))
    figure = draw_mechanism(mechanism, point, report)
    gids = [artist.get_gid() for artist in figure.axes[0].get_children() if (artist.get_gid() or "").startswith("lost")]
    assert gids == ["lost:actuator"] * 2 + ["lost:end_effector"] * 3
