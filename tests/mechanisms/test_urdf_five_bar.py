"""The imported 5-bar of the example-parallel-robots collection and the catalogue five-bar at the same geometry
give the same classification and the same singular configurations.

The URDF's frames and zero are not the catalogue's: its joints turn about the ground's x axis, its links hang
in the plane through the first motor normal to that axis, and its zero configuration is open. The two are matched
by geometry, not by joint values: the imported robot's joint centres at its closed home, projected on the plane
of motion, give the catalogue's lengths and its base A→B direction; a catalogue configuration (joint centres A, C,
P, D, B) is carried to the imported robot by the angles of its links in that plane, each joint's displacement the
change of the angle between its two links, signed by its axis. The map is checked: the imported robot's loops
close at every carried configuration and its joint centres land on the catalogue's.

The imported robot has one freedom more than the catalogue's: the spin of the two coaxial leaf joints welded by
its 6d closure, which moves neither a motor nor anything else and is reported as an idle freedom. The catalogue
five-bar has an end-effector (the tip) and the imported one none, so their end-effector kinds are not compared.
Singular configurations: where the distal links are aligned, θ3 − θ4 = kπ (Chablat, Wenger & Angeles 1998,
eq. 9), an actuator singularity; with the elbows C = D (θ3 − θ4 = 0 with equal distal links) a degenerate one
(Park & Kim 1999, Fig. 6b).
"""

import math
from pathlib import Path

import numpy as np
import pytest

from classify import classify
from mechanisms import configuration, home
from mechanisms.catalogue.five_bar import circle_intersection, five_bar
from mechanisms.kinematics import constraint
from mechanisms.urdf import read_urdf

ROBOT = Path(__file__).resolve().parents[1] / "data" / "robots" / "5bar_linkage"
#: imported link -> the two joint centres (catalogue names) whose direction is the link's angle in the plane;
#: 'sphere' is the leaf welded at P: its angle is the idle spin, kept with the left distal link
LINK_DIRECTIONS = {"rod": ("A", "C"), "rod_2": ("C", "P"), "sphere": ("C", "P"), "rod_3": ("B", "D"),
                   "end_rod": ("D", "P")}
#: imported joint -> the catalogue joint at the same centre
CENTRES = {"mot1": "A", "free1": "C", "closedloop1_A": "P", "free2": "D", "mot2": "B"}

pytest.importorskip("yourdfpy")


@pytest.fixture(scope="module")
def robot():
    """(imported mechanism, plane: origin, e1, e2, normal; catalogue lengths; home centres in the plane)."""
    mechanism = read_urdf(ROBOT / "robot.urdf", ROBOT / "robot.yaml").mechanism
    joints = {joint.name: joint for joint in mechanism.joints}
    normal = np.asarray(joints["mot1"].axis)
    origin = np.asarray(joints["mot1"].point)

    def in_plane(point):
        offset = np.asarray(point) - origin
        return offset - (offset @ normal) * normal

    e1 = in_plane(joints["mot2"].point)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    centres = {CENTRES[name]: np.array([in_plane(joints[name].point) @ e1, in_plane(joints[name].point) @ e2])
               for name in CENTRES}
    lengths = {key: float(np.linalg.norm(centres[second] - centres[first])) for key, (first, second) in
               {"base": ("A", "B"), "proximal": ("A", "C"), "distal": ("C", "P"), "proximal_right": ("B", "D"),
                "distal_right": ("D", "P")}.items()}
    return mechanism, (origin, e1, e2, normal), lengths, centres


def angle(centres, link):
    first, second = LINK_DIRECTIONS[link]
    direction = np.asarray(centres[second]) - np.asarray(centres[first])
    return math.atan2(direction[1], direction[0])


def cross(first, second):
    """The z component of the cross product of two plane vectors."""
    return float(first[0] * second[1] - first[1] * second[0])


def wrapped(value):
    return (value + math.pi) % (2 * math.pi) - math.pi


def carried(robot, centres):
    """The imported robot's configuration whose joint centres are the catalogue's `centres` (see the module's
    note), and those centres reached, in the plane."""
    mechanism, (origin, e1, e2, normal), _, at_home = robot
    values = {}
    def relative(shape, joint):
        first, second = (0.0 if link == mechanism.ground else angle(shape, link) for link in joint.links)
        return second - first

    for joint in mechanism.joints:
        change = relative(centres, joint) - relative(at_home, joint)
        values[joint.name] = float(np.sign(np.asarray(joint.axis) @ normal)) * wrapped(change)
    point = configuration(mechanism, values).point
    from mechanisms.kinematics import link_pose

    reached = {}
    for name, joint in ((name, next(j for j in mechanism.joints if j.name == name)) for name in CENTRES):
        pose = link_pose(mechanism, joint.links[0], point)
        position = pose[:3, :3] @ np.asarray(joint.point) + pose[:3, 3] - origin
        reached[CENTRES[name]] = np.array([position @ e1, position @ e2])
    return point, reached


def catalogue_centres(lengths, theta1, theta2, assembly, theta3=0.0):
    from mechanisms.catalogue.five_bar import five_bar_points

    return five_bar_points(**lengths, theta1=theta1, theta2=theta2, assembly=assembly, theta3=theta3)


def distal_aligned(lengths, theta1, side):
    """Centres with C, P, D in line, P between (θ3 − θ4 = π, Chablat, Wenger & Angeles 1998, eq. 9)."""
    c = np.array([lengths["proximal"] * math.cos(theta1), lengths["proximal"] * math.sin(theta1)])
    b = np.array([lengths["base"], 0.0])
    d = np.array(circle_intersection(tuple(c), lengths["distal"] + lengths["distal_right"], tuple(b),
                                     lengths["proximal_right"], side))
    p = c + lengths["distal"] * (d - c) / np.linalg.norm(d - c)
    return {"A": (0.0, 0.0), "C": tuple(c), "P": tuple(p), "D": tuple(d), "B": tuple(b)}


def compared(robot, centres, assembly, theta3=0.0):
    """(imported report, catalogue report) at the configuration with these centres."""
    mechanism, _, lengths, _ = robot
    theta1 = math.atan2(centres["C"][1], centres["C"][0])
    theta2 = math.atan2(centres["D"][1], centres["D"][0] - lengths["base"])
    catalogue = five_bar(**lengths, theta1=theta1, theta2=theta2, assembly=assembly, theta3=theta3)
    built = {joint.name: np.asarray(joint.point) for joint in catalogue.joints}
    for name in "ACPDB":
        assert np.allclose(built[name], centres[name], atol=1e-9)
    point, reached = carried(robot, centres)
    assert np.linalg.norm(constraint(mechanism, point)) < 1e-9  # the map carries a closed configuration ...
    for name in "ACPDB":
        assert np.allclose(reached[name], centres[name], atol=1e-9)  # ... to the same centres
    mine = classify(mechanism, point, rng=np.random.default_rng(0))
    theirs = classify(catalogue, home(catalogue), rng=np.random.default_rng(0))
    return mine, theirs


def assert_same_classification(mine, theirs):
    assert mine.dof == theirs.dof + 1 and mine.idle_freedoms == theirs.idle_freedoms + 1  # the welded leaf spin
    assert mine.kinds == tuple(kind for kind in theirs.kinds if kind != "end_effector")
    assert (mine.cspace.rank < mine.cspace.expected_rank) == (theirs.cspace.rank < theirs.cspace.expected_rank)
    assert (mine.actuator.rank, mine.actuator.expected_rank) == (theirs.actuator.rank, theirs.actuator.expected_rank)
    assert mine.degeneracy == theirs.degeneracy


def test_the_imported_geometry_is_a_five_bar(robot):
    _, _, lengths, centres = robot
    assert np.allclose(centres["A"], 0.0) and abs(centres["B"][1]) < 1e-12
    assert lengths["proximal"] == pytest.approx(lengths["proximal_right"])
    assert lengths["distal"] == pytest.approx(lengths["distal_right"])


@pytest.mark.parametrize("theta1, theta2", [(None, None), (-1.2, -1.9), (-2.0, -1.3), (-1.0, -2.4)])
def test_regular_configurations_classify_the_same(robot, theta1, theta2):
    _, _, lengths, at_home = robot
    if theta1 is None:  # the imported robot's own home
        centres = at_home
    else:
        centres = catalogue_centres(lengths, theta1, theta2, assembly=-1)
    c, d, p = (np.asarray(centres[name]) for name in "CDP")
    assembly = 1 if cross(d - c, p - c) > 0 else -1
    mine, theirs = compared(robot, centres, assembly)
    assert theirs.kinds == () and mine.kinds == ()
    assert_same_classification(mine, theirs)


@pytest.mark.parametrize("theta1, side", [(-1.4, 1), (-1.9, -1)])
def test_distal_links_aligned_are_actuator_singular_in_both(robot, theta1, side):
    """Chablat, Wenger & Angeles 1998, eq. 9: θ3 − θ4 = π; Park & Kim 1999, Fig. 6a."""
    _, _, lengths, _ = robot
    mine, theirs = compared(robot, distal_aligned(lengths, theta1, side), assembly=1)
    assert "actuator" in theirs.kinds and theirs.degeneracy == "nondegenerate"
    assert_same_classification(mine, theirs)


def test_a_scan_across_the_aligned_configuration_is_singular_only_there(robot):
    """θ1 held, the tip turned about C through the aligned posture: singular at it, regular on both sides."""
    _, _, lengths, _ = robot
    aligned = distal_aligned(lengths, -1.4, 1)
    c, p, b = (np.asarray(aligned[name]) for name in "CPB")
    theta3 = math.atan2(*(p - c)[::-1])
    for offset in (-0.15, 0.15):
        tip = c + lengths["distal"] * np.array([math.cos(theta3 + offset), math.sin(theta3 + offset)])
        # D on the aligned posture's side of the line P→B, so that the scan stays on one branch
        side = 1 if cross(b - p, np.asarray(aligned["D"]) - p) > 0 else -1
        d = circle_intersection(tuple(tip), lengths["distal_right"], tuple(b), lengths["proximal_right"], side)
        centres = {"A": (0.0, 0.0), "C": tuple(c), "P": tuple(tip), "D": d, "B": tuple(b)}
        assembly = 1 if cross(np.asarray(d) - c, tip - c) > 0 else -1
        mine, theirs = compared(robot, centres, assembly)
        assert theirs.kinds == () == mine.kinds
        assert_same_classification(mine, theirs)


def test_coincident_elbows_are_a_degenerate_actuator_singularity_in_both(robot):
    """C = D: the tip turns about the common elbow with the motors locked (Park & Kim 1999, Fig. 6b)."""
    _, _, lengths, _ = robot
    c = circle_intersection((0.0, 0.0), lengths["proximal"], (lengths["base"], 0.0), lengths["proximal_right"], -1)
    theta = math.atan2(c[1], c[0])
    theta2 = math.atan2(c[1], c[0] - lengths["base"])
    centres = catalogue_centres(lengths, theta, theta2, assembly=0, theta3=theta - 0.8)
    mine, theirs = compared(robot, centres, assembly=0, theta3=theta - 0.8)
    assert "actuator" in theirs.kinds and theirs.degeneracy == "degenerate"
    assert_same_classification(mine, theirs)
