"""The planar six-bar (6R loop) with equal links: Park & Kim Fig. 12a/b.

Park & Kim (1999, Case 3 and Fig. 12): "a planar
six-bar linkage with equal link lengths ... we ignore orientation and consider
only the Cartesian position of the end-effector frame. In this configuration
the end-effector frame is unable to translate along the link to which it is
attached, regardless of the number and choice of joints that are actuated.
However, if the end-effector frame is relocated to the adjacent link
(Figure 12b), it is now able to move in arbitrary directions in the plane."

Our reading (the figure itself is not in the text): joints J1..J6 around the
loop, J1 at the origin and J6 at (L, 0), so that the ground J6-J1 has the
same length L as the five moving links ``link1`` (J1-J2) ... ``link5``
(J5-J6). The end-effector is the midpoint of one link. Fig. 12a is link 2
aligned with link 1 (J1, J2, J3 collinear): link 2 then moves as the tip of
the 2R arm J1-J2, whose points can only move across the line J1-J3 -- not
along link 2, whichever joints drive the loop. Fig. 12b is the same
configuration with the end-effector on the adjacent link 3 (J3-J4), which is
not on that line: its midpoint moves in every direction of the plane.
"""

from __future__ import annotations

import math

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._six_bar import LINKS, actuated_joints
from ._entry import Entry

__all__ = ["planar_six_bar", "ENTRIES"]

def planar_six_bar(*, length=1.0, theta1=1.3, theta2=0.6, theta3=-2.0, branch=1, actuated="135",
                   end_effector_link=2):
    """Planar 6R loop with six equal links, assembled at the angles of joints J1, J2, J3.

    Parameters
    ----------
    length : float
        L, the common length of the six links (ground included) (Park & Kim Fig. 12: "equal
        link lengths").
    theta1 : float
        Angle (rad) of link 1 (J1 -> J2) from the ground direction J1 -> J6.
    theta2, theta3 : float
        Relative angles (rad) at J2 and J3: link 2 turned by θ2 from link 1, link 3 by θ3 from
        link 2. θ2 = 0 is the configuration of Fig. 12 (links 1 and 2 aligned).
    branch : int
        +1 / −1: J5 on the left / right of the line J4 -> J6 (the two closures of the dyad
        J4-J5-J6).
    actuated : str
        The driven joints as digits, e.g. ``"135"`` (any number of them: Park & Kim state Fig. 12
        "regardless of the number and choice of joints that are actuated").
    end_effector_link : int
        1-5: the link whose midpoint is the end-effector position (2 for Fig. 12a, 3 for
        Fig. 12b).

    Returns
    -------
    Mechanism
        Joints ``J1`` (ground-link1) ... ``J6`` (link5-ground).

    Raises
    ------
    MechanismError
        For a non-positive length, a bad `branch`, `actuated` or `end_effector_link`, or angles
        with which the dyad J4-J5-J6 cannot close.

    Notes
    -----
    J2 = J1 + L e(θ1), J3 = J2 + L e(θ1 + θ2), J4 = J3 + L e(θ1 + θ2 + θ3), with
    e(φ) = (cos φ, sin φ); J5 is the intersection of the circles of radius L about J4 and J6:
    J5 = (J4 + J6)/2 + branch · √(L² − d²/4) · n, d = ‖J6 − J4‖, n the unit normal to
    J6 − J4 turned by +90°.
    """
    if not length > 0:
        raise MechanismError(f"planar-six-bar: length must be positive, got {length}")
    if branch not in (1, -1):
        raise MechanismError(f"planar-six-bar: branch must be 1 or -1, got {branch}")
    if end_effector_link not in (1, 2, 3, 4, 5):
        raise MechanismError(f"planar-six-bar: end_effector_link must be 1-5, got {end_effector_link}")
    driven = actuated_joints(actuated, "planar-six-bar")
    points = [(0.0, 0.0)]
    heading = 0.0
    for angle in (theta1, theta2, theta3):
        heading += angle
        x, y = points[-1]
        points.append((x + length * math.cos(heading), y + length * math.sin(heading)))
    last = (length, 0.0)
    chord = (last[0] - points[3][0], last[1] - points[3][1])
    distance = math.hypot(*chord)
    if distance < 1e-12 * length:
        raise MechanismError("planar-six-bar: theta1, theta2, theta3 put J4 on J6: the dyad J4-J5-J6 "
                             "can fold about it freely (no unique closure)")
    if distance > 2 * length * (1 + 1e-12):
        raise MechanismError(f"planar-six-bar: theta1, theta2, theta3 put J4 at {distance:.6g} from J6, "
                             f"beyond the reach 2L = {2 * length} of links 4 and 5")
    height = math.sqrt(max(length ** 2 - distance ** 2 / 4, 0.0))
    normal = (-chord[1] / distance, chord[0] / distance)
    points.append(((points[3][0] + last[0]) / 2 + branch * height * normal[0],
                   (points[3][1] + last[1]) / 2 + branch * height * normal[1]))
    points.append(last)
    joints = [Joint(f"J{number}", "R", (LINKS[number - 1], LINKS[number]), point=points[number - 1],
                    actuated=number in driven) for number in range(1, 7)]
    start, end = points[end_effector_link - 1], points[end_effector_link]
    midpoint = ((start[0] + end[0]) / 2, (start[1] + end[1]) / 2)
    return Mechanism("planar-six-bar", "planar", joints,
                     end_effector=EndEffector(f"link{end_effector_link}", midpoint, "position"))


ENTRIES = (
    Entry("planar-six-bar", planar_six_bar,
          "Park & Kim (1999) Case 3, Fig. 12a/b",
          {
              "fig12a_end_effector": {"theta1": math.pi / 2, "theta2": 0.0, "theta3": -2 * math.pi / 3},
              "fig12b_relocated": {"theta1": math.pi / 2, "theta2": 0.0, "theta3": -2 * math.pi / 3,
                                   "end_effector_link": 3},
          }),
)
