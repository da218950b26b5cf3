"""Overconstrained loops: a Bennett linkage (spatial 4R) has rank DΦ = 3 < 6 rows on M, dof 1,
and that is not a C-space singularity (docs/design.rst, "Dimension")."""

import numpy as np
import pytest

from builders import bennett
from classify import classify
from manifold import project
from mechanisms import configuration_space, home, kinematics_of


def test_bennett_has_one_degree_of_freedom_and_is_regular_at_home():
    mechanism = bennett()
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert report.dof == 1
    assert "cspace" not in report.kinds
    assert report.cspace.rank == 3 and report.cspace.expected_rank == 3


@pytest.mark.parametrize("theta1", [0.3, 1.1, 2.0])
def test_bennett_is_not_cspace_singular_along_its_motion(theta1):
    """Walk along the motion (projected steps from home) and classify: never C-space singular."""
    mechanism = bennett(theta1=theta1)
    manifold = configuration_space(mechanism)
    space = kinematics_of(mechanism).ambient
    rng = np.random.default_rng(1)
    point = home(mechanism)
    for _ in range(3):
        point = project(manifold, space.retract(point, 0.2 * rng.standard_normal(space.dim)))
        report = classify(mechanism, point, rng=rng)
        assert report.dof == 1
        assert "cspace" not in report.kinds


def test_planar_loop_written_in_space_is_overconstrained_not_singular():
    """A planar four-bar written as a spatial mechanism (parallel z axes): 6 loop rows, rank 3."""
    from mechanisms import Joint, Mechanism
    points = [(0, 0, 0), (0.2, 1, 0), (2, 1.4, 0), (2.1, 0, 0)]
    links = ["ground", "crank", "coupler", "rocker", "ground"]
    mechanism = Mechanism("spatial four-bar", "spatial", [
        Joint(f"R{i + 1}", "R", (links[i], links[i + 1]), point=points[i], axis=(0, 0, 1), actuated=i == 0)
        for i in range(4)])
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert report.dof == 1 and report.kinds == ()
    assert report.cspace.rank == 3


def test_idle_freedom_is_reported_not_called_singular():
    """RSSR: the coupler spins freely about the line of its two ball joints. That freedom is a
    dimension of M that no actuator sees (G has rank ≤ 1 < m = 2 everywhere): an idle freedom."""
    from mechanisms import Joint, Mechanism
    mechanism = Mechanism("RSSR", "spatial", [
        Joint("A", "R", ("ground", "crank"), point=(0, 0, 0), axis=(0, 0, 1), actuated=True),
        Joint("B", "S", ("crank", "coupler"), point=(1, 0, 0.2)),
        Joint("C", "S", ("coupler", "rocker"), point=(1.5, 1.6, 0.6)),
        Joint("D", "R", ("rocker", "ground"), point=(0.3, 1.5, 0), axis=(1, 0.2, 0.1)),
    ])
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert report.dof == 2
    assert report.idle_freedoms == 1
    assert report.kinds == ()
    assert report.actuator.rank == 1 and report.actuator.expected_rank == 1
    assert report.to_dict()["actuator"]["idle_freedoms"] == 1


def test_spherical_four_bar_has_one_degree_of_freedom():
    from builders import spherical_four_bar
    mechanism = spherical_four_bar()
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert report.dof == 1 and report.kinds == ()
    assert len(report.manipulability.eigenvalues) == 1
