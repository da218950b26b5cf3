"""The round trip export → import (:mod:`mechanisms.export`, :mod:`mechanisms.urdf`) for every catalogue mechanism
and every named configuration: the URDF's zero configuration is closed, and the first-order picture is the same
(the dimension of ker DΦ, the ranks of the actuator and end-effector maps on it). Full classifications of the
configurations whose verdict rests on the end-effector, carried by the closures file's ``end_effector`` key (a
fixed leaf link at the end-effector's point; a ``tool``'s axis with it)."""

from xml.etree import ElementTree

import numpy as np
import pytest

from classify import classify
from mechanisms import home
from mechanisms.catalogue import entries, entry
from mechanisms.closures import closures_from_dict, closures_to_dict
from mechanisms.export import export_urdf
from mechanisms.kinematics import actuator_jacobian, constraint_jacobian, end_effector_jacobian
from mechanisms.urdf import import_tree, retype, tree_from_urdf

pytest.importorskip("yourdfpy")

CONFIGURATIONS = [(item.name, name) for item in entries() for name in (None, *item.configurations)]


def round_trip(mechanism):
    exported = export_urdf(mechanism)
    closures = closures_from_dict(closures_to_dict(exported.closures))
    return import_tree(retype(tree_from_urdf(exported.urdf, "exported"), closures), closures, mechanism.name)


def first_order(mechanism, point):
    """(dim ker DΦ, rank of the actuators on it, rank of the end-effector on it) at a point; a singular value
    counts when above 1e-8 of the largest of the whole map (DΦ, the actuator or the end-effector Jacobian), the
    kernel's basis being orthonormal."""
    def rank(matrix, scale):
        values = np.linalg.svd(matrix, compute_uv=False) if matrix.size else np.zeros(0)
        return int(np.sum(values > 1e-8 * scale))

    jacobian = constraint_jacobian(mechanism, point)
    _, _, right = np.linalg.svd(jacobian)
    kernel = right[rank(jacobian, np.linalg.norm(jacobian, 2)):].T
    actuator = actuator_jacobian(mechanism)
    actuators = rank(actuator @ kernel, np.linalg.norm(actuator, 2))
    effector = None
    if mechanism.end_effector is not None:
        output = end_effector_jacobian(mechanism, point)
        effector = rank(output @ kernel, np.linalg.norm(output, 2))
    return kernel.shape[1], actuators, effector


@pytest.mark.parametrize("name, configuration", CONFIGURATIONS)
def test_every_catalogue_configuration_round_trips_to_first_order(name, configuration):
    item = entry(name)
    mechanism = item.assemble(item.values(configuration))
    imported = round_trip(mechanism)
    assert imported.distance < 1e-9 and imported.residual < 1e-9  # exported at home: the zero closes
    again = imported.mechanism
    assert (again.end_effector is None) == (mechanism.end_effector is None)
    assert first_order(again, home(again)) == first_order(mechanism, home(mechanism))


def summary(report):
    return (report.dof, report.kinds, report.idle_freedoms, report.architecture_singular, report.actuator.rank,
            report.actuator.expected_rank, report.degeneracy,
            None if report.end_effector is None else (report.end_effector.rank, report.end_effector.expected_rank))


@pytest.mark.parametrize("name, configuration", [
    ("slider-crank", "fig3c_dead_centre"),  # an end-effector singularity (Park & Kim 1999, Fig. 3c)
    ("5-spu", "eq33_w_zero"),  # a tool output (Borràs, Thomas & Torras 2011, eq. 33), its spin an idle freedom
    ("gough-stewart", "eq87_parallel_legs"),  # an idle freedom that moves the end-effector (Park & Kim 1999, eq. 87)
    ("spherical-3rrr", "eq70_leg1_extended"),  # an orientation end-effector (Gosselin & Angeles 1990, eq. 70)
])
def test_end_effector_verdicts_survive_the_round_trip(name, configuration):
    item = entry(name)
    mechanism = item.assemble(item.values(configuration))
    again = round_trip(mechanism).mechanism
    original = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    reached = classify(again, home(again), rng=np.random.default_rng(0))
    assert summary(reached) == summary(original)
    assert original.kinds  # each case is singular: the round trip must keep a verdict, not only `regular`


def test_end_effector_key_is_read_and_checked():
    data = {"closed_loop": [["a", "b"]], "end_effector": {"frame": "tool", "output": "pose"}}
    assert closures_from_dict(data).end_effector == ("tool", "pose")
    assert closures_from_dict({"end_effector": {"frame": "tool"}}).end_effector == ("tool", "position")
    tool = closures_from_dict({"end_effector": {"frame": "spindle", "output": "tool", "axis": [0, 0, 2]}})
    assert (tool.end_effector, tool.end_effector_axis) == (("spindle", "tool"), (0.0, 0.0, 2.0))
    assert closures_from_dict(closures_to_dict(tool)) == tool
    from mechanisms import MechanismError

    for bad, message in (({"frame": "tool", "output": "speed"}, "field 'output'"), ({"output": "pose"}, "'frame'"),
                         ({"frame": "tool", "axis": [0, 0, 1]}, "only a 'tool' output has an axis"),
                         ({"frame": "tool", "output": "tool"}, "'axis': missing"),
                         ({"frame": "tool", "output": "tool", "axis": [0, 0]}, "three numbers"),
                         ({"frame": "tool", "output": "tool", "axis": [0, 0, 0]}, "not all zero"),
                         ({"frame": "tool", "output": "tool", "axis": [0, "1", 0]}, "three numbers"),
                         ({"frame": "tool", "gripper": 1}, "unknown key 'gripper'"), ("tool", "expected a mapping")):
        with pytest.raises(MechanismError, match=message):
            closures_from_dict({"end_effector": bad}, "c.yaml")


def test_a_tool_axis_is_read_in_its_frame_coordinates():
    """The closures' ``axis`` is in the frame's coordinates: a frame turned by a quarter turn about x, given the
    axis turned back, gives the same tool (Borràs, Thomas & Torras 2011: the 5-SPU's tool)."""
    item = entry("5-spu")
    mechanism = item.assemble(item.values(None))
    exported = export_urdf(mechanism)
    frame = exported.closures.end_effector[0]
    robot = ElementTree.fromstring(exported.urdf)
    robot.find(f"joint[@name='{frame}_frame']/origin").set("rpy", "1.5707963267948966 0 0")
    turned = ElementTree.tostring(robot, encoding="unicode")
    x, y, z = mechanism.end_effector.axis
    data = closures_to_dict(exported.closures)
    data["end_effector"]["axis"] = [x, z, -y]  # R_x(90°)ᵀ · axis
    closures = closures_from_dict(data)
    imported = import_tree(retype(tree_from_urdf(turned, "turned"), closures), closures, "turned").mechanism
    axis = np.asarray(imported.end_effector.axis)
    np.testing.assert_allclose(axis / np.linalg.norm(axis), np.asarray(mechanism.end_effector.axis)
                               / np.linalg.norm(mechanism.end_effector.axis), atol=1e-12)
    np.testing.assert_allclose(imported.end_effector.point, mechanism.end_effector.point, atol=1e-12)
