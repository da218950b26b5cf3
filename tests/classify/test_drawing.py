"""Mechanism drawings (:mod:`classify.figures.drawing`), tested by content (artists and their gids), not pixels."""

import numpy as np
import pytest

from classify import classify
from classify.figures.drawing import draw_mechanism, place_velocities, save_figure
from mechanisms import configuration
from tests.builders import catalogue_mechanism


def _gids(figure):
    return [artist.get_gid() for axes in figure.axes for artist in axes.get_children() if artist.get_gid()]


def _drawn(name, configuration_name=None):
    mechanism = catalogue_mechanism(name, configuration_name)
    point = configuration(mechanism, {}).point
    report = classify(mechanism, point)
    return mechanism, point, report, draw_mechanism(mechanism, point, report)


def test_five_bar_regular_has_links_joints_and_no_arrow():
    mechanism, _, report, figure = _drawn("five-bar")
    gids = _gids(figure)
    assert not report.kinds
    assert sorted(gid for gid in gids if gid.startswith("link:")) == [
        "link:distal_left", "link:distal_right", "link:proximal_left", "link:proximal_right"]
    assert sorted(gid for gid in gids if gid.startswith("actuated:")) == ["actuated:A", "actuated:B"]
    assert sorted(gid for gid in gids if gid.startswith("joint:")) == ["joint:C", "joint:D", "joint:P"]
    assert "end-effector" in gids and "ground" in gids
    assert not any(gid.startswith("lost:") for gid in gids)
    assert figure.axes[0].name == "rectilinear"


def test_five_bar_actuator_singularity_arrow_moves_the_end_effector_only():
    """Park & Kim 1999 Fig. 6a: with the distal links aligned and the actuators locked, P moves across the line."""
    mechanism, point, report, figure = _drawn("five-bar", "eq9_distal_aligned")
    assert "actuator" in report.kinds
    assert _gids(figure).count("lost:actuator") == 1
    places, velocities = place_velocities(mechanism, point, report.actuator.kernel[:, 0])
    speeds = {name: np.linalg.norm(value) for name, value in velocities.items()}
    assert max(speeds["A"], speeds["B"], speeds["C"], speeds["D"]) < 1e-6 * speeds["P"]
    line = places["D"] - places["C"]
    assert abs(velocities["P"] @ line) < 1e-6 * speeds["P"] * np.linalg.norm(line)


def test_slider_crank_draws_a_guide_for_the_slide():
    _, _, report, figure = _drawn("slider-crank", "fig3c_dead_centre")
    gids = _gids(figure)
    assert "guide:slide" in gids and "actuated:crank" in gids
    assert "lost:end_effector" in gids and "end_effector" in report.kinds


def test_spherical_drawing_is_on_the_unit_sphere_with_3d_axes():
    mechanism, _, report, figure = _drawn("spherical-3rrr", "eq70_leg1_extended")
    gids = _gids(figure)
    assert figure.axes[0].name == "3d" and "sphere" in gids
    assert len([gid for gid in gids if gid.startswith("actuated:")]) == 3
    for artist in figure.axes[0].get_lines():
        if (artist.get_gid() or "").startswith("link:"):
            x, y, z = artist.get_data_3d()
            np.testing.assert_allclose(np.sqrt(x ** 2 + y ** 2 + z ** 2), 1.0, atol=1e-9)
    assert "lost:end_effector" in gids


def test_spatial_drawing_has_3d_axes_and_legs(tmp_path):
    _, _, _, figure = _drawn("gough-stewart")
    gids = _gids(figure)
    assert figure.axes[0].name == "3d"
    assert len([gid for gid in gids if gid.startswith("guide:P")]) == 6
    assert "link:platform" in gids
    save_figure(figure, tmp_path / "gough.svg")
    assert (tmp_path / "gough.svg").stat().st_size > 1000


@pytest.mark.parametrize("suffix", ["png", "svg"])
def test_saved_without_display(tmp_path, suffix):
    _, _, _, figure = _drawn("planar-3rrr", "eq58_leg_stretched")
    save_figure(figure, tmp_path / f"figure.{suffix}")
    assert (tmp_path / f"figure.{suffix}").stat().st_size > 1000


def test_the_spherical_3rrrs_gripper_is_drawn_at_its_first_joints_axis_on_the_sphere():
    """On the sphere the end-effector is the image of its link's first joint axis (the module's convention);
    for a spherical mechanism nothing was drawn."""
    from mechanisms import link_pose

    mechanism, point, _, figure = _drawn("spherical-3rrr")
    artists = [artist for artist in figure.axes[0].get_children() if artist.get_gid() == "end-effector"]
    assert len(artists) == 1
    link = mechanism.end_effector.link
    axis = np.asarray(next(joint.axis for joint in mechanism.joints if link in joint.links), dtype=float)
    expected = link_pose(mechanism, link, point) @ (axis / np.linalg.norm(axis))
    drawn = np.array(artists[0].get_data_3d()).ravel()
    np.testing.assert_allclose(drawn, expected, atol=1e-12)
    assert abs(np.linalg.norm(drawn) - 1.0) < 1e-12
