"""The whole closures convention on hand-made robots (tests/data/robots/README.md), not only the three samples: a
Delta of ball-jointed parallelograms, a legged robot's knee linkage with a floating base, a universal-joint and a
FIXED re-typing, a mimic joint and a dangling foot, loops that cannot close; URDF files the parser refuses, and
MJCF elements that are not loop closures. Every refusal is one line naming the joint, element or loop."""

import re
import shutil

import numpy as np
import pytest

from classify import classify
from classify.cli import main
from mechanisms import MechanismError, assemble, home
from mechanisms.kinematics import link_pose
from mechanisms.urdf import ASSEMBLY_TOLERANCE, read_urdf
from builders import ROBOTS


pytest.importorskip("yourdfpy")


def robot_files(name):
    return ROBOTS / name / "robot.urdf", ROBOTS / name / "robot.yaml"


@pytest.fixture(scope="module")
def delta():
    return read_urdf(*robot_files("delta"))


@pytest.fixture(scope="module")
def leg():
    return read_urdf(*robot_files("leg_floating"))


def test_delta_platform_only_translates(delta):
    """Three ball-jointed parallelograms keep the platform's orientation: a motor turned by 0.2 rad moves the
    platform without turning it (the Delta's design principle), and the six rod spins are idle."""
    mechanism = delta.mechanism
    assert delta.distance > 0.05 and delta.residual <= ASSEMBLY_TOLERANCE  # the platform was turned at zero
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert (report.dof, report.idle_freedoms, report.actuator.rank, report.kinds) == (9, 6, 3, ())
    rod = link_pose(mechanism, "rod_1a", home(mechanism))
    before = link_pose(mechanism, "platform", home(mechanism))
    moved = assemble(mechanism, {"motor_1": 0.2}).point
    after = link_pose(mechanism, "platform", moved)
    assert np.linalg.norm(after[:3, 3] - before[:3, 3]) > 0.01
    assert np.allclose(after[:3, :3], before[:3, :3], atol=1e-8)
    assert not np.allclose(link_pose(mechanism, "rod_1a", moved)[:3, :3], rod[:3, :3], atol=1e-3)  # rods turn


def test_legged_robot_fixes_its_floating_base_and_says_so(leg):
    notes = " | ".join(leg.notes)
    assert "base link 'world' fixed as the ground" in notes
    assert "floating joint 'root_joint' (the floating base) held fixed" in notes
    assert "joints on no loop left out (each adds free coordinates): toe" in notes
    assert "<mimic> joints on no loop, left out with their coupling: toe" in notes


def test_legged_robot_retypings_and_ball_closure(leg):
    mechanism = leg.mechanism
    types = {joint.name: joint.type for joint in mechanism.joints}
    assert types == {"hip": "R", "knee_motor": "R", "knee": "R", "rod_joint": "U", "rod_end--shin_anchor": "S"}
    assert "ankle" not in types  # re-typed FIXED: the foot is part of the shin
    universal = mechanism.joint("rod_joint")
    assert np.allclose(np.abs(universal.axes[0]), [0, 1, 0]) and abs(np.dot(*universal.axes)) < 1e-12
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert (report.dof, report.cspace.rank, report.actuator.rank, report.idle_freedoms, report.kinds) == \
        (2, 6, 2, 0, ())


def test_legged_robot_agrees_with_pinocchio(leg):
    """Pinocchio reads the floating joint as a free flyer: its constraint Jacobian has the same rank (less the
    ball's 3 coordinates, which it does not have), and the free flyer's 6 freedoms come on top."""
    pin = pytest.importorskip("pinocchio")
    from mechanisms.closures import read_closures
    from tests.mechanisms.test_urdf import pinocchio_constraint_jacobian, pinocchio_model, pinocchio_rank

    urdf, closures_file = robot_files("leg_floating")
    closures = read_closures(closures_file)
    model = pinocchio_model(pin, urdf, closures)
    values = {**leg.values, "root_joint": None, "toe": 0.0, "ankle": 0.0}
    q = pin.neutral(model)
    for index in range(1, model.njoints):
        name, joint = model.names[index], model.joints[index]
        base = name[:-2] if name[-2:] in ("_A", "_B") and name[:-2] in values else name
        if values.get(base) is None:
            continue
        value = values[base]
        q[joint.idx_q] = value[0 if name.endswith("_A") else 1] if isinstance(value, list) else value
    jacobian, data = pinocchio_constraint_jacobian(pin, model, q, closures.loops[:1], ["3d"])
    gap = data.oMf[model.getFrameId(closures.loops[0][0])].translation - \
        data.oMf[model.getFrameId(closures.loops[0][1])].translation
    assert np.linalg.norm(gap) < 1e-9
    rank = pinocchio_rank(jacobian)
    assert rank == 6 - 3
    # free flyer 6 + hip, knee, knee_motor, U (2), ankle, toe: the ankle and toe move freely in Pinocchio's model
    assert model.nv - rank == 6 + 2 + 2


def run(arguments, capsys):
    status = main(arguments)
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_loops_that_cannot_close_exit_2_naming_the_open_loop_only(capsys):
    urdf, closures = robot_files("cannot_close")
    status, out, err = run(["classify", str(urdf), "--closures", str(closures)], capsys)
    assert status == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert "the loops cannot be closed" in err
    assert "loop 1" not in err
    named = re.search(r"loop 2 \['coupler_tip', 'follower_tip'\] residual ([0-9.]+)", err)
    # the four-bar's pivots are 1.0 apart and its links reach 0.5 at most: its gap is 0.5 or more, over the tree's
    # characteristic length (the ground's pivots are 1.118 apart), wherever Gauss-Newton stalls
    assert named and float(named.group(1)) >= 0.5 / np.hypot(1.0, 0.5) - 1e-3


def test_the_legged_robot_converts_and_draws(tmp_path, capsys):
    urdf, closures = robot_files("leg_floating")
    status, out, err = run(["convert", str(urdf), "--closures", str(closures), "--write", str(tmp_path / "leg.yaml")],
                           capsys)
    assert status == 0, err
    assert "imported: floating joint 'root_joint' (the floating base) held fixed" in out
    status, out, err = run(["draw", str(urdf), "--closures", str(closures), "--out", str(tmp_path / "leg.png")],
                           capsys)
    assert status == 0, err
    assert (tmp_path / "leg.png").read_bytes().startswith(b"\x89PNG")
    from mechanisms.io import read

    converted = read(tmp_path / "leg.yaml")
    assert "floating joint 'root_joint'" in converted.description
    assert {joint.name for joint in converted.mechanism.joints} == {joint.name for joint in
                                                                      read_urdf(urdf, closures).mechanism.joints}


def test_a_urdf_saved_as_xml_is_read_as_a_urdf(tmp_path):
    """``import_file`` reads a ``.xml`` file whose root element is ``<robot>`` as a URDF, any other as MJCF."""
    from classify.cli._common import import_file
    from mechanisms.urdf import looks_like_urdf

    urdf, closures = robot_files("leg_floating")
    shutil.copy(urdf, tmp_path / "leg.xml")
    assert looks_like_urdf(tmp_path / "leg.xml")
    assert not looks_like_urdf(ROBOTS / "five_bar_mjcf" / "model.xml")  # a leading comment, then <mujoco>
    assert import_file(tmp_path / "leg.xml", closures).closures.actuated == ("hip", "knee_motor")


LEG = (ROBOTS / "leg_floating" / "robot.urdf").read_text()


@pytest.mark.parametrize("edit, message", [
    (lambda text: text.replace('<joint name="knee" type="revolute">', '<joint name="knee" type="floating">'),
     "joint 'knee': field 'type': a floating joint inside the tree (its parent 'thigh' is not the base link"),
    (lambda text: text.replace('<joint name="knee" type="revolute">', '<joint name="knee" type="planar">'),
     "joint 'knee': field 'type': a 'planar' joint is not supported"),
    (lambda text: text.replace('<parent link="thigh"/><child link="shin"/>',
                               '<parent link="thigh"/><child link="shin"/><mimic joint="hip"/>'),
     "joint 'knee': a <mimic> joint on a loop is not supported"),
    (lambda text: text.replace('<parent link="crank"/>', ''), "<joint> 'rod_joint': <parent link=\"...\"/> is missing"),
    (lambda text: text.replace('<link name="rod"/>', '<link/>'), "a <link>: attribute 'name' is missing"),
    (lambda text: text.replace('xyz="0 0 -0.4"', 'xyz="0 0 ${-thigh}"', 1), "a xacro file"),
    (lambda text: text.replace("<robot ", "<sdf ").replace("</robot>", "</sdf>"), "the root element is <sdf>"),
    (lambda text: text.replace("</robot>", ""), "not well-formed XML"),
    (lambda text: text.replace('xyz="0 0 -0.4"', 'xyz="0 0 nan"', 1), "joint 'knee': field 'origin': not a finite"),
])
def test_urdf_refusals_are_one_line_naming_the_element(tmp_path, edit, message):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(edit(LEG))
    with pytest.raises(MechanismError) as caught:
        read_urdf(urdf, ROBOTS / "leg_floating" / "robot.yaml")
    assert message in str(caught.value) and "\n" not in str(caught.value)


def test_meshes_that_do_not_exist_are_never_loaded(leg):
    assert "meshes/thigh.dae" in LEG and not (ROBOTS / "leg_floating" / "meshes").exists()
    assert leg.residual <= ASSEMBLY_TOLERANCE


SLIDER_CRANK = """<mujoco model="slider-crank">
  <worldbody>
    <body name="crank">
      <joint name="crank_joint" type="hinge" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01"/>
      <body name="rod" pos="0.1 0 0">
        <joint name="pin" type="hinge" axis="0 0 1"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.01"/>
        <site name="rod_end" pos="0.3 0 0"/>
      </body>
    </body>
    <body name="slider" pos="0.4 0 0">
      <joint name="slide" type="slide" axis="1 0 0"/>
      <joint name="wrist" type="hinge" axis="0 0 1"/>
      <geom type="box" size="0.02 0.02 0.02"/>
      <site name="slider_pin"/>
    </body>
  </worldbody>
  <tendon><fixed name="coupling"><joint joint="pin" coef="1"/></fixed></tendon>
  <equality>EQUALITY</equality>
  <actuator><motor joint="crank_joint"/><motor name="on_tendon" tendon="coupling"/></actuator>
</mujoco>
"""


def test_mjcf_slider_crank_with_a_site_weld_and_a_tendon_actuator(tmp_path):
    """Two joints in one body (slide, then wrist) are chained; a weld of two sites is a 6d closure; an actuator on
    a tendon is named in the notes and not counted."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "slider.xml"
    path.write_text(SLIDER_CRANK.replace("EQUALITY", '<weld site1="rod_end" site2="slider_pin"/>'))
    imported = read_mjcf(path)
    assert imported.closures.types == ("6d",) and imported.closures.actuated == ("crank_joint",)
    assert any("drive no joint" in note and "on_tendon" in note for note in imported.notes)
    types = {joint.name: joint.type for joint in imported.mechanism.joints}
    assert types == {"crank_joint": "R", "pin": "R", "slide": "P", "wrist": "R"}
    report = classify(imported.mechanism, home(imported.mechanism), rng=np.random.default_rng(0))
    assert (report.dof, report.actuator.rank, report.kinds) == (1, 1, ())


def test_mjcf_joint_equality_is_refused_naming_it(tmp_path):
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "coupled.xml"
    path.write_text(SLIDER_CRANK.replace("EQUALITY", '<joint name="gear" joint1="pin" joint2="wrist"/>'))
    with pytest.raises(MechanismError, match="equality 'gear': a joint equality is not supported") as caught:
        read_mjcf(path)
    assert "\n" not in str(caught.value)
