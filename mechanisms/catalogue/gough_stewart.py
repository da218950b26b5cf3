"""The Gough–Stewart platform (6-UPS): Gosselin & Angeles eqs. (71)-(87), Figs. 10-12.

Six legs join base points Bᵢ (universal joints) to platform points Pᵢ
(spherical joints) through actuated prismatic joints of lengths cᵢ. The
points lie on circles of radii R_B (base, eq. 71) and R_P (platform, eq. 73),
grouped by pairs at the angles θᵢ (eq. 72) and ηᵢ (eq. 74) built from φ_B and
φ_P. The platform pose is its centre x and orientation Q; the velocity
relation is A ẏ + B ċ = 0 with rows aᵢ = [wᵢᵀ, ((Q p′ᵢ) × wᵢ)ᵀ] (eq. 82),
wᵢ = Pᵢ − Bᵢ (eq. 80) and B = diag(cᵢ) (eq. 83)
(Gosselin & Angeles 1990 Section VII).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry

__all__ = ["gough_stewart", "attachment_angles", "base_points", "platform_points", "ENTRIES"]

#: leg length below which a leg counts as collapsed (cᵢ = 0, eq. 84)
_COLLAPSED = 1e-12


def attachment_angles(phi):
    """The six angles of eq. (72) (φ = φ_B, giving θ) or eq. (74) (φ = φ_P, giving η), shape=[6]."""
    third = 2 * math.pi / 3
    return np.array([phi, third - phi, third + phi, 2 * third - phi, 2 * third + phi, -phi])


def _circle(radius, angles):
    return np.stack([radius * np.cos(angles), radius * np.sin(angles), np.zeros_like(angles)], axis=-1)


def base_points(base_radius, base_angle):
    """bᵢ = R_B (cos θᵢ, sin θᵢ, 0) (eq. 71), shape=[6, 3]."""
    return _circle(base_radius, attachment_angles(base_angle))


def platform_points(platform_radius, platform_angle):
    """p′ᵢ = R_P (cos ηᵢ, sin ηᵢ, 0) in the platform frame (eq. 73), shape=[6, 3]."""
    return _circle(platform_radius, attachment_angles(platform_angle))


def _universal_axes(direction):
    """Two axes ⟂ the leg: the first horizontal (fixed in the base), the second completing them."""
    first = np.cross((0.0, 0.0, 1.0), direction)
    if np.linalg.norm(first) < 1e-9:
        first = np.array([1.0, 0.0, 0.0])
    first /= np.linalg.norm(first)
    return first, np.cross(direction, first)


def gough_stewart(*, base_radius=1.0, platform_radius=0.5, base_angle=math.pi / 18,
                  platform_angle=math.pi / 3 - math.pi / 18, x=0.0, y=0.0, z=1.0,
                  rotation_x=0.0, rotation_y=0.0, rotation_z=0.0, end_effector=True):
    """Gough–Stewart platform (6-UPS) assembled at the platform pose (x, Q), legs driven.

    Parameters
    ----------
    base_radius, platform_radius : float
        R_B and R_P, radii of the circles of the base and platform joints (eqs. 71, 73).
    base_angle, platform_angle : float
        φ_B and φ_P (rad): half the angular gap within a pair of joints (eqs. 72, 74).
        The paper gives no numbers: the defaults R_B = 1, R_P = 0.5, φ_B = π/18 (10°),
        φ_P = π/3 − π/18 (50°) are a design of ours.
    x, y, z : float
        The platform centre x = (x, y, z) in the base frame (eqs. 76-78).
    rotation_x, rotation_y, rotation_z : float
        The platform orientation Q = exp([r]ₓ) as a rotation vector r (rad).
    end_effector : bool
        Whether the platform pose is the end-effector (frame at the platform centre).

    Returns
    -------
    Mechanism
        Spatial; for i = 1..6, joints ``U{i}`` (ground-cylinder{i}, at Bᵢ, first
        axis horizontal ⟂ the leg), ``P{i}`` (cylinder{i}-piston{i}, along the
        leg eᵢ, actuated: the length cᵢ), ``S{i}`` (piston{i}-platform, at Pᵢ).
        A collapsed leg (cᵢ = 0, eq. 84) has no direction; it is taken vertical.

    Raises
    ------
    MechanismError
        For non-positive radii.

    Notes
    -----
    The legs are the vectors wᵢ = x + Q p′ᵢ − bᵢ = (Uᵢ, Vᵢ, Wᵢ) of eqs. (76)-(78),
    of lengths cᵢ = ‖wᵢ‖ (eq. 75): the inverse kinematics, in closed form.

    References
    ----------
    Gosselin & Angeles 1990 Section VII, Figs. 10-12, eqs. (71)-(87).
    """
    for name, value in (("base_radius", base_radius), ("platform_radius", platform_radius)):
        if not value > 0:
            raise MechanismError(f"gough-stewart: {name} must be positive, got {value}")
    orientation = Rotation.from_rotvec([rotation_x, rotation_y, rotation_z]).as_matrix()
    centre = np.array([x, y, z], dtype=float)
    bases = base_points(base_radius, base_angle)
    platforms = centre + platform_points(platform_radius, platform_angle) @ orientation.T
    joints = []
    for index, (base, platform) in enumerate(zip(bases, platforms), start=1):
        leg = platform - base
        length = np.linalg.norm(leg)
        direction = leg / length if length > _COLLAPSED else np.array([0.0, 0.0, 1.0])
        joints += [
            Joint(f"U{index}", "U", ("ground", f"cylinder{index}"), point=tuple(base),
                  axes=tuple(tuple(axis) for axis in _universal_axes(direction))),
            Joint(f"P{index}", "P", (f"cylinder{index}", f"piston{index}"), axis=tuple(direction),
                  actuated=True),
            Joint(f"S{index}", "S", (f"piston{index}", "platform"), point=tuple(platform)),
        ]
    return Mechanism("gough-stewart", "spatial", joints,
                     end_effector=EndEffector("platform", tuple(centre), "pose") if end_effector else None)


def _collapsed_leg_pose(rotation=(-0.3, 0.2, 0.4)):
    """A pose of the default design with leg 1 of zero length: x = b₁ − Q p′₁ (eq. 84)."""
    orientation = Rotation.from_rotvec(rotation).as_matrix()
    centre = base_points(1.0, math.pi / 18)[0] - orientation @ platform_points(0.5, math.pi / 3 - math.pi / 18)[0]
    pose = dict(zip(("x", "y", "z"), (float(value) for value in centre)))
    pose.update(zip(("rotation_x", "rotation_y", "rotation_z"), (float(value) for value in rotation)))
    return pose


ENTRIES = (
    Entry("gough-stewart", gough_stewart,
          "Gosselin & Angeles (1990) Section VII, Figs. 10-12, eqs. (71)-(87); "
          "Fichter (their ref. [28]) for the ±90° rotation",
          {
              # leg 1 of zero length, cᵢ = 0: B = diag(cᵢ) singular (eq. 84)
              "eq84_leg1_zero_length": _collapsed_leg_pose(),
              # the platform turned ±90° about the vertical: the leg lines are dependent, det A = 0
              # (eq. 82; the singularity of Fichter, ref. [28])
              "fichter_rotated_plus_90": {"rotation_z": math.pi / 2},
              "fichter_rotated_minus_90": {"rotation_z": -math.pi / 2},
              # R_P = R_B, θ = η, Q = 1, all legs of equal length: the legs are parallel (eq. 87)
              "eq87_parallel_legs": {"platform_radius": 1.0, "platform_angle": math.pi / 18, "x": 0.3,
                                     "y": -0.2, "z": 1.0},
          }),
)
