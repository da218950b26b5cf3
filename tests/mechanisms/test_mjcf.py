"""MJCF import (:mod:`mechanisms.mjcf`): a five-bar written as MuJoCo bodies with one ``connect`` equality
classifies as the catalogue five-bar (Park & Kim 1999, Fig. 6a: the distal links aligned)."""

import re

import numpy as np
import pytest

from classify import classify
from mechanisms import MechanismError, home
from mechanisms.catalogue import entry

pytest.importorskip("mujoco")


def five_bar_xml(mechanism):
    """The catalogue five-bar as MJCF: two legs from the world, their tips joined by a connect (a ball)."""
    points = {joint.name: np.array([*joint.point, 0.0]) for joint in mechanism.joints}

    def vector(values):
        return " ".join(repr(float(value)) for value in values)

    legs = []
    for proximal, distal, hinge, elbow in (("proximal_left", "distal_left", "A", "C"),
                                           ("proximal_right", "distal_right", "B", "D")):
        legs.append(f"""
    <body name="{proximal}" pos="{vector(points[hinge])}">
      <joint name="{hinge}" type="hinge" axis="0 0 1"/>
      <geom type="sphere" size="0.05"/>
      <body name="{distal}" pos="{vector(points[elbow] - points[hinge])}">
        <joint name="{elbow}" type="hinge" axis="0 0 1"/>
        <geom type="sphere" size="0.05"/>
      </body>
    </body>""")
    anchor = points["P"] - points["C"]
    return f"""<mujoco model="five-bar">
  <worldbody>{''.join(legs)}
  </worldbody>
  <equality><connect name="tip" body1="distal_left" body2="distal_right" anchor="{vector(anchor)}"/></equality>
  <actuator><motor joint="A"/><motor joint="B"/></actuator>
</mujoco>
"""


@pytest.mark.parametrize("configuration, kinds", [(None, ()), ("fig6a_distal_aligned", ("actuator",))])
def test_mjcf_five_bar_classifies_as_the_catalogue_five_bar(tmp_path, configuration, kinds):
    from mechanisms.mjcf import read_mjcf

    item = entry("five-bar")
    catalogue = item.assemble(item.values(configuration))
    path = tmp_path / "five_bar.xml"
    path.write_text(five_bar_xml(catalogue))
    imported = read_mjcf(path)
    assert imported.residual < 1e-9 and imported.closures.types == ("3d",)
    mechanism = imported.mechanism
    assert [joint.name for joint in mechanism.joints if joint.actuated] == ["A", "B"]
    mine = classify(mechanism, home(mechanism), rng=np.random.default_rng(0))
    theirs = classify(catalogue, home(catalogue), rng=np.random.default_rng(0))
    assert mine.dof == theirs.dof == 2
    assert mine.kinds == tuple(kind for kind in theirs.kinds if kind != "end_effector") == kinds
    assert (mine.actuator.rank, mine.actuator.expected_rank) == (theirs.actuator.rank, theirs.actuator.expected_rank)
    assert mine.degeneracy == theirs.degeneracy


def test_mjcf_compiler_errors_are_one_line(tmp_path):
    from mechanisms.mjcf import read_mjcf

    path = tmp_path / "bad.xml"
    path.write_text("<mujoco><worldbody><body><joint type='hinge' axis='0 0 0'/></body></worldbody></mujoco>")
    with pytest.raises(MechanismError, match="MJCF: cannot compile") as caught:
        read_mjcf(path)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize("pattern, replacement, message", [
    (r'axis="0 0 1"', 'axis="nan 0 1"', "joint 'A': its axis is not finite"),
    (r'(<joint name="B" type="hinge" axis="0 0 1")', r'\1 pos="inf 0 0"', "joint 'B': its pos is not finite"),
    (r'anchor="[^"]*"', 'anchor="inf 0 0"', "equality 'tip': its anchor or relpose is not finite"),
    (r'(<joint name="B" type="hinge" axis="0 0 1")', r'\1 pos="1e300 0 0"', "joint 'B': its pos is beyond ±1e\\+12"),
    (r'anchor="[^"]*"', 'anchor="1e300 0 0"', "equality 'tip': its anchor or relpose is beyond"),
    # MuJoCo normalises 1e300 to 0 0 0: the import divided by its norm and ended in a LinAlgError
    (r'axis="0 0 1"', 'axis="0 0 1e300"', "joint 'A': its axis has no direction"),
])
def test_non_finite_or_huge_geometry_is_refused_in_one_line(tmp_path, capfd, pattern, replacement, message):
    """MuJoCo compiles NaN and infinity with a warning on stdout; the import used to end in a LinAlgError."""
    from mechanisms.mjcf import read_mjcf

    text = five_bar_xml(entry("five-bar").mechanism())
    changed = re.sub(pattern, replacement, text, count=1)
    assert changed != text
    path = tmp_path / "bad.xml"
    path.write_text(changed, encoding="utf-8")
    with pytest.raises(MechanismError, match=f"bad.xml: MJCF: {message}"):
        read_mjcf(path)
    captured = capfd.readouterr()  # MuJoCo writes from C: the file descriptors, not sys.stdout
    assert captured.out == "" and captured.err == ""


def test_an_inactive_connect_is_said_not_to_close_a_loop(tmp_path):
    """MuJoCo's active="false": the equality is off, so no loop; the import said nothing of it."""
    from mechanisms.mjcf import read_mjcf

    text = five_bar_xml(entry("five-bar").mechanism()).replace('<connect name="tip"', '<connect name="tip" '
                                                               'active="false"', 1)
    path = tmp_path / "off.xml"
    path.write_text(text, encoding="utf-8")
    imported = read_mjcf(path)
    assert imported.mechanism.loop_count == 0
    assert any("equality 'tip' is inactive" in note for note in imported.notes)


def test_made_up_names_never_take_a_name_the_file_gives(tmp_path):
    """An unnamed connect was called ``equality1`` like the named one, whose frames it replaced: the five-bar lost
    its tip closure and was classified with 1 loop instead of 2, exit 0. A body named ``a#1`` was also the name of
    the intermediate link of body ``a``'s two hinges: the tree became a cycle and the import never ended."""
    from mechanisms.mjcf import read_mjcf

    text = five_bar_xml(entry("five-bar").mechanism()).replace(
        '<connect name="tip"', '<connect name="equality1"').replace(
        "</equality>", '<connect body1="distal_left" body2="world" anchor="0 0 0"/></equality>')
    path = tmp_path / "two_connects.xml"
    path.write_text(text, encoding="utf-8")
    assert read_mjcf(path).mechanism.loop_count == 2
    path = tmp_path / "intermediate.xml"
    path.write_text("""<mujoco><worldbody>
  <body name="a"><joint name="j1" type="hinge" axis="0 0 1"/><joint name="j2" type="hinge" axis="1 0 0"/>
    <geom size="0.1"/>
    <body name="a#1" pos="1 0 0"><joint name="j3" type="hinge" axis="0 0 1"/><geom size="0.1"/></body>
  </body>
</worldbody></mujoco>""", encoding="utf-8")
    mechanism = read_mjcf(path).mechanism
    assert {"a", "a#1", "a#1~2"} <= set(mechanism.links) and [joint.name for joint in mechanism.joints] == [
        "j1", "j2", "j3"]
