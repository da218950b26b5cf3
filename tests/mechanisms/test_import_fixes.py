"""URDF and MJCF import fixes: a weld's anchor and relpose read as MuJoCo reads them, an MJCF's meshes and
includes found beside the file (and missing meshes not needed), keyframes named when left out, and no numpy
warnings printed by the URDF parser."""

import warnings

import numpy as np
import pytest

from mechanisms import MechanismError
from mechanisms.closures import Closures
from builders import ROBOTS

# ------------------------------------------------------------------------------------------- MJCF weld

#: a planar five-bar whose left distal link `l2` is welded to the right leg's tip: dof 2 (5 hinges, 3 planar
#: constraints)
WELDED = """<mujoco><worldbody>
 <body name="l1"><joint name="A" type="hinge" axis="0 0 1"/><geom size=".05"/>
  <body name="l2" pos="1 0 0"><joint name="C" type="hinge" axis="0 0 1"/><geom size=".05"/></body></body>
 <body name="r1" pos="2 0 0"><joint name="B" type="hinge" axis="0 0 1"/><geom size=".05"/>
  <body name="r2" pos="0 1 0"><joint name="D" type="hinge" axis="0 0 1"/><geom size=".05"/>
   <body name="tip" pos="-0.5 0.5 0"><joint name="E" type="hinge" axis="0 0 1"/><geom size=".05"/></body></body></body>
</worldbody><equality><weld name="w" body1="l2" body2="tip" {weld}/></equality>
<actuator><motor joint="A"/><motor joint="B"/></actuator></mujoco>"""


def mujoco_residual(path, values):
    """MuJoCo's equality residual (``efc_pos``) with the joints at `values`."""
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    for name, value in values.items():
        data.qpos[model.jnt_qposadr[model.joint(name).id]] = value
    mujoco.mj_forward(model, data)
    return float(np.abs(data.efc_pos[:data.ne]).max())


@pytest.mark.parametrize("weld", [
    'anchor="0.3 0.2 0"',  # the relpose is MuJoCo's reference pose: closed at qpos0
    'anchor="0.3 0.2 0" relpose="0.3 0.1 0 0.9961947 0 0 0.0871557"',  # a given relpose: assembled
    'anchor="0 0 0" relpose="0.4 0.9 0 0.9961947 0 0 -0.0871557"',
])
def test_a_weld_closes_where_mujoco_closes_it(tmp_path, weld):
    """The anchor on body2 (``eq_data[0:3]``) was ignored: with anchor 0.3 0.2 0 MuJoCo's residual is 0 at
    qpos0, and the import moved 0.322 to a configuration where MuJoCo's residual is 0.307."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "weld.xml"
    path.write_text(WELDED.format(weld=weld))
    imported = read_mjcf(path)
    assert imported.residual < 1e-9 and imported.closures.types == ("6d",)
    assert mujoco_residual(path, imported.values) < 1e-9
    if "relpose" not in weld:
        assert imported.distance < 1e-9  # MuJoCo's reference pose is closed


def test_a_weld_without_torque_is_a_3d_closure(tmp_path):
    """``torquescale="0"`` drops the weld's rotation rows: MuJoCo holds the anchor point only, a ball."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "weld.xml"
    path.write_text(WELDED.format(weld='anchor="0.3 0.2 0" relpose="0.3 0.1 0 1 0 0 0" torquescale="0"'))
    imported = read_mjcf(path)
    assert imported.closures.types == ("3d",) and imported.residual < 1e-9
    assert mujoco_residual(path, imported.values) < 1e-9
    assert any("torquescale 0" in note and "'w'" in note for note in imported.notes)


# ------------------------------------------------------------------------------------------- MJCF files

def tetrahedron():
    """A tetrahedron of side 0.1, as binary STL (MuJoCo reads no ASCII STL)."""
    import struct

    corners = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]])
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    data = bytearray(80) + struct.pack("<I", len(faces))
    for face in faces:
        data += struct.pack("<12fH", *np.zeros(3), *corners[list(face)].ravel(), 0)
    return bytes(data)


MESHED = """<mujoco model="meshed"><compiler meshdir="meshes"/>
<asset><mesh name="m" file="{mesh}"/></asset>
<worldbody>
 <body name="l1"><joint name="A" type="hinge" axis="0 0 1"/><geom type="mesh" mesh="m"/>
  <body name="l2" pos="1 0 0"><joint name="C" type="hinge" axis="0 0 1"/><geom type="mesh" mesh="m"/></body></body>
 <body name="r1" pos="2 0 0"><joint name="B" type="hinge" axis="0 0 1"/><geom type="mesh" mesh="m"/>
  <body name="r2" pos="0 1 0"><joint name="D" type="hinge" axis="0 0 1"/><geom type="mesh" mesh="m"/></body></body>
</worldbody>
<equality><connect name="tip" body1="l2" body2="r2" anchor="0.5 1 0"/></equality>
<include file="actuators.xml"/>
</mujoco>"""


def meshed_model(folder, mesh="m.stl", write_mesh=True):
    folder.mkdir()
    (folder / "meshes").mkdir()
    if write_mesh:
        (folder / "meshes" / "m.stl").write_bytes(tetrahedron())
    (folder / "actuators.xml").write_text('<mujoco><actuator><motor joint="A"/><motor joint="B"/></actuator>'
                                          '</mujoco>')
    path = folder / "model.xml"
    path.write_text(MESHED.format(mesh=mesh))
    return path


def test_meshes_and_includes_are_found_beside_the_model(tmp_path, monkeypatch):
    """They were looked for in the current directory: 'Error opening file' from anywhere but the model's
    folder."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = meshed_model(tmp_path / "robot")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    imported = read_mjcf(path)
    assert imported.residual < 1e-9 and imported.closures.actuated == ("A", "B")
    assert not any("mesh" in note for note in imported.notes)


def test_missing_meshes_are_not_needed(tmp_path, capfd):
    """As for a URDF, the meshes are not needed for the kinematics: the model compiles without them, and the
    notes say so; a file that is no MJCF still fails in one line."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = meshed_model(tmp_path / "robot", mesh="nowhere/missing.stl", write_mesh=False)
    imported = read_mjcf(path)
    assert imported.residual < 1e-9 and imported.mechanism.loop_count == 1
    assert imported.closures.actuated == ("A", "B")
    assert any("compiled without its meshes" in note and "missing.stl" in note for note in imported.notes)
    path.write_text(path.read_text().replace("</mujoco>", "<bad/></mujoco>"))
    with pytest.raises(MechanismError, match="MJCF: cannot compile") as caught:
        read_mjcf(path)
    assert "\n" not in str(caught.value)
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""


def test_keyframes_left_out_are_named(tmp_path):
    """A ``<keyframe>`` was dropped without a word."""
    pytest.importorskip("mujoco")
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "keyed.xml"
    path.write_text(WELDED.format(weld='anchor="0 0 0"').replace(
        "</mujoco>", '<keyframe><key name="bent" qpos="0.1 0 0 0 0"/><key qpos="0 0 0 0 0"/></keyframe></mujoco>'))
    notes = read_mjcf(path).notes
    assert any("keyframes" in note and "'bent'" in note and "'key1'" in note for note in notes)


# ------------------------------------------------------------------------------------------- URDF warnings

def five_bar_with(tmp_path, old, new):
    text = (ROBOTS / "5bar_linkage" / "robot.urdf").read_text()
    assert old in text
    path = tmp_path / "robot.urdf"
    path.write_text(text.replace(old, new, 1))
    return path


def test_an_infinite_rpy_is_refused_without_numpy_warnings(tmp_path, capfd):
    """trimesh's euler_matrix printed 'RuntimeWarning: invalid value encountered in sin' (4 lines) before the
    one-line refusal."""
    pytest.importorskip("yourdfpy")
    from mechanisms.urdf import read_urdf

    path = five_bar_with(tmp_path, 'rpy="-1.5128280870939263564e-40 -3.6734198463195946286e-40 '
                         '-6.1876044703704446752e-78"', 'rpy="0 0 inf"')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(MechanismError, match="joint 'free1': field 'origin': not a finite pose") as error:
            read_urdf(path, ROBOTS / "5bar_linkage" / "robot.yaml")
    assert "\n" not in str(error.value)
    assert [str(item.message) for item in caught] == []
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""


def test_an_infinite_rpy_in_a_visual_imports_without_numpy_warnings(tmp_path, capfd):
    """The visual is not read for the kinematics: the import succeeds, silently."""
    pytest.importorskip("yourdfpy")
    from mechanisms.urdf import read_urdf

    path = five_bar_with(tmp_path, '<origin xyz="0 0 0" rpy="0 -0 0" />', '<origin xyz="0 0 0" rpy="inf 0 0" />')
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        imported = read_urdf(path, ROBOTS / "5bar_linkage" / "robot.yaml")
    assert imported.residual < 1e-9
    assert [str(item.message) for item in caught] == []
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""


def test_the_urdf_reader_leaves_numpy_error_state_alone(tmp_path):
    pytest.importorskip("yourdfpy")
    from mechanisms.urdf import read_urdf

    before = np.geterr()
    read_urdf(ROBOTS / "5bar_linkage" / "robot.urdf", Closures())
    assert np.geterr() == before
