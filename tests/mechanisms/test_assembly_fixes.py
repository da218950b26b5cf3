"""Fixes of the assembly and closure checks (mechanisms.assembly, mechanisms.closes).

1. Assembly with nothing left to solve: when the held values fix every coordinate, the only candidate is the
   configuration they name; it is the assembly if it closes, else the usual "no assembly" error (exit 2 on the
   command line), never an internal error.
2. A configuration whose ball-joint block is not a rotation matrix is no point of M: Φ's rotation rows
   ½ vee(R − Rᵀ) do not see a symmetric part, so :func:`mechanisms.closes` checks the blocks too.
"""

import io

import numpy as np
import pytest

from classify import classify
from classify.cli import main
from manifold import AmbientSpace
from mechanisms import (
    AssemblyError, ConfigurationError, assemble, assemblies, closes, constraint, home, kinematics_of, load,
)
from mechanisms.catalogue.gough_stewart import gough_stewart
from mechanisms import kinematics

SLIDER_CRANK = "examples/slider_crank.yaml"
ALL_HELD = {"crank": 0, "pin": 0, "wrist": 0, "slide": 0}

SR = """\
name: sr_coaxial
space: spatial
joints:
- name: R1
  type: R
  links: [ground, body]
  point: [0.0, 0.0, 0.0]
  axis: [0.0, 0.0, 1.0]
  actuated: true
- name: S1
  type: S
  links: [body, ground]
  point: [0.0, 0.0, 0.7]
end_effector:
  link: body
  point: [0.3, 0.2, 0.1]
  output: pose
"""


@pytest.fixture
def sr_path(tmp_path):
    path = tmp_path / "sr.yaml"
    path.write_text(SR)
    return str(path)


def run(argv, capsys):
    out = io.StringIO()
    status = main(argv, out=out)
    return status, out.getvalue(), capsys.readouterr().err


# ----------------------------------------------------------------------------- 1. nothing left to solve

@pytest.mark.parametrize("method", [None, "newton", "continuation"])
def test_every_coordinate_held_at_a_closed_configuration_is_the_assembly(method):
    mechanism = load(SLIDER_CRANK)
    reached = assemble(mechanism, ALL_HELD, method=method)
    assert np.array_equal(reached.point, home(mechanism))
    assert reached.residual <= 1e-12 and (reached.branch, reached.branches) == (0, 1)
    assert reached.displacements == {name: 0.0 for name in ALL_HELD}


def test_every_coordinate_held_lists_one_assembly_and_takes_a_guess_and_branch_0():
    mechanism = load(SLIDER_CRANK)
    found = assemblies(mechanism, ALL_HELD)
    assert len(found) == 1 and found[0].branch == 0
    assert assemble(mechanism, ALL_HELD, guess={"pin": 0.1}).branch == 0
    assert assemble(mechanism, ALL_HELD, branch=0).branch == 0
    with pytest.raises(AssemblyError, match="branch 1"):
        assemble(mechanism, ALL_HELD, branch=1)


@pytest.mark.parametrize("method", [None, "newton", "continuation"])
def test_every_coordinate_held_where_the_loops_do_not_close_is_no_assembly(method):
    mechanism = load(SLIDER_CRANK)
    with pytest.raises(AssemblyError, match="no assembly with crank = 0.3"):
        assemble(mechanism, {**ALL_HELD, "crank": 0.3}, method=method)
    with pytest.raises(AssemblyError, match="no assembly"):
        assemblies(mechanism, {**ALL_HELD, "crank": 0.3})


def test_a_ball_joint_held_with_the_actuator_at_home(sr_path):
    mechanism = load(sr_path)
    with pytest.raises(AssemblyError, match="no assembly with S1"):
        assemble(mechanism, {"S1": [0.0, 0.0, 0.5]})
    reached = assemble(mechanism, {"S1": [0.0, 0.0, 0.0]})
    assert np.array_equal(reached.point, home(mechanism)) and reached.branch == 0


def test_a_ball_joint_and_the_actuator_held_where_they_close(sr_path):
    mechanism = load(sr_path)
    for rotation in ([0.0, 0.0, 0.5], [0.0, 0.0, -0.5]):
        try:
            reached = assemble(mechanism, {"R1": 0.5, "S1": rotation})
        except AssemblyError:
            continue
        assert reached.residual <= 1e-10 and reached.displacements["R1"] == 0.5
        break
    else:
        pytest.fail("R1 = 0.5 closes with S1 turned by ±0.5 about z")


def test_cli_every_coordinate_held_classifies_or_exits_2(capsys, sr_path):
    status, text, error = run(["classify", SLIDER_CRANK, "--at", '{"crank":0,"pin":0,"wrist":0,"slide":0}',
                               "--assemble"], capsys)
    assert status == 0 and "internal error" not in error and text
    status, text, error = run(["classify", sr_path, "--at", '{"S1":[0,0,0.5]}', "--assemble"], capsys)
    assert status == 2 and text == ""
    assert error.count("\n") == 1 and error.startswith("closedchain: error:") and "no assembly" in error


# ----------------------------------------------------------------------------- 2. rotation blocks

def _with_block(mechanism, point, joint, block):
    point = np.array(point, dtype=float)
    point[..., kinematics_of(mechanism).point_parts[joint][0]] = np.asarray(block, dtype=float).ravel()
    return point


NOT_ROTATIONS = [
    np.diag([1.5, 1.5, 1.0]),                 # |Φ| = 0: a symmetric stretch
    np.diag([0.2, 0.2, 1.0]),
    np.diag([1.0, -1.0, 1.0]),                # a reflection: orthogonal, det −1, positive trace, |Φ| = 0
    np.eye(3) + 1e-8 * np.diag([1.0, 0.0, 0.0]),  # ten times the tolerance
]


@pytest.mark.parametrize("block", NOT_ROTATIONS)
def test_a_ball_joint_block_that_is_no_rotation_does_not_close(block, sr_path):
    mechanism = load(sr_path)
    point = _with_block(mechanism, home(mechanism), "S1", block)
    assert not bool(closes(mechanism, point))
    assert not bool(closes(mechanism, point, np.inf))
    with pytest.raises(ConfigurationError):
        classify(mechanism, point)


def test_the_rotation_tolerance_is_documented():
    assert kinematics.ROTATION_TOLERANCE == 1e-9
    assert "ROTATION_TOLERANCE" in kinematics.closes.__doc__


def test_a_rotation_within_the_tolerance_and_after_many_retractions_closes(sr_path):
    mechanism = load(sr_path)
    point = home(mechanism)
    assert bool(closes(mechanism, _with_block(mechanism, point, "S1", np.eye(3) + 1e-12)))
    ambient = kinematics_of(mechanism).ambient
    step = np.zeros(ambient.dim)
    step[ambient.tangent_slices[1]] = [0.3, -0.2, 0.7]
    moved = point
    for _ in range(10000):
        moved = ambient.retract(ambient.retract(moved, step), -step)
    block = moved[kinematics_of(mechanism).point_parts["S1"][0]].reshape(3, 3)
    assert not np.array_equal(block, np.eye(3))  # the drift is there
    assert bool(closes(mechanism, moved))


def test_batched_closes_equals_single_closes():
    mechanism = gough_stewart()
    compiled = kinematics_of(mechanism)
    start = home(mechanism)
    balls = [joint.name for joint in mechanism.joints if joint.type == "S"]
    assert balls
    points = [start] + [_with_block(mechanism, start, name, block) for name in balls[:3] for block in NOT_ROTATIONS]
    stack = np.array(points).reshape(len(points), 1, -1)
    batched = np.asarray(closes(mechanism, stack))
    assert batched.shape == (len(points), 1)
    single = [bool(closes(mechanism, point)) for point in points]
    assert batched[:, 0].tolist() == single and single[0] and not any(single[1:])
    assert np.asarray(closes(mechanism, np.zeros((0, compiled.point_size)))).shape == (0,)


def test_batched_closes_equals_single_closes_where_phi_vanishes(sr_path):
    """On the coaxial S-R the stretched blocks give Φ = 0 exactly: only the rotation test refuses them."""
    mechanism = load(sr_path)
    start = home(mechanism)
    points = np.array([start] + [_with_block(mechanism, start, "S1", block) for block in NOT_ROTATIONS[:3]])
    assert np.all(np.linalg.norm(constraint(mechanism, points), axis=-1) == 0.0)
    batched = np.asarray(closes(mechanism, points.reshape(2, 2, -1)))
    assert batched.tolist() == [[True, False], [False, False]]
    assert batched.reshape(-1).tolist() == [bool(closes(mechanism, point)) for point in points]
    names, rotations = kinematics.rotation_blocks(mechanism, points)
    assert names == ("S1",) and rotations[:, 0].tolist() == [True, False, False, False]


def test_a_planar_mechanism_without_ball_joints_is_unchanged():
    mechanism = load(SLIDER_CRANK)
    assert AmbientSpace(kinematics_of(mechanism).ambient.factors).factors.count("SO3") == 0
    assert bool(closes(mechanism, home(mechanism)))


@pytest.mark.parametrize("block", NOT_ROTATIONS)
def test_a_block_that_is_no_rotation_is_refused_in_a_stack_too_naming_the_joint(block, sr_path):
    """classify_many decides closure from one expansion of each loop (not from `closes`): it accepted the
    stretched block that classify refuses. Both now refuse it, naming the ball joint."""
    from classify import classify_many

    mechanism = load(sr_path)
    point = _with_block(mechanism, home(mechanism), "S1", block)
    with pytest.raises(ConfigurationError, match="block of ball joint 'S1' is not a rotation"):
        classify(mechanism, point)
    with pytest.raises(ConfigurationError, match="configuration 1: the block of ball joint 'S1' is not a rotation"):
        classify_many(mechanism, np.stack([home(mechanism), point]))
