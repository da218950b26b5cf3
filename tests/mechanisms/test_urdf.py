"""URDF + closures import (:mod:`mechanisms.urdf`, :mod:`mechanisms.closures`): the sample robots of the
Gepetto example-parallel-robots collection assemble, close and classify; Pinocchio agrees on the ranks; bad input
is one line naming the field."""


import numpy as np
import pytest

from classify import classify
from mechanisms import MechanismError, home
from mechanisms.closures import Closures, closures_from_dict, read_closures
from mechanisms.urdf import ASSEMBLY_TOLERANCE, read_urdf
from builders import ROBOTS

#: robot -> (C-space dimension, rank DΦ, motors, idle freedoms); the idle freedom of the 5-bar is the spin of the
#: two coaxial leaf joints welded by its 6d closure; `delta` is hand-made (tests/data/robots/README.md): three
#: translations and the spins of its six rods about their axes
EXPECTED = {"5bar_linkage": (3, 3, 2, 1), "5bar_linkage_iso3d": (2, 6, 2, 0), "battobot_6d": (12, 36, 12, 0),
            "delta": (9, 30, 3, 6)}

pytest.importorskip("yourdfpy")


def robot_files(name):
    return ROBOTS / name / "robot.urdf", ROBOTS / name / "robot.yaml"


@pytest.fixture(scope="module")
def imported():
    return {name: read_urdf(*robot_files(name)) for name in EXPECTED}


@pytest.fixture(scope="module")
def reports(imported):
    return {name: classify(item.mechanism, home(item.mechanism), rng=np.random.default_rng(0))
            for name, item in imported.items()}


@pytest.mark.parametrize("name", list(EXPECTED))
def test_sample_robot_closes_and_classifies(name, imported, reports):
    dimension, rank, motors, idle = EXPECTED[name]
    item, report = imported[name], reports[name]
    assert item.residual <= ASSEMBLY_TOLERANCE and max(item.loop_residuals) <= ASSEMBLY_TOLERANCE
    assert len(item.closures.actuated) == motors
    assert report.dof == dimension
    assert report.cspace.rank == report.cspace.expected_rank == rank
    assert report.actuator.rank == report.actuator.expected_rank == motors
    assert report.kinds == ()
    assert report.idle_freedoms == idle
    assert any("fixed as the ground" in note for note in item.notes)


def test_weld_merges_links_and_ball_closure_is_a_spherical_joint(imported):
    five_bar = imported["5bar_linkage"].mechanism
    assert "sphere_2" not in five_bar.links and "sphere" in five_bar.links
    iso = imported["5bar_linkage_iso3d"].mechanism
    assert [joint.type for joint in iso.joints].count("S") == 1
    battobot = imported["battobot_6d"].mechanism
    types = {joint.name: joint.type for joint in battobot.joints}
    assert types["right_spherical_foot_1"] == "S" and types["free_knee_left"] == "U"
    assert sum(joint.actuated for joint in battobot.joints) == 12


def test_assembly_moves_the_zero_configuration_and_reports_it(imported):
    item = imported["5bar_linkage"]
    assert item.distance > 0.1  # the sample's zero configuration is open
    assert "assembled from the zero configuration" in item.notes[-1]
    assert set(item.values) == {joint.name for joint in item.mechanism.joints}


def pinocchio_model(pin, urdf, closures):
    """Pinocchio's model with the closures file's re-typings, as the collection's own loader builds it."""
    from mechanisms.closures import universal_axes

    model = pin.buildModelFromUrdf(str(urdf))
    rebuilt = pin.Model()
    revolute = (pin.JointModelRX, pin.JointModelRY, pin.JointModelRZ)
    for place, inertia, name, parent, joint in list(zip(model.jointPlacements, model.inertias, model.names,
                                                        model.parents, model.joints))[1:]:
        parent = rebuilt.getJointId(model.names[parent]) if parent else 0
        kind = closures.retyped.get(name)
        if kind == "SPHERICAL":
            joint = pin.JointModelSpherical()
        elif kind is not None and kind.startswith("UJOINT"):
            first, second = universal_axes(kind)
            parent = rebuilt.addJoint(parent, revolute[first](), place, name + "_A")
            place, joint, name = pin.SE3.Identity(), revolute[second](), name + "_B"
        index = rebuilt.addJoint(parent, joint, place, name)
        rebuilt.appendBodyToJoint(index, inertia, pin.SE3.Identity())
    for frame in list(model.frames)[1:]:
        parent = model.names[frame.parentJoint]
        if closures.retyped.get(parent, "").startswith("UJOINT"):
            parent += "_B"
        rebuilt.addFrame(pin.Frame(frame.name, rebuilt.getJointId(parent) if frame.parentJoint else 0,
                                   frame.placement, frame.type), False)
    return rebuilt


def pinocchio_configuration(pin, model, values):
    q = pin.neutral(model)
    for index in range(1, model.njoints):
        name, joint = model.names[index], model.joints[index]
        base = name[:-2] if name[-2:] in ("_A", "_B") and name[:-2] in values else name
        value = values[base]
        if joint.nq == 4:
            q[joint.idx_q:joint.idx_q + 4] = pin.Quaternion(value).coeffs()
        elif isinstance(value, list):
            q[joint.idx_q] = value[0 if name.endswith("_A") else 1]
        else:
            q[joint.idx_q] = value
    return q


def pinocchio_constraint_jacobian(pin, model, q, loops, types):
    """Pinocchio's constraint Jacobian at `q` of the closures (`loops`, `types`), as the collection's loader builds
    them: a RigidConstraintModel per loop (CONTACT_6D or CONTACT_3D, LOCAL), between the two frames' joints. The
    constraint data are placed at `q` (``RigidConstraintModel.calc``) before the Jacobian is taken: fresh data
    hold no contact placements, and getConstraintsJacobian took every 3d contact at the world origin.

    Returns
    -------
    jacobian : ndarray
    data : pinocchio.Data
        Forward kinematics, frames and joint Jacobians at `q`.
    """
    constraints = []
    for (first, second), kind in zip(loops, types):
        frame_a, frame_b = model.frames[model.getFrameId(first)], model.frames[model.getFrameId(second)]
        contact = pin.ContactType.CONTACT_6D if kind == "6d" else pin.ContactType.CONTACT_3D
        constraints.append(pin.RigidConstraintModel(contact, model, frame_a.parentJoint, frame_a.placement,
                                                    frame_b.parentJoint, frame_b.placement, pin.ReferenceFrame.LOCAL))
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    pin.computeJointJacobians(model, data, q)
    constraint_data = [constraint.createData() for constraint in constraints]
    for constraint, placed in zip(constraints, constraint_data):
        constraint.calc(model, data, placed)  # the contact placements oMc1, oMc2 at q (fresh data has none)
    return pin.getConstraintsJacobian(model, data, constraints, constraint_data), data


def pinocchio_rank(jacobian):
    values = np.linalg.svd(jacobian, compute_uv=False)
    return int(np.sum(values > 1e-8 * values[0]))


@pytest.mark.parametrize("name", list(EXPECTED))
def test_pinocchio_constraint_jacobian_rank_agrees(name, imported):
    """Pinocchio's RigidConstraintModel (6D/3D contacts, as the collection's loader builds them) at the imported
    closed configuration: the frames coincide, and rank J_c equals rank DΦ (less the 3 coordinates of the ball
    joint each 3d closure adds here, which Pinocchio does not have), so the C-space dimensions agree."""
    pin = pytest.importorskip("pinocchio")
    urdf, closures_file = robot_files(name)
    closures = read_closures(closures_file)
    item = imported[name]
    model = pinocchio_model(pin, urdf, closures)
    q = pinocchio_configuration(pin, model, item.values)
    jacobian, data = pinocchio_constraint_jacobian(pin, model, q, closures.loops, closures.types)
    for (first, second), kind in zip(closures.loops, closures.types):
        gap = data.oMf[model.getFrameId(first)].inverse() * data.oMf[model.getFrameId(second)]
        error = pin.log6(gap).vector if kind == "6d" else gap.translation
        assert np.linalg.norm(error) < 1e-9
    rank = pinocchio_rank(jacobian)
    dimension, expected_rank, _, _ = EXPECTED[name]
    balls = 3 * closures.types.count("3d")
    assert rank == expected_rank - balls
    assert model.nv - rank == dimension


def test_pinocchio_rank_with_two_3d_closures_between_the_same_links(tmp_path):
    """The iso3d five-bar with a second 3d closure between the same two links, 0.03 apart along the ball's z:
    together a hinge, so one freedom is left (closedchain's dof 1). The recipe called getConstraintsJacobian on
    fresh constraint data, whose contact placements were never set: both contacts were taken at the world
    origin, rank 3 instead of 4."""
    from xml.etree import ElementTree

    pin = pytest.importorskip("pinocchio")
    urdf, closures_file = robot_files("5bar_linkage_iso3d")
    closures = read_closures(closures_file)
    first, second = closures.loops[0]
    item = read_urdf(urdf, closures)
    model = pin.buildModelFromUrdf(str(urdf))
    data = model.createData()
    pin.framesForwardKinematics(model, data, pinocchio_configuration(pin, model, item.values))
    pose_a, pose_b = (data.oMf[model.getFrameId(name)] for name in (first, second))
    offset = np.array([0.0, 0.0, 0.03])
    robot = ElementTree.parse(urdf).getroot()
    for name, parent, point in (("A2", first, offset),
                                ("B2", second, pose_b.actInv(pose_a.act(offset)))):
        ElementTree.SubElement(robot, "link", name=name)
        joint = ElementTree.SubElement(robot, "joint", name=name + "_joint", type="fixed")
        ElementTree.SubElement(joint, "parent", link=parent)
        ElementTree.SubElement(joint, "child", link=name)
        ElementTree.SubElement(joint, "origin", xyz=" ".join(repr(float(value)) for value in point), rpy="0 0 0")
    variant = tmp_path / "robot.urdf"
    ElementTree.ElementTree(robot).write(variant)
    loops, types = ((first, second), ("A2", "B2")), ("3d", "3d")
    twice = read_urdf(variant, Closures(loops, types, closures.actuated))
    report = classify(twice.mechanism, home(twice.mechanism), rng=np.random.default_rng(0))
    assert report.dof == 1
    model = pin.buildModelFromUrdf(str(variant))
    q = pinocchio_configuration(pin, model, twice.values)
    jacobian, _ = pinocchio_constraint_jacobian(pin, model, q, loops, types)
    assert model.nv - pinocchio_rank(jacobian) == report.dof == 1


# ------------------------------------------------------------------------------------------- bad input

FIVE_BAR_URDF = (ROBOTS / "5bar_linkage" / "robot.urdf").read_text()


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("closures, message", [
    ({"closed_loop": [["closedloop1_A", "nowhere"]], "name_mot": ["mot1"]}, "unknown frame 'nowhere'"),
    ({"closed_loop": [["closedloop1_A", "closedloop1_B"]], "name_mot": ["mot9"]},
     "field 'name_mot': item 0: unknown joint 'mot9'"),
    ({"closed_loop": [["closedloop1_A", "closedloop1_B"]], "name_mot": ["effector_frame"]}, "is fixed"),
    ({"closed_loop": [["closedloop1_A", "built"]]}, "the loops cannot be closed"),
    ({"closed_loop": [["closedloop1_A", "closedloop1_B"]], "name_mot": ["ot9"]},
     "field 'name_mot': item 0: unknown joint 'ot9' \\(no joint has that name, and no movable joint's name "
     "contains it"),
])
def test_bad_closures_are_one_line_naming_the_field(tmp_path, closures, message):
    import yaml

    urdf = write(tmp_path, "robot.urdf", FIVE_BAR_URDF)
    with pytest.raises(MechanismError, match=message) as caught:
        read_urdf(urdf, write(tmp_path, "robot.yaml", yaml.safe_dump(closures)))
    assert "\n" not in str(caught.value)


def test_loops_that_cannot_close_are_named(tmp_path):
    import yaml

    urdf = write(tmp_path, "robot.urdf", FIVE_BAR_URDF)
    closures = {"closed_loop": [["closedloop1_A", "closedloop1_B"], ["closedloop1_A", "built"]], "type": ["6d", "6d"]}
    with pytest.raises(MechanismError, match=r"loop 2 \['closedloop1_A', 'built'\]"):
        read_urdf(urdf, write(tmp_path, "robot.yaml", yaml.safe_dump(closures)))


@pytest.mark.parametrize("data, message", [
    ([1, 2], "expected a mapping"),
    ({"closed_loop": [["a"]]}, "field 'closed_loop': item 0: expected a pair"),
    ({"closed_loop": [["a", "b"]], "type": ["4d"]}, "field 'type': item 0: expected 6d or 3d"),
    ({"closed_loop": [["a", "b"]], "type": ["6d", "3d"]}, "field 'type': expected 1 types"),
    ({"joint_name": ["a"], "joint_type": ["HINGE"]}, "field 'joint_type': item 0"),
    ({"joint_name": ["a"]}, "field 'joint_type': expected 1 types"),
    ({"name_mot": {"mot1": 1}}, "field 'name_mot': expected a list"),
    ({"rotule_name": ["to_rotule"]}, "field 'rotule_name'"),
    ({1: "a"}, "key 1: expected a text key"),
    ({"name": "five-bar", "joints": [], "end_effector": {"link": "a"}},
     "not a closures file: it has keys 'name', 'joints' and none of closed_loop, type, name_mot"),
])
def test_closures_file_of_the_wrong_shape(data, message):
    with pytest.raises(MechanismError, match=message):
        closures_from_dict(data, "c.yaml")


def test_closures_types_default_to_6d_and_read_case_insensitively():
    closures = closures_from_dict({"closed_loop": [["a", "b"], ["c", "d"]], "type": ["3D", "6d"]})
    assert closures.types == ("3d", "6d")
    assert closures_from_dict({"closed_loop": [["a", "b"]]}).types == ("6d",)
    assert closures_from_dict({"joint_name": ["j"], "joint_type": ["CARDAN"]}).retyped == {"j": "UJOINT_XY"}


@pytest.mark.parametrize("edit, message", [
    (lambda text: text.replace('<parent link="rod" />', '<parent link="rodd" />'), "unknown link 'rodd'"),
    (lambda text: text.replace('<child link="rod_3" />', '<child link="rod" />'), "already has the parent joint"),
    (lambda text: text.replace("</robot>", "<joint name='loop' type='fixed'><parent link='rod'/>"
                                           "<child link='built'/></joint></robot>"), "cycle"),
    (lambda text: text[:len(text) // 2], "URDF: cannot parse"),
    (lambda text: '<!DOCTYPE r [<!ENTITY e SYSTEM "file:///etc/passwd">]>' + text, "DOCTYPE"),
    # after a long comment: only the first 4096 characters were read, and its ATTLIST defaults filled in axes
    (lambda text: text.replace('<robot name="onshape">', "<!--" + " " * 4100 + '-->\n<!DOCTYPE robot '
                               '[<!ATTLIST axis xyz CDATA "0 0 1">]>\n<robot name="onshape">', 1), "DOCTYPE"),
    (lambda text: text.replace('type="revolute"', 'type="planar"', 1), "'planar' joint is not supported"),
    # the parser's own words named no element: 'could not broadcast…', 'could not convert string to float', 'name'
    (lambda text: text.replace('<origin xyz="0 0 0" rpy="0 -0 0" />', '<origin xyz="0.1 0.15" />', 1),
     "<link> 'built': <origin xyz='0.1 0.15'>: expected three numbers"),
    (lambda text: text.replace('<axis xyz="0 0 1" />', '<axis xyz="a b c" />', 1),
     "<joint> '[^']+': <axis xyz='a b c'>: expected three numbers"),
    (lambda text: text.replace('<robot name="onshape">', '<robot>', 1), "<robot>: attribute 'name' is missing"),
    # overflow warnings, then the closures file blamed for loops that could not close
    (lambda text: text.replace('<origin xyz="0 0 0" rpy="0 -0 0" />', '<origin xyz="1e300 0 0" />', 1),
     "<origin xyz='1e300 0 0'>: a number beyond ±1e\\+12"),
    # deeper than the parser reads: it recovered with what it had read and said "URDF: no link"
    (lambda text: text.replace('<robot name="onshape">', '<robot name="onshape">' + "<a>" * 300 + "</a>" * 300, 1),
     "nested more than 256 deep"),
    # a numeral that overflows (not the word inf): let through, then trimesh's warnings and "not a finite pose"
    (lambda text: text.replace('<origin xyz="0 0 0" rpy="0 -0 0" />', '<origin xyz="1e400 0 0" />', 1),
     "<origin xyz='1e400 0 0'>: a number beyond ±1e\\+12"),
    (lambda text: text.replace('<origin xyz="0 0 0" rpy="0 -0 0" />', '<origin xyz="0&#10;x 0" />', 1),
     "<origin xyz='0\\\\nx 0'>: expected three numbers"),  # one line: the newline escaped
])
def test_malformed_urdf_is_one_line(tmp_path, edit, message):
    urdf = write(tmp_path, "robot.urdf", edit(FIVE_BAR_URDF))
    with pytest.raises(MechanismError, match=message) as caught:
        read_urdf(urdf, Closures())
    assert "\n" not in str(caught.value)


def test_joint_names_resolve_to_their_child_frames(tmp_path):
    """As Pinocchio's getFrameId: the joint 'closedloop1_A' and its child link 'sphere' are one frame."""
    urdf, closures_file = robot_files("5bar_linkage")
    by_links = read_urdf(urdf, Closures((("sphere", "sphere_2"),), ("6d",), ("mot1", "mot2")))
    by_joints = read_urdf(urdf, closures_file)
    assert np.allclose([joint.point for joint in by_links.mechanism.joints],
                       [joint.point for joint in by_joints.mechanism.joints])


@pytest.mark.parametrize("kind", ["3d", "6d"])
def test_a_closure_within_one_rigid_link_is_left_out_and_said_so(kind):
    """The joint 'closedloop1_A' and its child link 'sphere' are one frame: a closure between them constrains
    nothing. The 3d case said so in the notes; the 6d one was dropped without a word."""
    closures = closures_from_dict({"closed_loop": [["closedloop1_A", "sphere"]], "type": [kind]})
    imported = read_urdf(ROBOTS / "5bar_linkage" / "robot.urdf", closures)
    assert imported.mechanism.loop_count == 0
    assert f"{kind} closure ['closedloop1_A', 'sphere'] joins one rigid link: left out" in imported.notes


def test_a_floating_base_retyped_is_not_said_to_be_held_fixed(tmp_path):
    """A closures file may re-type the floating base (here SPHERICAL: three coordinates); the notes still said
    it was held fixed."""
    import dataclasses

    text = FIVE_BAR_URDF.replace('<robot name="onshape">', '<robot name="onshape"><link name="world"/><joint '
                                 'name="fl" type="floating"><parent link="world"/><child link="built"/></joint>', 1)
    closures = read_closures(ROBOTS / "5bar_linkage" / "robot.yaml")
    held = read_urdf(write(tmp_path, "held.urdf", text), closures)
    assert "floating joint 'fl' (the floating base) held fixed" in held.notes
    turned = read_urdf(write(tmp_path, "turned.urdf", text), dataclasses.replace(closures, retyped={"fl": "SPHERICAL"}))
    assert "floating joint 'fl' (the floating base) re-typed SPHERICAL by the closures file" in turned.notes
    assert not any("held fixed" in note and "'fl'" in note for note in turned.notes)
    assert turned.mechanism.joint("fl").type == "S"
