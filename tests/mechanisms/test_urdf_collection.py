"""What trying the real robots of the Gepetto ``example-parallel-robots`` collection taught the importer, each on a
hand-made reproduction (our own URDF text; the collection's files are not shipped, see docs/robots.rst):

- the older closures files (``name_mot: mot`` as one name pattern, ``rotule_name`` re-typing every joint whose name
  contains it as a ball joint, ``Lidmot``/``Lidvmot`` indices) read as that collection's loader reads them;
- ``name_mot`` entries matched as its ``ActuationModel`` matches them (``entry in name``) when they name no joint;
- keys not read, and ``joint_name`` entries that name no joint, are skipped as its loader skips them, but said;
- a humanoid whose legs carry the loops (ball joints written as three revolutes, 3d closures on fixed joints' frames,
  dangling arms, a head and grippers with ``<mimic>`` joints) imports and classifies in seconds;
- a URDF with two links of one name is refused in one line.
"""

import dataclasses

import numpy as np
import pytest

from classify import classify
from classify.cli import main
from mechanisms import MechanismError, home
from mechanisms.closures import closures_from_dict, read_closures
from mechanisms.urdf import ASSEMBLY_TOLERANCE, read_urdf
from builders import ROBOTS

WALKER = ROBOTS / "legacy_walker" / "robot.urdf"
WALKER_CLOSURES = ROBOTS / "legacy_walker" / "robot.yaml"

pytest.importorskip("yourdfpy")


@pytest.fixture(scope="module")
def walker():
    return read_urdf(WALKER, WALKER_CLOSURES)


def write_closures(tmp_path, data):
    import yaml

    path = tmp_path / "closures.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_older_closures_file_reads_as_the_collections_older_loader(walker):
    """``name_mot: mot`` actuates the movable joints whose names contain "mot" (not the fixed bracket), ``rotule_name``
    turns both rod-end revolutes into ball joints, the unused index lists are named as ignored; the leg closes from
    its open zero configuration and has the hip, the knee linkage and the rod's idle spin."""
    notes = " | ".join(walker.notes)
    assert "key(s) 'Lidmot', 'Lidvmot' not read" in notes
    assert "name_mot 'mot' names no joint: read as a pattern" in notes and "mot_hip, mot_crank" in notes
    assert "rotule_name 'to_rotule': joints re-typed SPHERICAL (their names contain it): to_rotule_crank, " \
           "to_rotule_shin" in notes
    mechanism = walker.mechanism
    types = {joint.name: (joint.type, joint.actuated) for joint in mechanism.joints}
    assert types == {"mot_hip": ("R", True), "mot_crank": ("R", True), "free_knee": ("R", False),
                     "to_rotule_crank": ("S", False), "to_rotule_shin": ("S", False)}
    assert walker.distance > 0.1 and walker.residual <= ASSEMBLY_TOLERANCE
    report = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    assert (report.dof, report.actuator.rank, report.idle_freedoms, report.kinds) == (3, 2, 1, ())


def test_older_file_and_listed_names_give_the_same_robot(walker, tmp_path):
    """The same closures written the current way (motors listed, joints re-typed by name) give the same closed
    configuration and the same classification: the older keys are read, not guessed."""
    listed = write_closures(tmp_path, {
        "closed_loop": [["fermeture1_B", "fermeture1_A"]], "type": ["6d"], "name_mot": ["mot_hip", "mot_crank"],
        "joint_name": ["to_rotule_crank", "to_rotule_shin"], "joint_type": ["SPHERICAL", "SPHERICAL"]})
    current = read_urdf(WALKER, listed)
    assert not any("pattern" in note or "not read" in note for note in current.notes)
    assert np.allclose(home(current.mechanism), home(walker.mechanism), atol=1e-12)
    first, second = (classify(imported.mechanism, home(imported.mechanism), rng=np.random.default_rng(0))
                     for imported in (walker, current))
    assert (first.dof, first.actuator.rank, first.idle_freedoms) == (second.dof, second.actuator.rank,
                                                                      second.idle_freedoms)
    assert np.allclose(first.actuator.decision.singular_values, second.actuator.decision.singular_values,
                       rtol=1e-9)


@pytest.mark.parametrize("entries, motors, pattern", [
    (["mot_crank"], {"mot_crank"}, False),               # an exact name names that joint alone
    (["hip"], {"mot_hip"}, True),                        # no joint of that name: the joints containing it
    (["mot", "mot_hip"], {"mot_hip", "mot_crank"}, True),  # a joint selected twice is one motor
])
def test_name_mot_entries_exact_or_contained(tmp_path, entries, motors, pattern):
    closures = write_closures(tmp_path, {"closed_loop": [["fermeture1_B", "fermeture1_A"]], "name_mot": entries,
                                         "rotule_name": "to_rotule"})
    imported = read_urdf(WALKER, closures)
    assert {joint.name for joint in imported.mechanism.joints if joint.actuated} == motors
    assert any("read as a pattern" in note for note in imported.notes) == pattern


@pytest.mark.parametrize("entry, message", [
    ("bracket", "item 0: unknown joint 'bracket' \\(no joint has that name, and no movable joint's name contains it"),
    ("mot_bracket", "item 0: joint 'mot_bracket' is fixed and cannot be actuated"),
    ("crank", "item 0: joint 'to_rotule_crank' is spherical and cannot be actuated"),  # and 'mot_crank'
    ("rotule", "item 0: joint 'to_rotule_(crank|shin)' is spherical and cannot be actuated"),
])
def test_name_mot_entries_that_select_nothing_to_drive_are_refused(tmp_path, entry, message):
    closures = write_closures(tmp_path, {"closed_loop": [["fermeture1_B", "fermeture1_A"]], "name_mot": [entry],
                                         "rotule_name": "to_rotule"})
    with pytest.raises(MechanismError, match=message) as caught:
        read_urdf(WALKER, closures)
    assert "\n" not in str(caught.value) and "field 'name_mot'" in str(caught.value)


def test_keys_not_read_and_stale_retypings_are_said_not_refused(tmp_path):
    """The collection's loader ignores keys it does not use and re-types only the joints that exist; so does the
    importer, naming what it skipped (a stale ``joint_name`` from another version of the URDF, say)."""
    data = {"closed_loop": [["fermeture1_B", "fermeture1_A"]], "name_mot": ["mot_hip", "mot_crank"],
            "joint_name": ["to_rotule_crank", "to_rotule_shin", "foot_free_joint"],
            "joint_type": ["SPHERICAL", "SPHERICAL", "SPHERICAL"], "comment": "from another tool"}
    closures = closures_from_dict(data, "c.yaml")
    assert closures.notes == ("closures file: key(s) 'comment' not read (only closed_loop, type, name_mot, "
                              "joint_name, joint_type, end_effector, rotule_name are), ignored as the collection's "
                              "loaders ignore them",)
    imported = read_urdf(WALKER, closures)
    notes = " | ".join(imported.notes)
    assert "key(s) 'comment' not read" in notes
    assert "joint_name 'foot_free_joint': no joint of that name, re-typing not applied" in notes
    assert imported.mechanism.joint("to_rotule_shin").type == "S"


def test_closures_file_round_trips_the_older_keys():
    from mechanisms.closures import closures_to_dict

    closures = read_closures(WALKER_CLOSURES)
    assert (closures.actuated, closures.spherical_pattern) == (("mot",), "to_rotule")
    again = closures_from_dict(closures_to_dict(closures))
    assert (again.actuated, again.spherical_pattern, again.loops) == (("mot",), "to_rotule", closures.loops)


def test_older_walker_agrees_with_pinocchio(walker):
    """The older loader's model (every "to_rotule" joint spherical, 6D contact between the two fermeture frames):
    the closure gap is zero at the imported configuration and its constraint Jacobian leaves as many freedoms as
    the imported C-space has."""
    pin = pytest.importorskip("pinocchio")
    from tests.mechanisms.test_urdf import (pinocchio_configuration, pinocchio_constraint_jacobian, pinocchio_model,
                                            pinocchio_rank)

    closures = read_closures(WALKER_CLOSURES)
    spherical = {name: "SPHERICAL" for name in ("to_rotule_crank", "to_rotule_shin")}
    model = pinocchio_model(pin, WALKER, dataclasses.replace(closures, retyped=spherical))
    q = pinocchio_configuration(pin, model, walker.values)
    jacobian, data = pinocchio_constraint_jacobian(pin, model, q, closures.loops[:1], ["6d"])
    placed = [data.oMf[model.getFrameId(name)] for name in closures.loops[0]]
    assert np.linalg.norm(pin.log(placed[0].inverse() * placed[1]).vector) < 1e-9
    rank = pinocchio_rank(jacobian)
    assert model.nv - rank == classify(walker.mechanism, home(walker.mechanism), rng=np.random.default_rng(0)).dof


# ------------------------------------------------------------------------------------------- a humanoid, hand-made

def _joint(name, kind, parent, child, xyz=(0, 0, 0), rpy=(0, 0, 0), axis=(1, 0, 0), mimic=None):
    text = (f'<joint name="{name}" type="{kind}"><origin xyz="{" ".join(map(str, xyz))}" '
            f'rpy="{" ".join(map(str, rpy))}"/><parent link="{parent}"/><child link="{child}"/>')
    if kind != "fixed":
        text += f'<axis xyz="{" ".join(map(str, axis))}"/><limit lower="-3" upper="3" effort="1" velocity="1"/>'
    if mimic:
        text += f'<mimic joint="{mimic}" multiplier="-1"/>'
    return text + "</joint>"


def humanoid_urdf():
    """A humanoid in the layout of the collection's two-legged Talos (our own text and numbers): a torso, a head,
    two 7-joint arms with grippers whose fingers mimic the gripper joint, and two legs whose ankle pitch is driven
    from a knee crank through a rod, the rod's foot end a ball written as three revolutes about x, y, z, its knee
    end a ``3d`` closure between two fixed joints' frames."""
    joints = [_joint("waist_yaw", "revolute", "base", "waist", (0, 0, 0.07), axis=(0, 0, 1)),
              _joint("waist_pitch", "revolute", "waist", "chest", axis=(0, 1, 0)),
              _joint("neck_pitch", "revolute", "chest", "neck", (0.02, 0, 0.32), axis=(0, 1, 0)),
              _joint("neck_yaw", "revolute", "neck", "head", axis=(0, 0, 1)),
              _joint("camera_mount", "fixed", "head", "camera", (0.06, 0, 0.2))]
    for side, sign in (("left", 1), ("right", -1)):
        arm = [("chest", (0, sign * 0.16, 0.23), (0, 0, 1)), (None, (0.005, sign * 0.14, 0.05), (1, 0, 0)),
               (None, (0, 0, 0), (0, 0, 1)), (None, (0.02, 0, -0.27), (0, 1, 0)), (None, (-0.02, 0, -0.26), (0, 0, 1)),
               (None, (0, 0, 0), (1, 0, 0)), (None, (0, 0, 0), (0, 1, 0))]
        parent = "chest"
        for index, (_, xyz, axis) in enumerate(arm, 1):
            joints.append(_joint(f"arm_{side}_{index}", "revolute", parent, f"arm_{side}_{index}_link", xyz,
                                 axis=axis))
            parent = f"arm_{side}_{index}_link"
        joints += [_joint(f"wrist_{side}", "fixed", parent, f"hand_{side}", (0, 0, -0.08), (0, 0, sign * 1.5708)),
                   _joint(f"gripper_{side}", "revolute", f"hand_{side}", f"gripper_{side}_link", (0, 0.02, -0.03)),
                   _joint(f"finger_{side}_1", "revolute", f"hand_{side}", f"finger_{side}_1_link", (0, 0.005, -0.056),
                          mimic=f"gripper_{side}"),
                   _joint(f"finger_{side}_2", "revolute", f"finger_{side}_1_link", f"finger_{side}_2_link",
                          (0.03, 0.046, -0.066), mimic=f"gripper_{side}")]
        number = 1 if side == "right" else 2
        leg = f"leg_{side}"
        joints += [_joint(f"{leg}_hip_yaw", "revolute", "base", f"{leg}_1", (-0.02, sign * 0.085, -0.27),
                          axis=(0, 0, 1)),
                   _joint(f"{leg}_hip_roll", "revolute", f"{leg}_1", f"{leg}_2", axis=(1, 0, 0)),
                   _joint(f"{leg}_hip_pitch", "revolute", f"{leg}_2", f"{leg}_3", axis=(0, 1, 0)),
                   _joint(f"{leg}_knee", "revolute", f"{leg}_3", f"{leg}_4", (0, 0, -0.4), axis=(0, 1, 0)),
                   _joint(f"{leg}_ankle_pitch", "revolute", f"{leg}_4", f"{leg}_5", (0, 0, -0.35), axis=(0, 1, 0)),
                   _joint(f"{leg}_ankle_roll", "revolute", f"{leg}_5", f"{leg}_6", axis=(1, 0, 0)),
                   _joint(f"{leg}_sole", "fixed", f"{leg}_6", f"{leg}_sole_link", (0, 0, -0.1)),
                   _joint(f"{leg}_crank", "revolute", f"{leg}_4", f"{leg}_crank_link", (0, sign * 0.1, -0.1),
                          axis=(0, 1, 0)),
                   _joint(f"closedloop{number}_B", "fixed", f"{leg}_crank_link", f"{leg}_crank_tip", (0.1, 0, 0)),
                   _joint(f"{leg}_ball_x", "revolute", f"{leg}_5", f"{leg}_ball_1", (0.1, sign * 0.1, 0.05)),
                   _joint(f"{leg}_ball_y", "revolute", f"{leg}_ball_1", f"{leg}_ball_2", axis=(0, 1, 0)),
                   _joint(f"{leg}_ball_z", "revolute", f"{leg}_ball_2", f"{leg}_rod", axis=(0, 0, 1)),
                   _joint(f"closedloop{number}_A", "fixed", f"{leg}_rod", f"{leg}_rod_tip", (0, 0, 0.22))]
    import re

    links = sorted({name for joint in joints for name in re.findall(r'link="([^"]+)"', joint)})
    return ('<robot name="humanoid">' + "".join(f'<link name="{name}"/>' for name in links) + "".join(joints)
            + "</robot>")


def test_humanoid_legs_carry_the_loops_and_the_rest_is_left_out(tmp_path):
    """Only the legs' joints are on loops: the torso, head, arms, grippers (and their mimic fingers), and the ankle
    rolls are left out and named (a long list is cut); each leg keeps three hip motors, the knee and the crank,
    the ankle pitch driven through the rod (idle spin). A humanoid imports and classifies in seconds."""
    import time

    urdf = tmp_path / "robot.urdf"
    urdf.write_text(humanoid_urdf())
    motors = [f"leg_{side}_{name}" for side in ("left", "right") for name in ("hip_yaw", "hip_roll", "hip_pitch",
                                                                            "knee", "crank", "ankle_roll")]
    closures = write_closures(tmp_path, {
        "closed_loop": [["closedloop1_A", "closedloop1_B"], ["closedloop2_A", "closedloop2_B"]], "type": ["3d", "3d"],
        "name_mot": motors + ["waist_yaw", "waist_pitch", "arm_left_", "arm_right_", "gripper", "finger", "neck"]})
    start = time.perf_counter()
    imported = read_urdf(urdf, closures)
    report = classify(imported.mechanism, home(imported.mechanism), rng=np.random.default_rng(0))
    elapsed = time.perf_counter() - start
    notes = " | ".join(imported.notes)
    assert "and 14 more (26 in all); actuated among them:" in notes  # 7 + 7 arm, 2 neck, 2 ankle roll, 2 + 4 hand
    mimics = next(note for note in imported.notes if note.startswith("<mimic> joints on no loop, left out"))
    assert set(mimics.split(": ")[1].split(", ")) == {f"finger_{side}_{index}" for side in ("left", "right")
                                                      for index in (1, 2)}
    assert imported.residual <= ASSEMBLY_TOLERANCE and imported.distance > 0.01
    # the closure map is in frame A's coordinates: the hips and knees carry both frames of their leg's loop and stay
    # at zero (in world coordinates the minimum-norm steps would bend them to turn the gap)
    assert all(abs(imported.values[f"leg_{side}_{name}"]) < 1e-12 for side in ("left", "right")
               for name in ("hip_yaw", "hip_roll", "hip_pitch", "knee"))
    assert imported.values["leg_left_ankle_pitch"] != 0.0
    assert (report.dof, report.actuator.rank, report.idle_freedoms, report.kinds) == (12, 10, 2, ())
    assert elapsed < 20.0  # seconds, generous: the real two-legged Talos takes about 2 s here


def test_two_links_of_one_name_are_refused_in_one_line(tmp_path, capsys):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text('<robot name="r"><link name="base"/><link name="foot"/><link name="foot"/>'
                    + _joint("ankle", "revolute", "base", "foot") + _joint("foot_frame", "fixed", "foot", "foot")
                    + "</robot>")
    status = main(["classify", str(urdf)])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "link 'foot': two <link> elements have this name (link names must be unique" in err
