"""Idle freedoms and architecture singularities with the ``tool`` output (docs/design.rst, "The three kinds").

An idle freedom is a direction of ker G ∩ ker J, generically on M: it moves neither an actuator nor
the end-effector, and is not counted as a singularity. A locked-actuator freedom that moves the
end-effector (ker G outside ker J, generically on M) makes the design architecturally singular
(Gosselin & Angeles 1990, eq. 87): the report says so in JSON (``architecture_singular``,
``moving_idle_freedoms``) and in text. The 5-SPU's free spin (Borràs, Thomas & Torras 2011, Fig. 1)
does not move its tool: idle. The Gough–Stewart platform of eq. (87) moves its tool point when its
legs are locked: architecture singularity, whatever the tool's axis.
"""

import json

import numpy as np
import pytest

from builders import catalogue_mechanism, shared_mechanism
from classify import classify, classify_many, model_of, survey_of
from classify.cli import main
from manifold import project
from mechanisms import EndEffector, Mechanism, configuration_space, home, kinematics_of, save

#: Gosselin & Angeles 1990 eq. (87) design at a generic pose (as in tests/catalogue)
EQ87_POSE = {"x": 0.3, "y": -0.2, "z": 0.8, "rotation_x": 0.4, "rotation_y": -0.3, "rotation_z": 0.5}


def with_tool(mechanism, axis, point=None):
    """`mechanism` with an axisymmetric tool on its end-effector link (``output: tool``)."""
    point = mechanism.end_effector.point if point is None else tuple(float(value) for value in point)
    tool = EndEffector(mechanism.end_effector.link, point, "tool", tuple(float(value) for value in axis))
    return shared_mechanism(Mechanism(mechanism.name, mechanism.space, mechanism.joints, mechanism.ground, tool))


def at_home(mechanism):
    return classify(mechanism, home(mechanism), rng=np.random.default_rng(0))


def nearby_points(mechanism, count, seed):
    """`count` points of M near the home (projected random displacements), shape=[count, point_size]."""
    rng = np.random.default_rng(seed)
    space = kinematics_of(mechanism).ambient
    manifold = configuration_space(mechanism)
    starts = space.retract(home(mechanism), 0.05 * space.tangent_scales * rng.standard_normal((count, space.dim)))
    return np.array([project(manifold, start) for start in starts])


@pytest.fixture(scope="module")
def eq87_tool():
    """Gosselin & Angeles 1990 eq. (87) (similar hexagons, parallel legs) with a tool along a direction of the
    platform that is not its normal."""
    mechanism = catalogue_mechanism("gough-stewart", "eq87_parallel_legs", **EQ87_POSE)
    return with_tool(mechanism, (0.2, 0.9, -0.4))


@pytest.fixture(scope="module")
def five_spu_tool():
    return catalogue_mechanism("5-spu", "eq33_second_factor")


# ----------------------------------------------------------------------------- Gough–Stewart eq. (87)

@pytest.mark.parametrize("axis", [(0.2, 0.9, -0.4), "normal"])
def test_eq87_is_an_architecture_singularity_with_a_tool(axis):
    """With the legs locked the eq. (87) platform still moves its tool point: a locked-actuator freedom that moves
    the end-effector, not an idle one — whatever the tool's axis (a tilted one, or the platform normal)."""
    mechanism = catalogue_mechanism("gough-stewart", "eq87_parallel_legs", **EQ87_POSE)
    if axis == "normal":
        from scipy.spatial.transform import Rotation

        rotation = Rotation.from_rotvec([EQ87_POSE[f"rotation_{name}"] for name in "xyz"]).as_matrix()
        axis = rotation[:, 2]
    report = at_home(with_tool(mechanism, axis))
    assert report.dof == 6 and report.idle_freedoms == 0 and report.moving_idle_freedoms == 1
    assert report.architecture_singular and report.kinds == ("actuator",)
    assert (report.actuator.rank, report.actuator.expected_rank) == (5, 6)
    assert report.end_effector.rank == report.end_effector.expected_rank == 5


def test_eq87_says_architecture_singularity_in_json_and_text(eq87_tool):
    data = at_home(eq87_tool).to_dict()
    assert data["architecture_singular"] is True and data["moving_idle_freedoms"] == 1
    assert data["actuator"]["architecture_singular"] is True and data["actuator"]["moving_idle_freedoms"] == 1
    assert data["actuator"]["idle_freedoms"] == 0
    json.dumps(data, allow_nan=False)
    text = at_home(eq87_tool).to_text()
    assert "architecture singularity" in text.lower()
    assert "ARCHITECTURE SINGULARITY: 1 locked-actuator freedom(s) move the end-effector" in text


def test_eq87_from_a_file_through_the_command(tmp_path, capsys, eq87_tool):
    """``closedchain classify FILE`` on the eq. (87) platform saved with ``output: tool`` and its ``axis``."""
    path = tmp_path / "eq87_tool.yaml"
    save(eq87_tool, path)
    assert "axis:" in path.read_text() and "output: tool" in path.read_text()
    assert main(["classify", str(path), "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["architecture_singular"] is True and data["moving_idle_freedoms"] == 1
    assert data["end_effector"]["rank"] == 5
    assert "architecture singularity" in " ".join(data["notes"])


def test_a_generic_gough_stewart_with_a_tool_is_not_architecturally_singular():
    """The platform's spin about the tool axis moves the legs: neither idle nor moving with the actuators locked."""
    report = at_home(with_tool(catalogue_mechanism("gough-stewart"), (0.0, 0.3, 1.0)))
    assert (report.dof, report.idle_freedoms, report.moving_idle_freedoms) == (6, 0, 0)
    assert not report.architecture_singular and report.kinds == ()
    assert report.to_dict()["architecture_singular"] is False and "architecture" not in report.to_text().lower()


# ----------------------------------------------------------------------------- batches agree with single calls

@pytest.mark.parametrize("name", ["eq87", "5-spu"])
def test_batched_rows_agree_with_single_calls(name, eq87_tool, five_spu_tool):
    mechanism = eq87_tool if name == "eq87" else five_spu_tool
    points = np.concatenate([home(mechanism)[None], nearby_points(mechanism, 1, seed=3)])
    shared = survey_of(model_of(mechanism))
    result = classify_many(mechanism, points, survey=shared)
    for index, row in enumerate(result.rows()):
        report = classify(mechanism, points[index], survey=shared)
        data = report.to_dict()
        assert row["architecture_singular"] == data["architecture_singular"] == (name == "eq87")
        assert row["moving_idle_freedoms"] == data["moving_idle_freedoms"] == (1 if name == "eq87" else 0)
        assert row["idle_freedoms"] == data["actuator"]["idle_freedoms"] == (0 if name == "eq87" else 1)
        assert row["kinds"] == data["kinds"] and row["ranks"]["actuator"] == report.actuator.rank
        assert result.report(index).to_dict()["architecture_singular"] == data["architecture_singular"]
    assert result.to_dict()["rows"] == result.rows()


# ----------------------------------------------------------------------------- the 5-SPU's spin is idle

def test_the_five_spu_spin_is_idle_with_a_tool_and_moving_with_a_pose(five_spu_tool):
    """Borràs, Thomas & Torras 2011 Fig. 1: the five aligned revolutes let the tool spin about Λ. With ``output:
    tool`` that spin is an idle freedom — the report's JSON and text say so and raise no architecture
    singularity; with the platform pose as end-effector it would be one."""
    report = at_home(five_spu_tool)
    data = report.to_dict()
    assert data["architecture_singular"] is False and data["moving_idle_freedoms"] == 0
    assert data["actuator"]["idle_freedoms"] == 1 and data["dof"] == 6
    assert "idle freedoms: 1" in report.to_text() and "architecture" not in report.to_text().lower()
    pose = catalogue_mechanism("5-spu", "eq33_second_factor", end_effector="pose")
    assert at_home(pose).to_dict()["architecture_singular"] is True


def test_the_tool_verdicts_do_not_depend_on_the_axis_sign_nor_the_point_along_it(five_spu_tool):
    """The same verdicts, ranks and idle freedoms with the tool axis reversed or the tool point moved along Λ;
    the same proper values with the axis reversed (JᵀHJ is unchanged), on a regular pose of M near the home."""
    end = five_spu_tool.end_effector
    unit = np.asarray(end.axis) / np.linalg.norm(end.axis)
    variants = [with_tool(five_spu_tool, -unit), with_tool(five_spu_tool, unit, np.asarray(end.point) + 1.5 * unit)]
    for point in (home(five_spu_tool), nearby_points(five_spu_tool, 1, seed=5)[0]):
        reference = classify(five_spu_tool, point, rng=np.random.default_rng(0))
        for index, other in enumerate(variants):
            report = classify(other, point, survey=survey_of(model_of(five_spu_tool)), rng=np.random.default_rng(0))
            assert (report.kinds, report.degeneracy, report.idle_freedoms, report.moving_idle_freedoms) == \
                (reference.kinds, reference.degeneracy, reference.idle_freedoms, reference.moving_idle_freedoms)
            assert (report.actuator.rank, report.end_effector.rank) == \
                (reference.actuator.rank, reference.end_effector.rank)
            if index == 0 and reference.manipulability is not None:
                np.testing.assert_allclose(report.manipulability.eigenvalues, reference.manipulability.eigenvalues,
                                           rtol=1e-9)
