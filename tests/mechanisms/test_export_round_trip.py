"""The round trip export → import (:mod:`mechanisms.export`, :mod:`mechanisms.urdf`) for every catalogue mechanism
and every named configuration: the URDF's zero configuration is closed, and the first-order picture is the same
(the dimension of ker DΦ, the ranks of the actuator and end-effector maps on it). Full classifications of the
configurations whose verdict rests on the end-effector, carried by the closures file's ``end_effector`` key.

The exporter does not write the end-effector yet (mechanisms/export.py is another module's work): these tests add
to the exported URDF the frame it would write, a fixed leaf link ``end_effector`` at the end-effector's point, and
name it in the closures."""

from collections import deque

import numpy as np
import pytest

from classify import classify
from mechanisms import home
from mechanisms.catalogue import entries, entry
from mechanisms.closures import Closures, closures_from_dict, closures_to_dict
from mechanisms.export import export_urdf
from mechanisms.kinematics import actuator_jacobian, constraint_jacobian, end_effector_jacobian
from mechanisms.urdf import import_tree, retype, tree_from_urdf

pytest.importorskip("yourdfpy")

CONFIGURATIONS = [(item.name, name) for item in entries() for name in (None, *item.configurations)]


def with_end_effector(mechanism, exported):
    """The exported URDF and closures with the mechanism's end-effector as a frame (see the module's note)."""
    effector = mechanism.end_effector
    if effector is None:
        return exported.urdf, exported.closures
    tree = tree_from_urdf(exported.urdf, "exported")
    origins, queue = {tree.root: np.zeros(3)}, deque([tree.root])
    children = {}
    for joint in tree.joints:
        children.setdefault(joint.parent, []).append(joint)
    while queue:  # every link frame of the export is parallel to the ground's: origins add up
        link = queue.popleft()
        for joint in children.get(link, ()):
            origins[joint.child] = origins[link] + joint.placement[:3, 3]
            queue.append(joint.child)
    point = origins[effector.link] if effector.point is None else np.array([*effector.point, 0.0][:3])
    offset = " ".join(repr(float(value)) for value in point - origins[effector.link])
    urdf = exported.urdf.replace("</robot>", f"""  <link name="end_effector" />
  <joint name="end_effector_frame" type="fixed">
    <origin xyz="{offset}" rpy="0 0 0" />
    <parent link="{effector.link}" />
    <child link="end_effector" />
  </joint>
</robot>""")
    closures = exported.closures
    return urdf, Closures(closures.loops, closures.types, closures.actuated, closures.retyped,
                          ("end_effector", effector.output))


def round_trip(mechanism):
    urdf, closures = with_end_effector(mechanism, export_urdf(mechanism))
    closures = closures_from_dict(closures_to_dict(closures))
    return import_tree(retype(tree_from_urdf(urdf, "exported"), closures), closures, mechanism.name)


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
    ("5-spu", None),  # the tool's free spin: an architecture singularity, seen only with the end-effector
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
    from mechanisms import MechanismError

    for bad, message in (({"frame": "tool", "output": "speed"}, "field 'output'"), ({"output": "pose"}, "'frame'"),
                         ({"frame": "tool", "axis": 1}, "unknown key 'axis'"), ("tool", "expected a mapping")):
        with pytest.raises(MechanismError, match=message):
            closures_from_dict({"end_effector": bad}, "c.yaml")
