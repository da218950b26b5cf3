"""The spherical six-bar (6R loop) with three actuators: Park & Kim Figs. 7, 8a, 8b.

Park & Kim (1999, Case 2, Figs. 7-8): "Figure 7
indicates a nondegenerate actuator singularity for a spherical six-bar
closed-loop linkage, in which the three actuated joints are indicated by
arrows. The general condition for an actuator singularity in this case is
that the axes corresponding to the three actuated joints are coplanar. By
moving one of the actuators to a different joint as shown in Figure 8a, the
same kinematic configuration now becomes nonsingular. Alternatively, one can
add an actuator."

Our reading (the figures are not in the text). Six revolute axes u1..u6
through the centre of the sphere, consecutive axes at the same twist α (the
six links, ground included, are equal arcs); the ground link carries u6 and
u1. The loop has m = 6 − 3 = 3 degrees of freedom and its tangent space is
the kernel of the 3 × 6 matrix [u1 ... u6] (Σ θ̇ᵢ uᵢ = 0). The actuated
coordinates are local coordinates exactly when the *passive* block of that
matrix is invertible (the implicit-function criterion Park & Kim state for
the five-bar in Case 2), so with three actuators the actuator singularity is
that the three **passive** axes are coplanar; coplanar actuated axes alone do
not make one. We therefore read Fig. 7 as the configuration with three
coplanar axes, the three other joints driven; the paper's sentence, taken
literally, is tested as a known error (see the tests).

The named configurations use the threefold-symmetric hexagon: uₖ at azimuth
60°(k − 1), the odd axes at polar angle a, the even axes in the equatorial
plane (polar angle 90°), with sin a = 2 cos α so that every twist is α. The
even axes u2, u4, u6 are coplanar; Fig. 7 drives J1, J3, J5; Fig. 8a moves
the actuator of J5 to J4; Fig. 8b adds an actuator at J2.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import MechanismError
from ..joints import Joint
from ..mechanism import Mechanism
from ._six_bar import LINKS, actuated_joints
from ._entry import Entry

__all__ = ["spherical_six_bar", "symmetric_hexagon", "joint_angles", "ENTRIES"]

def _tangent_towards(axis, other):
    """Unit tangent of the sphere at `axis` along the great circle towards `other`."""
    tangent = other - (axis @ other) * axis
    return tangent / np.linalg.norm(tangent)


def _next_axis(previous, axis, twist, angle):
    """The axis at arc `twist` from `axis`, turned by `angle` (right-handed about `axis`) from `previous`."""
    tangent = _tangent_towards(axis, previous)
    return math.cos(twist) * axis + math.sin(twist) * (math.cos(angle) * tangent
                                                      + math.sin(angle) * np.cross(axis, tangent))


def joint_angles(axes):
    """The angles θ1, θ2, θ3 and the branch of a closed spherical hexagon u1..u6.

    θₖ is the angle at the vertex uₖ, right-handed about uₖ, from the arc towards u(k−1) to the
    arc towards u(k+1); the branch is the sign of det[u4, u6, u5].

    Parameters
    ----------
    axes : array_like, shape=[6, 3]
        Unit axes u1..u6.

    Returns
    -------
    angles : tuple of three float
    branch : int
    """
    axes = np.asarray(axes, dtype=float)
    angles = []
    for index in range(3):
        axis, previous, following = axes[index], axes[index - 1], axes[index + 1]
        tangent = _tangent_towards(axis, previous)
        direction = _tangent_towards(axis, following)
        angles.append(math.atan2(np.cross(axis, tangent) @ direction, tangent @ direction))
    branch = 1 if np.linalg.det(np.stack([axes[3], axes[5], axes[4]])) > 0 else -1
    return tuple(angles), branch


def symmetric_hexagon(twist):
    """The threefold-symmetric hexagon of twist α with the even axes coplanar (equatorial).

    Parameters
    ----------
    twist : float
        α (rad), 0 < α < π/2 with 2 cos α ≤ 1.

    Returns
    -------
    ndarray, shape=[6, 3]
        uₖ = (sin aₖ cos 60°(k−1), sin aₖ sin 60°(k−1), cos aₖ), a = arcsin(2 cos α) for odd k,
        a = 90° for even k (then uₖ·u(k+1) = sin a · cos 60° = cos α).
    """
    polar_odd = math.asin(2 * math.cos(twist))
    axes = []
    for index in range(6):
        polar = polar_odd if index % 2 == 0 else math.pi / 2
        azimuth = math.radians(60 * index)
        axes.append((math.sin(polar) * math.cos(azimuth), math.sin(polar) * math.sin(azimuth), math.cos(polar)))
    return np.array(axes)


def spherical_six_bar(*, twist=math.radians(70), theta1=1.5, theta2=1.9, theta3=1.4, branch=1,
                      actuated="135"):
    """Spherical 6R loop with equal twists, assembled at the angles of joints J1, J2, J3.

    Parameters
    ----------
    twist : float
        α (rad), the arc between consecutive axes (all six links equal).
    theta1, theta2, theta3 : float
        Angles (rad) at the vertices u1, u2, u3 of the spherical hexagon, right-handed about the
        axis, from the arc towards the previous axis to the arc towards the next one.
    branch : int
        +1 / −1: the sign of det[u4, u6, u5] (the two closures of the dyad J4-J5-J6).
    actuated : str
        The driven joints as digits: ``"135"`` (Fig. 7), ``"134"`` (Fig. 8a, an actuator moved),
        ``"1235"`` (Fig. 8b, redundantly actuated).

    Returns
    -------
    Mechanism
        Spherical joints ``J1`` (ground-link1) ... ``J6`` (link5-ground); u1 = z and u6 in the
        x-z plane at arc α from it.

    Raises
    ------
    MechanismError
        For a twist outside (0, π), a bad `branch` or `actuated`, or angles with which the dyad
        J4-J5-J6 cannot close.

    Notes
    -----
    u1 = (0, 0, 1), u6 = (sin α, 0, cos α); u(k+1) = cos α uₖ + sin α (cos θₖ tₖ + sin θₖ uₖ × tₖ)
    for k = 1, 2, 3, tₖ the unit tangent at uₖ towards u(k−1); u5 = c (u4 + u6) + branch · s n with
    c = cos α / (1 + u4·u6), s = √(1 − 2 c cos α), n = u4 × u6 / ‖u4 × u6‖
    (u5·u4 = u5·u6 = cos α).
    """
    if not 0 < twist < math.pi:
        raise MechanismError(f"spherical-six-bar: twist must be in (0, pi), got {twist}")
    if branch not in (1, -1):
        raise MechanismError(f"spherical-six-bar: branch must be 1 or -1, got {branch}")
    driven = actuated_joints(actuated, "spherical-six-bar")
    axes = [np.array([0.0, 0.0, 1.0])]
    previous = np.array([math.sin(twist), 0.0, math.cos(twist)])
    for angle in (theta1, theta2, theta3):
        axes.append(_next_axis(previous, axes[-1], twist, angle))
        previous = axes[-2]
    last = np.array([math.sin(twist), 0.0, math.cos(twist)])
    normal = np.cross(axes[3], last)
    if np.linalg.norm(normal) < 1e-9:
        raise MechanismError("spherical-six-bar: theta1, theta2, theta3 put u4 on ±u6: the dyad "
                             "J4-J5-J6 has no unique closure")
    scale = math.cos(twist) / (1 + axes[3] @ last)
    height_squared = 1 - 2 * scale * math.cos(twist)
    if height_squared < -1e-12:
        raise MechanismError(f"spherical-six-bar: theta1, theta2, theta3 put u4 at "
                             f"{math.degrees(math.acos(np.clip(axes[3] @ last, -1, 1))):.6g}° from u6, "
                             f"beyond the reach 2α of links 4 and 5")
    axes.append(scale * (axes[3] + last) + branch * math.sqrt(max(height_squared, 0.0))
                * normal / np.linalg.norm(normal))
    axes.append(last)
    joints = [Joint(f"J{number}", "R", (LINKS[number - 1], LINKS[number]), axis=tuple(axes[number - 1]),
                    actuated=number in driven) for number in range(1, 7)]
    return Mechanism("spherical-six-bar", "spherical", joints)


_SYMMETRIC_ANGLES, _SYMMETRIC_BRANCH = joint_angles(symmetric_hexagon(math.radians(70)))
_FIG7 = {"theta1": _SYMMETRIC_ANGLES[0], "theta2": _SYMMETRIC_ANGLES[1], "theta3": _SYMMETRIC_ANGLES[2],
         "branch": _SYMMETRIC_BRANCH}

ENTRIES = (
    Entry("spherical-six-bar", spherical_six_bar,
          "Park & Kim (1999) Case 2, Figs. 7, 8a, 8b",
          {
              "fig7_actuator": {**_FIG7, "actuated": "135"},
              "fig7_actuated_axes_coplanar": {**_FIG7, "actuated": "246"},
              "fig8a_moved_actuator": {**_FIG7, "actuated": "134"},
              "fig8b_added_actuator": {**_FIG7, "actuated": "1235"},
          }),
)
