"""Manipulability with idle freedoms: the proper values on a complement of the motions that move nothing.

A Gough–Stewart platform with S joints at the base (6-SPS) has six idle freedoms, each leg's spin about its
own axis: G = (E^½ T)ᵀ(E^½ T) is singular on T_pM, so no λ was given. G and JᵀHJ both vanish on those spins,
and the pencil det(λG − JᵀHJ) of the quotient by them (Park & Kim 1999, Section 2) is that of the 6-UPS,
whose U joints do not spin: the same λ's.
"""

import numpy as np
import pytest

from classify import classify, classify_many, model_of
from manifold import sample_manifold
from mechanisms import Joint, Mechanism, catalogue, configuration


def balls_for_universals(mechanism):
    """The same mechanism with every U joint a ball joint (S) at the same centre."""
    joints = [Joint(joint.name, "S", joint.links, point=joint.point) if joint.type == "U" else joint
              for joint in mechanism.joints]
    return Mechanism(mechanism.name, mechanism.space, joints, mechanism.ground, mechanism.end_effector)


@pytest.mark.parametrize("pose", [{}, {"x": 0.1, "y": -0.05, "rotation_x": 0.15, "rotation_z": 0.3}])
def test_a_6sps_has_the_proper_values_of_its_6ups(pose):
    universal = catalogue.entry("gough-stewart").mechanism(**pose)
    ball = balls_for_universals(universal)
    expected = classify(universal, configuration(universal, {}).point)
    found = classify(ball, configuration(ball, {}).point)
    assert found.idle_freedoms == 6 and expected.idle_freedoms == 0
    assert found.kinds == expected.kinds == ()
    np.testing.assert_allclose(found.manipulability.eigenvalues, expected.manipulability.eigenvalues, rtol=1e-9)
    assert found.manipulability.condition_number == pytest.approx(expected.manipulability.condition_number,
                                                                  rel=1e-9)


def test_the_batch_gives_the_proper_values_with_idle_freedoms_as_single_calls():
    ball = balls_for_universals(catalogue.entry("gough-stewart").mechanism())
    model = model_of(ball)
    points = sample_manifold(model.manifold, np.random.default_rng(8), model.starts, random_count=0, walk_count=6)
    batch = classify_many(model, points)
    for item in range(len(points)):
        single = classify(model, points[item])
        assert single.manipulability is not None
        np.testing.assert_allclose(batch.eigenvalues[item], single.manipulability.eigenvalues, rtol=1e-9)


def in_space(mechanism):
    """A planar mechanism written as a spatial one: its points at z = 0, its R axes along z."""
    from mechanisms import EndEffector

    joints = [Joint(joint.name, joint.type, joint.links, point=tuple(joint.point) + (0.0,), axis=(0.0, 0.0, 1.0),
                    actuated=joint.actuated) for joint in mechanism.joints]
    end_effector = mechanism.end_effector
    return Mechanism(mechanism.name, "spatial", joints, mechanism.ground,
                     EndEffector(end_effector.link, tuple(end_effector.point) + (0.0,), end_effector.output))


@pytest.mark.parametrize("name", [None, "fig12a_end_effector"])
def test_a_planar_mechanism_written_in_space_has_its_planar_proper_values(name):
    """Park & Kim 1999's planar six-bar (3 dof, a position output): written in space its end-effector has a
    third coordinate, z, that never moves, and a third λ = 0 made κ infinite at every configuration (as a URDF
    round trip showed, found by an audit). There are as many λ's as J has rank on M."""
    from mechanisms import home

    planar = catalogue.entry("planar-six-bar").mechanism(**({"configuration": name} if name else {}))
    spatial = in_space(planar)
    expected, found = classify(planar, home(planar)), classify(spatial, home(spatial))
    assert found.kinds == expected.kinds
    np.testing.assert_allclose(found.manipulability.eigenvalues, expected.manipulability.eigenvalues, rtol=1e-9,
                               atol=1e-12)  # at Fig. 12a λ₂ is rounding (1e-65)
    assert (found.manipulability.condition_number is None) == (name is not None)
    batch = classify_many(spatial, home(spatial)[None])  # the columns (report(0) would be a single call)
    np.testing.assert_allclose(batch.eigenvalues[0][:2], expected.manipulability.eigenvalues, rtol=1e-9, atol=1e-12)
    assert np.isnan(batch.eigenvalues[0][2])
    if name is None:
        assert batch.condition_number[0] == pytest.approx(expected.manipulability.condition_number, rel=1e-9)
