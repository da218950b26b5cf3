"""The spherical 3-RRR parallel wrist: Gosselin & Angeles eqs. (66)-(70), Fig. 9.

Three legs, each a motor (axis uᵢ, fixed), an intermediate joint (axis wᵢ)
and a gripper joint (axis vᵢ), every axis through the centre of the sphere;
the proximal links span the arc α₁ = ∠(uᵢ, wᵢ) and the distal links the arc
α₂ = ∠(wᵢ, vᵢ), the same for every leg (eq. 66). As the paper states for its
symmetric layout, the motor axes lie in one plane, 120° apart, and so do the
gripper axes (Gosselin & Angeles 1990 Section VI). The velocity relation
is A ω + B θ̇ = 0 with A rows (wᵢ × vᵢ)ᵀ (eq. 68) and
B = diag((wᵢ × uᵢ)·vᵢ) (eq. 69).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry, ReadOnly

__all__ = ["spherical_3rrr", "motor_axes", "folded_legs", "leg_axes", "ENTRIES"]

#: tolerance on ‖uᵢ × vᵢ‖ below which a leg is folded onto its motor axis
_FOLDED = 1e-12


def motor_axes():
    """The unit motor axes uᵢ: in the base plane z = 0, 120° apart, shape=[3, 3].

    The gripper axes in the gripper frame are the same vectors, so that at
    Q = 1 the gripper axes coincide with the motor axes (vᵢ = uᵢ).
    """
    angles = 2 * np.pi * np.arange(3) / 3
    return np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], axis=-1)


def folded_legs(rotation_x, rotation_y, rotation_z):
    """The legs (1, 2, 3) whose gripper axis vᵢ = Q uᵢ lies on the motor axis uᵢ (vᵢ = ±uᵢ), where the input θ
    is free (:func:`leg_axes` places wᵢ by `theta_folded` there).

    Parameters
    ----------
    rotation_x, rotation_y, rotation_z : float
        The gripper orientation as a rotation vector (rad), as :func:`spherical_3rrr`.

    Returns
    -------
    tuple of int
    """
    orientation = Rotation.from_rotvec([rotation_x, rotation_y, rotation_z]).as_matrix()
    return tuple(leg for leg, motor in enumerate(motor_axes(), start=1)
                 if np.linalg.norm(np.cross(motor, orientation @ motor)) < _FOLDED)


def leg_axes(motor, gripper, alpha1, alpha2, working_mode, theta_folded=0.0, leg=1):
    """The intermediate axis w of one leg, from its motor axis u and gripper axis v.

    Parameters
    ----------
    motor, gripper : array_like, shape=[3]
        Unit vectors u and v.
    alpha1, alpha2 : float
        α₁ = ∠(u, w) and α₂ = ∠(w, v) (rad).
    working_mode : {1, -1}
        The side of the plane (u, v) on which w lies: the sign of (u × v)·w.
    theta_folded : float
        Where u = ±v (possible only for α₁ = α₂, resp. α₁ + α₂ = π) w is any
        point of a circle about u; θ is its angle from the base plane z = 0.
    leg : int
        Leg number, for error messages.

    Returns
    -------
    ndarray, shape=[3]
        The unit vector w.

    Notes
    -----
    With cos γ = u·v, w = a u + b v + c (u × v)/‖u × v‖ where
    a = (cos α₁ − cos α₂ cos γ)/sin²γ, b = (cos α₂ − cos α₁ cos γ)/sin²γ and
    c = ±√(1 − a² − b² − 2ab cos γ): the two working modes (the inverse
    kinematics of a leg, whose branches meet where the leg is fully extended
    or folded: eq. (70)).

    Raises
    ------
    MechanismError
        If v is out of the reach of the leg.
    """
    motor, gripper = np.asarray(motor, dtype=float), np.asarray(gripper, dtype=float)
    cosine = float(np.clip(motor @ gripper, -1.0, 1.0))
    normal = np.cross(motor, gripper)
    sine = float(np.linalg.norm(normal))
    if sine < _FOLDED:
        reach = alpha1 - alpha2 if cosine > 0 else alpha1 + alpha2 - np.pi
        if abs(reach) > 1e-9:
            raise MechanismError(f"spherical-3rrr: leg {leg}: the gripper axis coincides with the motor axis "
                                 f"(v = {'+' if cosine > 0 else '−'}u), reachable only when "
                                 f"{'α₁ = α₂' if cosine > 0 else 'α₁ + α₂ = π'}; got alpha1 = {alpha1}, "
                                 f"alpha2 = {alpha2}")
        tangent = np.cross((0.0, 0.0, 1.0), motor)
        tangent /= np.linalg.norm(tangent)
        circle = math.cos(theta_folded) * tangent + math.sin(theta_folded) * np.array([0.0, 0.0, 1.0])
        return math.cos(alpha1) * motor + math.sin(alpha1) * circle
    first = (math.cos(alpha1) - math.cos(alpha2) * cosine) / sine ** 2
    second = (math.cos(alpha2) - math.cos(alpha1) * cosine) / sine ** 2
    height = 1.0 - first ** 2 - second ** 2 - 2 * first * second * cosine
    if abs(height) < 1e-12:  # fully extended or folded to rounding: w in the plane (u, v)
        height = 0.0
    if height < 0:
        angle = math.degrees(math.acos(cosine))
        raise MechanismError(f"spherical-3rrr: leg {leg}: the gripper orientation (rotation_x, rotation_y, "
                             f"rotation_z) is out of reach: ∠(u, v) = {angle:.6g}° is outside "
                             f"[‖α₁ − α₂‖, α₁ + α₂] = [{math.degrees(abs(alpha1 - alpha2)):.6g}°, "
                             f"{math.degrees(alpha1 + alpha2):.6g}°]")
    return first * motor + second * gripper + working_mode * math.sqrt(height) * normal / sine


def spherical_3rrr(*, alpha1=math.pi / 3, alpha2=math.pi / 4, rotation_x=0.3, rotation_y=-0.2,
                   rotation_z=1.0, working_mode_1=1, working_mode_2=1, working_mode_3=1,
                   theta_folded=0.0, end_effector=True):
    """Spherical 3-RRR parallel wrist assembled at the gripper orientation Q, motors driven.

    Parameters
    ----------
    alpha1, alpha2 : float
        Link angles α₁ (motor to intermediate axis) and α₂ (intermediate to
        gripper axis), the same for the three legs (G-A eq. 66), rad. The paper
        gives no numbers: the defaults α₁ = π/3, α₂ = π/4 are a design of ours,
        with α₁ ≠ α₂ and α₁ + α₂ ≠ π, so that no leg can fold onto its motor
        axis (the special designs of Section VI are named configurations).
    rotation_x, rotation_y, rotation_z : float
        The gripper orientation Q = exp([r]ₓ) as a rotation vector r in the
        base frame (rad); the gripper axes are vᵢ = Q uᵢ (:func:`motor_axes`).
    working_mode_1, working_mode_2, working_mode_3 : {1, -1}
        Working mode of each leg: the sign of (uᵢ × vᵢ)·wᵢ (G-A eq. 69 has
        Bᵢᵢ = (wᵢ × uᵢ)·vᵢ = (uᵢ × vᵢ)·wᵢ = working_mode ‖Bᵢᵢ‖).
    theta_folded : float
        Input angle θ (rad, from the base plane) of a leg folded onto its
        motor axis (vᵢ = uᵢ, reachable when α₁ = α₂ at Q = 1), where the
        orientation leaves it free (:func:`folded_legs`); unused otherwise (the
        catalogue entry refuses it set there).
    end_effector : bool
        Whether the gripper orientation is the end-effector.

    Returns
    -------
    Mechanism
        Spherical; joints ``motor{i}`` (ground-proximal{i}, axis uᵢ, actuated),
        ``elbow{i}`` (proximal{i}-distal{i}, axis wᵢ), ``wrist{i}``
        (distal{i}-gripper, axis vᵢ), i = 1, 2, 3.

    Raises
    ------
    MechanismError
        Naming the parameter: non-positive link angles, a working mode other
        than ±1, an orientation out of reach of a leg.

    Notes
    -----
    Each wᵢ follows from uᵢ, vᵢ = Q uᵢ and the working mode in closed form
    (:func:`leg_axes`). The paper's Jacobians (eqs. 68-69) are
    A = [(wᵢ × vᵢ)ᵀ] and B = diag((wᵢ × uᵢ)·vᵢ): kind I where a leg is fully
    extended or folded (eq. 70), kind II where the wᵢ × vᵢ are coplanar.

    References
    ----------
    Gosselin & Angeles 1990 Section VI, Fig. 9, eqs. (66)-(70).
    """
    for name, value in (("alpha1", alpha1), ("alpha2", alpha2)):
        if not 0 < value < math.pi:
            raise MechanismError(f"spherical-3rrr: {name} must be in (0, π), got {value}")
    modes = (working_mode_1, working_mode_2, working_mode_3)
    for index, mode in enumerate(modes, start=1):
        if mode not in (1, -1):
            raise MechanismError(f"spherical-3rrr: working_mode_{index} must be 1 or -1, got {mode}")
    orientation = Rotation.from_rotvec([rotation_x, rotation_y, rotation_z]).as_matrix()
    motors = motor_axes()
    joints = []
    for index, (motor, mode) in enumerate(zip(motors, modes), start=1):
        gripper = orientation @ motor
        elbow = leg_axes(motor, gripper, alpha1, alpha2, mode, theta_folded, leg=index)
        joints += [
            Joint(f"motor{index}", "R", ("ground", f"proximal{index}"), axis=tuple(motor), actuated=True),
            Joint(f"elbow{index}", "R", (f"proximal{index}", f"distal{index}"), axis=tuple(elbow)),
            Joint(f"wrist{index}", "R", (f"distal{index}", "gripper"), axis=tuple(gripper)),
        ]
    return Mechanism("spherical-3rrr", "spherical", joints,
                     end_effector=EndEffector("gripper", None, "orientation") if end_effector else None)


def _rotation_vector(precession, nutation, spin=0.0):
    """The rotation vector of Q = R_z(precession) R_x(nutation) R_z(spin), as plain floats."""
    vector = Rotation.from_euler("ZXZ", [precession, nutation, spin]).as_rotvec()
    return dict(zip(("rotation_x", "rotation_y", "rotation_z"), (float(value) for value in vector)))


ENTRIES = (
    Entry("spherical-3rrr", spherical_3rrr,
          "Gosselin & Angeles (1990) Section VI, Fig. 9, eqs. (66)-(70)",
          {
              # leg 1 fully extended, ∠(u₁, v₁) = α₁ + α₂ (rotation about an axis ⟂ u₁): eq. (70)
              "eq70_leg1_extended": {"rotation_x": 0.0,
                                     "rotation_y": 7 * math.pi / 12 * math.cos(1.1),
                                     "rotation_z": 7 * math.pi / 12 * math.sin(1.1)},
              # leg 1 folded, ∠(u₁, v₁) = α₁ − α₂: eq. (70)
              # (Q = R_z(α₁ − α₂) R_x(0.8): u₁ at α₁ − α₂ from v₁, the other legs within reach)
              "eq70_leg1_folded": _rotation_vector(math.pi / 12, 0.8),
              # gripper in the base plane, distal links orthogonal to it: cos ψ = cos α₁ / cos α₂ (eq. 68)
              "eq68_distal_links_orthogonal": {"rotation_x": 0.0, "rotation_y": 0.0,
                                               "rotation_z": math.acos(math.cos(math.pi / 3)
                                                                       / math.cos(math.pi / 4))},
              # α₁ = α₂: the legs folded onto the motor axes, uᵢ = vᵢ (Section VI, "first set")
              "section6_equal_alphas_folded": {"alpha1": math.pi / 3, "alpha2": math.pi / 3, "rotation_x": 0.0,
                                     "rotation_y": 0.0, "rotation_z": 0.0, "theta_folded": 0.7},
              # α₁ = α₂ = π/2, vᵢ coplanar with uᵢ: the gripper spins about the normal (Section VI)
              "section6_right_alphas_coplanar": {"alpha1": math.pi / 2, "alpha2": math.pi / 2, "rotation_x": 0.0,
                                       "rotation_y": 0.0, "rotation_z": 1.0},
          },
          read_only={"theta_folded": ReadOnly(
              "where a leg is folded onto its motor axis (vᵢ = ±uᵢ; none is at this orientation)",
              lambda values: bool(folded_legs(values["rotation_x"], values["rotation_y"], values["rotation_z"])))}),
)
