"""Export to URDF + closures (:mod:`mechanisms.export`) and import back (:mod:`mechanisms.urdf`): the same
classification, the home found closed."""

import numpy as np
import pytest

from classify import classify
from mechanisms import home
from mechanisms.catalogue import entry
from mechanisms.closures import closures_from_dict, closures_to_dict
from mechanisms.export import export_urdf
from mechanisms.urdf import import_tree, retype, tree_from_urdf
from tests.builders import shared_mechanism

pytest.importorskip("yourdfpy")


def round_trip(mechanism):
    exported = export_urdf(mechanism)
    closures = closures_from_dict(closures_to_dict(exported.closures))
    tree = retype(tree_from_urdf(exported.urdf, "exported"), closures)
    return import_tree(tree, closures, mechanism.name)


def summary(report):
    return (report.dof, report.kinds, report.cspace.rank, report.actuator.rank, report.actuator.expected_rank,
            report.degeneracy)


@pytest.mark.parametrize("name, configuration", [
    ("five-bar", None), ("five-bar", "fig6a_distal_aligned"), ("slider-crank", None), ("gough-stewart", None),
])
def test_round_trip_classifies_the_same(name, configuration):
    item = entry(name)
    mechanism = shared_mechanism(item.assemble(item.values(configuration)))
    imported = round_trip(mechanism)
    assert imported.distance < 1e-9 and imported.residual < 1e-9
    rng = np.random.default_rng(0)
    original = classify(mechanism, home(mechanism), rng=rng)
    again = classify(imported.mechanism, home(imported.mechanism), rng=np.random.default_rng(0))
    assert summary(again)[:3] == summary(original)[:3] and summary(again)[3:] == summary(original)[3:]


def test_chord_ball_joints_become_3d_closures():
    item = entry("gough-stewart")
    exported = export_urdf(item.assemble(item.values(None)))
    assert "3d" in exported.closures.types
    assert set(exported.closures.retyped.values()) <= {"SPHERICAL"}


@pytest.mark.parametrize("name", ["five-bar", "slider-crank", "hybrid", "spherical-3rrr", "gough-stewart"])
def test_an_exported_robot_exports_again(name):
    """A mechanism read from an exported URDF has links named P_B, P_A, end_effector…: exported again, the
    names made up for its closures took those (two <link> elements 'P_B'), an invalid URDF written with exit 0.
    Made-up names now never take a name the mechanism has."""
    mechanism = shared_mechanism(entry(name).mechanism())
    once = round_trip(mechanism)
    twice = round_trip(once.mechanism)
    assert twice.distance < 1e-9 and twice.residual < 1e-9
    original = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    again = classify(twice.mechanism, home(twice.mechanism), rng=np.random.default_rng(0))
    assert summary(again) == summary(original)
