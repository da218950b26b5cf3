"""The Eclipse (SNU mechanism): Park & Kim Figs. 9, 10, 11c.

Park & Kim (1999, Case 2 and Case 3): "the Eclipse,
a 6 d.o.f. parallel manipulator designed for 5-face machining; each serial
substructure is an RPS chain, which are all mounted on a circular track and
are able to move independently"; the columns of the static Jacobian J_f are
"lines that coincide with the links connecting the mobile platform to the
vertical columns" and "lines passing through each of the three ball joints
..., with direction parallel to the joint axis of the revolute joint on the
corresponding vertical column (i.e., the ball joint and revolute joint
connected by a rigid link forms a pair)". Fig. 10: an actuator singularity
where "four lines meet at a single point"; Fig. 11c: an end-effector
singularity, "the moving platform is parallel to the fixed platform, and one
of the spherical joints lies exactly above the center of the fixed
platform", at which J_f is nonsingular (not an actuator singularity).

Our reading (the figures are not in the text). Three legs i = 1, 2, 3, each

- ``track{i}``: R, ground -> ``carriage{i}``, about the vertical axis z through
  the centre of the circular track (the carriage runs on the track); actuated;
- ``column{i}``: P, ``carriage{i}`` -> ``slider{i}``, vertical, along the
  column standing on the carriage at radius R; actuated;
- ``hinge{i}``: R, ``slider{i}`` -> ``link{i}``, at rᵢ on the column, axis
  horizontal and tangent to the track, so that the rigid link swings in the
  column's vertical radial plane; passive;
- ``ball{i}``: S, ``link{i}`` -> ``platform``, at bᵢ; passive.

Six actuated joints for 6 degrees of freedom (18 joint coordinates, two
loops of 6). With the two actuators of a leg locked, its passive R and S
joints let it push on the platform along two lines through bᵢ: the link
(rᵢ bᵢ) and the line through bᵢ parallel to the hinge axis -- the six
Plücker lines of J_f the paper describes, which is what fixes the hinge axis
and the two actuators. The end-effector is the pose of the platform (at its
centre).

Fig. 11c: platform horizontal, ball 1 on the track axis. The track rotation
of leg 1 and the rotations of ball 1 about the vertical then share a line,
so leg 1 (and the platform) loses a twist: ball 1 cannot move along the
tangent of its column's circle. Fig. 10: platform horizontal with its
circumcircle through the track axis and ball 1 opposite the axis: the
horizontal tangent lines through balls 2 and 3 pass through ball 1 (Thales),
so with the link and tangent lines of leg 1, four lines meet at ball 1.
Turning that platform about its centre (yaw) keeps its circumcircle through
the axis: the three horizontal tangent lines then still meet, at the point of
the circle opposite the axis, and lie in one plane -- a dependent planar
pencil, the same actuator singularity without the mirror symmetry of Fig. 10
(``fig10_turned``).

Assembly (inverse kinematics, closed form): the column of leg i stands at
the azimuth of bᵢ, on the side of the leg's nominal azimuth 90° + 120°(i − 1)
(at the nominal azimuth when bᵢ is on the axis), the slider at height
h = z(bᵢ) + elbow · √(l² − (R − s)²), s the signed horizontal distance of bᵢ
from the axis towards the column.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry

__all__ = ["eclipse", "ball_positions", "plucker_lines", "ENTRIES"]

#: azimuths of the balls on the platform (platform frame) and nominal azimuths of the columns
NOMINAL_AZIMUTHS = tuple(math.radians(90 + 120 * index) for index in range(3))


def ball_positions(*, platform_radius, x, y, z, roll, pitch, yaw):
    """Ball centres b1, b2, b3 for a platform pose.

    Parameters
    ----------
    platform_radius : float
        ρ, the radius of the circle of the balls on the platform.
    x, y, z : float
        Platform centre.
    roll, pitch, yaw : float
        Platform orientation (rad), R = Rz(yaw) Ry(pitch) Rx(roll).

    Returns
    -------
    ndarray, shape=[3, 3]
        bᵢ = (x, y, z) + R ρ (cos βᵢ, sin βᵢ, 0), βᵢ = 90° + 120°(i − 1).
    """
    rotation = Rotation.from_euler("ZYX", [yaw, pitch, roll]).as_matrix()
    local = np.array([[platform_radius * math.cos(angle), platform_radius * math.sin(angle), 0.0]
                      for angle in NOMINAL_AZIMUTHS])
    return np.array([x, y, z]) + local @ rotation.T


def plucker_lines(mechanism):
    """The six columns of Park & Kim's static Jacobian J_f, from the joints of an Eclipse.

    Parameters
    ----------
    mechanism : Mechanism
        Built by :func:`eclipse`.

    Returns
    -------
    ndarray, shape=[6, 6]
        Columns (s, b × s): for each leg, the link line (s = b − r) and the line through b along
        the hinge axis (Park & Kim Case 2, Fig. 10).
    """
    joints = {joint.name: joint for joint in mechanism.joints}
    columns = []
    for leg in (1, 2, 3):
        hinge, ball = joints[f"hinge{leg}"], joints[f"ball{leg}"]
        point = np.array(ball.point)
        for direction in (point - np.array(hinge.point), np.array(hinge.axis)):
            direction = direction / np.linalg.norm(direction)
            columns.append(np.concatenate([direction, np.cross(point, direction)]))
    return np.array(columns).T


def eclipse(*, track_radius=1.0, link_length=1.2, platform_radius=0.3, x=0.05, y=0.02, z=0.0,
            roll=0.1, pitch=-0.05, yaw=0.2, elbow=1):
    """The Eclipse (3 legs: track R, column P, hinge R, ball S), assembled at a platform pose.

    Parameters
    ----------
    track_radius : float
        R, radius of the circular track on which the columns run.
    link_length : float
        l, length of the rigid link from the hinge rᵢ to the ball bᵢ.
    platform_radius : float
        ρ, radius of the circle of the three balls on the moving platform.
    x, y, z, roll, pitch, yaw : float
        Platform pose: centre and orientation R = Rz(yaw) Ry(pitch) Rx(roll) (rad); the track axis
        is the z axis.
    elbow : int
        +1: every slider above its ball (the links hang down to the platform); −1: below.

    Returns
    -------
    Mechanism
        Joints ``track{i}``, ``column{i}`` (actuated), ``hinge{i}``, ``ball{i}``; end-effector:
        pose of ``platform`` at its centre.

    Raises
    ------
    MechanismError
        For non-positive dimensions, a bad `elbow`, or a pose at which a ball is out of reach of
        its link (‖R − s‖ > l, naming the leg).
    """
    for name, value in (("track_radius", track_radius), ("link_length", link_length),
                        ("platform_radius", platform_radius)):
        if not value > 0:
            raise MechanismError(f"eclipse: {name} must be positive, got {value}")
    if elbow not in (1, -1):
        raise MechanismError(f"eclipse: elbow must be 1 or -1, got {elbow}")
    balls = ball_positions(platform_radius=platform_radius, x=x, y=y, z=z, roll=roll, pitch=pitch, yaw=yaw)
    joints = []
    for leg, (ball, nominal) in enumerate(zip(balls, NOMINAL_AZIMUTHS), start=1):
        horizontal = math.hypot(ball[0], ball[1])
        if horizontal <= 1e-12 * track_radius:
            azimuth = nominal
        else:
            azimuth = math.atan2(ball[1], ball[0])
            if math.cos(azimuth - nominal) < 0:
                azimuth += math.pi
        radial = np.array([math.cos(azimuth), math.sin(azimuth), 0.0])
        offset = track_radius - ball[:2] @ radial[:2]
        if abs(offset) > link_length * (1 + 1e-12):
            raise MechanismError(f"eclipse: x, y, z, roll, pitch, yaw put ball {leg} at {abs(offset):.6g} "
                                 f"from column {leg}, beyond the link length {link_length}")
        height = ball[2] + elbow * math.sqrt(max(link_length ** 2 - offset ** 2, 0.0))
        hinge = track_radius * radial + np.array([0.0, 0.0, height])
        tangent = (-radial[1], radial[0], 0.0)
        joints += [
            Joint(f"track{leg}", "R", ("ground", f"carriage{leg}"), point=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
                  actuated=True),
            Joint(f"column{leg}", "P", (f"carriage{leg}", f"slider{leg}"), axis=(0.0, 0.0, 1.0), actuated=True),
            Joint(f"hinge{leg}", "R", (f"slider{leg}", f"link{leg}"), point=tuple(hinge), axis=tangent),
            Joint(f"ball{leg}", "S", (f"link{leg}", "platform"), point=tuple(ball)),
        ]
    return Mechanism("eclipse", "spatial", joints, end_effector=EndEffector("platform", (x, y, z), "pose"))


ENTRIES = (
    Entry("eclipse", eclipse,
          "Park & Kim (1999) Case 2 (Figs. 9, 10) and Case 3 (Fig. 11c)",
          {
              # platform horizontal, its circumcircle through the track axis, ball 1 opposite the axis
              "fig10_actuator": {"x": 0.0, "y": 0.3, "z": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0},
              # the same platform turned about its centre: the three tangent lines meet off ball 1
              "fig10_turned": {"x": 0.0, "y": 0.3, "z": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.1},
              # platform horizontal, ball 1 (at ρ along +y from the centre) on the track axis
              "fig11c_end_effector": {"x": 0.0, "y": -0.3, "z": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0},
          }),
)
