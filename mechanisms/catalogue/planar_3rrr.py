"""Planar 3-RRR parallel manipulator: Gosselin & Angeles (1990) Fig. 7, eqs. (42)-(65).

Three legs M_i D_i A_i: a motor at M_i drives the proximal link l₁ (angle θ_i),
the distal link l₂ joins the elbow to vertex A_i of the gripper, an
equilateral triangle with circumradius l₃ and centroid (x, y), turned by φ.
The motors sit on an equilateral triangle of side ``base`` (1 in the paper,
eq. 42 ff.): M₁ = (0, 0), M₂ = (b, 0), M₃ = (b/2, b√3/2). Vertex i of the
gripper is (x, y) − l₃ (cos φ_i, sin φ_i) with φ₁ = φ + π/6, φ₂ = φ + 5π/6,
φ₃ = φ − π/2 (eqs. 50-55).

Our reading (Fig. 7 is not in the text): the motor positions above are the
ones that make the statements after eqs. (64)-(65) true — at φ = 0 the
gripper is the base triangle shrunk about its own centroid, so with
l₃ = √3/3 its vertices lie on the motors, and the proximal links at
θ = (−150°, −30°, 90°) point away from the base centroid (eq. 65); with
l₁ = √3/3 the three elbows can meet at the base centroid (eq. 64).
"""

from __future__ import annotations

import inspect
import math

import numpy as np
from scipy.optimize import least_squares

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry, read_only_with

__all__ = ["planar_3rrr", "planar_3rrr_positions", "motor_centres", "gripper_vertices", "leg_aligned_pose",
           "concurrent_distal_pose", "parallel_distal_pose", "ENTRIES"]

#: φ_i − φ of eqs. (50)-(52).
_VERTEX_OFFSETS = (math.pi / 6, 5 * math.pi / 6, -math.pi / 2)
#: Relative tolerance on a leg that just fails to close (rounding at a stretched or folded leg).
_REACH_TOLERANCE = 1e-9


def motor_centres(base=1.0):
    """M₁, M₂, M₃ (ndarray, shape=[3, 2]): the vertices of the base triangle of side `base`."""
    return base * np.array([[0.0, 0.0], [1.0, 0.0], [0.5, math.sqrt(3.0) / 2]])


def gripper_vertices(x, y, phi, l3):
    """A_i = (x, y) − l₃ (cos φ_i, sin φ_i), G-A eqs. (50)-(55) (ndarray, shape=[3, 2])."""
    angles = phi + np.array(_VERTEX_OFFSETS)
    return np.array([x, y]) - l3 * np.stack([np.cos(angles), np.sin(angles)], axis=-1)


def planar_3rrr_positions(*, base, l1, l2, l3, x, y, phi, modes, thetas):
    """Motor, elbow and gripper-vertex positions of the three legs (inverse kinematics).

    Parameters
    ----------
    base, l1, l2, l3 : float
        Side of the motor triangle, proximal and distal link lengths, gripper circumradius.
    x, y, phi : float
        Gripper pose: centroid and orientation φ (rad).
    modes : sequence of three int in {1, -1, 0}
        Working mode γ_i of leg i (eq. 56): ±1, the elbow on the left (+1) or right (−1) of
        M_i → A_i, i.e. θ_i = atan2(A_i − M_i) + γ_i ψ_i with ψ_i of eq. (53); 0: θ_i is given.
    thetas : sequence of three float
        θ_i (rad) of the legs whose mode is 0 (the others are ignored).

    Returns
    -------
    motors, elbows, vertices : ndarray, shape=[3, 2]
    thetas : tuple of float
        The input angles θ_i.

    Raises
    ------
    MechanismError
        Naming the parameter, when a leg cannot reach its vertex.
    """
    motors = motor_centres(base)
    vertices = gripper_vertices(x, y, phi, l3)
    elbows, inputs = [], []
    for leg, (motor, vertex, mode, theta) in enumerate(zip(motors, vertices, modes, thetas), start=1):
        reach = vertex - motor
        distance = float(np.hypot(*reach))
        if mode == 0:
            elbow = motor + l1 * np.array([math.cos(theta), math.sin(theta)])
            gap = float(np.hypot(*(vertex - elbow))) - l2
            if abs(gap) > _REACH_TOLERANCE * max(1.0, l2):
                raise MechanismError(f"planar-3rrr: theta{leg} = {theta} with mode{leg} = 0: the distal link "
                                     f"does not reach the gripper (‖D{leg} A{leg}‖ − l2 = {gap:.3g})")
        else:
            if distance < _REACH_TOLERANCE * max(1.0, l1):
                raise MechanismError(f"planar-3rrr: vertex {leg} is on motor {leg}, θ{leg} is free: "
                                     f"give it with mode{leg} = 0 and theta{leg}")
            cosine = (l1 ** 2 - l2 ** 2 + distance ** 2) / (2 * l1 * distance)  # eq. (53)
            if abs(cosine) > 1 + _REACH_TOLERANCE:
                raise MechanismError(f"planar-3rrr: pose x = {x}, y = {y}, phi = {phi}: leg {leg} cannot "
                                     f"reach its vertex (‖M{leg} A{leg}‖ = {distance:.6g}, "
                                     f"l1 = {l1}, l2 = {l2})")
            theta = math.atan2(reach[1], reach[0]) + mode * math.acos(max(-1.0, min(1.0, cosine)))
            elbow = motor + l1 * np.array([math.cos(theta), math.sin(theta)])
        elbows.append(elbow)
        inputs.append(theta)
    return motors, np.array(elbows), vertices, tuple(inputs)


def planar_3rrr(*, base=1.0, l1=0.5, l2=0.4, l3=0.2, x=0.5, y=0.3, phi=0.2, mode1=1, mode2=1, mode3=1,
                theta1=math.radians(-150), theta2=math.radians(-30), theta3=math.radians(90),
                end_effector=True):
    """Planar 3-RRR (G-A Fig. 7) with fixed motors, assembled at the gripper pose (x, y, φ).

    Parameters
    ----------
    base : float
        Distance between two motors (1 in the paper).
    l1, l2, l3 : float
        Proximal link l₁, distal link l₂, gripper circumradius l₃ (eqs. 42, 54-55). The paper
        gives no numbers; the defaults are a generic design.
    x, y, phi : float
        Gripper centroid and orientation φ (rad), eqs. (50)-(55).
    mode1, mode2, mode3 : {1, -1, 0}
        Working mode γ_i (eq. 56): the elbow left (+1) or right (−1) of M_i → A_i; 0: the leg's
        input θ_i is given (where the vertex sits on the motor, eq. 65, the inverse
        kinematics leaves θ_i free).
    theta1, theta2, theta3 : float
        θ_i (rad) for the legs with mode 0; default the values of eq. (65), −150°, −30°, 90°. Read only
        for those legs (the catalogue entry refuses θ_i set for a leg of mode ±1).
    end_effector : bool
        Whether the gripper's pose (at its centroid) is the end-effector.

    Returns
    -------
    Mechanism
        Joints ``motor{i}`` (ground-proximal{i}, actuated), ``elbow{i}`` (proximal{i}-distal{i}),
        ``wrist{i}`` (distal{i}-gripper), i = 1, 2, 3.

    Notes
    -----
    G-A eq. (43): A ṡ + B θ̇ = 0, B = diag(d_i), d_i ∝ sin ψ_i (eq. 48). Kind I: a leg stretched
    or folded (eq. 58). Kind II: the distal links' lines concurrent (eq. 61) or parallel
    (eq. 63). Kind III designs: eqs. (64), (65).
    """
    for name, value in {"base": base, "l1": l1, "l2": l2, "l3": l3}.items():
        if not value > 0:
            raise MechanismError(f"planar-3rrr: {name} must be positive, got {value}")
    modes = (mode1, mode2, mode3)
    for leg, mode in enumerate(modes, start=1):
        if mode not in (-1, 0, 1):
            raise MechanismError(f"planar-3rrr: mode{leg} must be 1, -1 or 0, got {mode}")
    motors, elbows, vertices, _ = planar_3rrr_positions(
        base=base, l1=l1, l2=l2, l3=l3, x=x, y=y, phi=phi, modes=modes, thetas=(theta1, theta2, theta3))
    joints = []
    for leg in range(3):
        i = leg + 1
        joints += [
            Joint(f"motor{i}", "R", ("ground", f"proximal{i}"), point=tuple(motors[leg]), actuated=True),
            Joint(f"elbow{i}", "R", (f"proximal{i}", f"distal{i}"), point=tuple(elbows[leg])),
            Joint(f"wrist{i}", "R", (f"distal{i}", "gripper"), point=tuple(vertices[leg])),
        ]
    return Mechanism("planar-3rrr", "planar", joints,
                     end_effector=EndEffector("gripper", (float(x), float(y)), "pose") if end_effector else None)


def _modes_of(motors, elbows, vertices):
    """γ_i of assembled legs: the side of M_i → A_i the elbow is on."""
    modes = []
    for motor, elbow, vertex in zip(motors, elbows, vertices):
        reach, arm = vertex - motor, elbow - motor
        modes.append(1 if reach[0] * arm[1] - reach[1] * arm[0] >= 0 else -1)
    return modes


def concurrent_distal_pose(*, base, l1, l2, l3, folded=False, side=1):
    """A symmetric pose where the three distal links point at the base centroid (eq. 61).

    With the gripper centroid on the base centroid c, the configuration is invariant under the
    rotation by 2π/3 about c, so the three distal lines are concurrent as soon as one of them
    passes through c: A₁ = c − l₃ e(φ₁) and D₁ = c − (l₃ ± l₂) e(φ₁)
    with ‖D₁ − M₁‖ = l₁.

    Parameters
    ----------
    base, l1, l2, l3 : float
        The design.
    folded : bool
        D₁ between c and A₁ (‖c D₁‖ = ‖l₃ − l₂‖, True) or beyond A₁ (l₃ + l₂, False).
    side : {1, -1}
        Which intersection of the circles ‖c D₁‖ = const and ‖M₁ D₁‖ = l₁.

    Returns
    -------
    dict
        ``x``, ``y``, ``phi``, ``mode1``, ``mode2``, ``mode3`` for :func:`planar_3rrr`.

    Raises
    ------
    MechanismError
        If the design has no such pose.
    """
    motors = motor_centres(base)
    centre = motors.mean(axis=0)
    radius = abs(l3 - l2) if folded else l3 + l2
    chord = motors[0] - centre
    distance = float(np.hypot(*chord))
    cosine = (radius ** 2 + distance ** 2 - l1 ** 2) / (2 * radius * distance)
    if abs(cosine) > 1:
        raise MechanismError(f"planar-3rrr: no pose with the distal links concurrent at the centroid "
                             f"(l1 = {l1}, l2 = {l2}, l3 = {l3})")
    direction = math.atan2(chord[1], chord[0]) + side * math.acos(cosine)  # of D₁ − c
    outward = direction if (not folded or l3 > l2) else direction + math.pi  # of A₁ − c
    phi = outward + math.pi - _VERTEX_OFFSETS[0]  # A₁ − c = −l₃ e(φ + π/6)
    pose = {"x": float(centre[0]), "y": float(centre[1]), "phi": phi}
    return {**pose, **_modes_for(base=base, l1=l1, l2=l2, l3=l3, pose=pose,
                                 elbow=centre + radius * np.array([math.cos(direction), math.sin(direction)]))}


def _modes_for(*, base, l1, l2, l3, pose, elbow):
    """The working modes whose leg-1 elbow is at `elbow` (the others follow by symmetry)."""
    for mode in (1, -1):
        _, elbows, _, _ = planar_3rrr_positions(base=base, l1=l1, l2=l2, l3=l3, **pose,
                                                modes=(mode,) * 3, thetas=(0.0,) * 3)
        if np.hypot(*(elbows[0] - elbow)) < 1e-9:
            return {"mode1": mode, "mode2": mode, "mode3": mode}
    raise MechanismError("planar-3rrr: no working mode puts the elbow at the requested point")


def parallel_distal_pose(*, base, l1, l2, l3, direction, guess=(0.5, 0.3, 0.0)):
    """A pose where the three distal links are parallel to e(`direction`) (eq. 63), solved numerically.

    Unknowns (x, y, φ); equations ‖A_i − l₂ e(direction) − M_i‖² = l₁², i = 1, 2, 3: the
    elbows D_i = A_i − l₂ e(direction) on the motors' circles. Solved with
    :func:`scipy.optimize.least_squares` from `guess`, then checked.

    Parameters
    ----------
    base, l1, l2, l3 : float
        The design.
    direction : float
        Angle (rad) of the distal links D_i → A_i.
    guess : tuple of three float
        Starting (x, y, φ).

    Returns
    -------
    dict
        ``x``, ``y``, ``phi``, ``mode1``, ``mode2``, ``mode3`` for :func:`planar_3rrr`.

    Raises
    ------
    MechanismError
        If the solve does not close the legs to 1e-12.
    """
    motors = motor_centres(base)
    along = l2 * np.array([math.cos(direction), math.sin(direction)])

    def residual(pose):
        elbows = gripper_vertices(*pose, l3) - along
        return np.sum((elbows - motors) ** 2, axis=-1) - l1 ** 2

    solution = least_squares(residual, guess, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    if np.max(np.abs(residual(solution.x))) > 1e-12:
        raise MechanismError(f"planar-3rrr: no pose with the distal links parallel to direction = {direction} "
                             f"found from guess = {guess}")
    x, y, phi = (float(value) for value in solution.x)
    vertices = gripper_vertices(x, y, phi, l3)
    modes = _modes_of(motors, vertices - along, vertices)
    return {"x": x, "y": y, "phi": phi, "mode1": modes[0], "mode2": modes[1], "mode3": modes[2]}


def leg_aligned_pose(*, base, l1, l2, l3, phi, heading, stretched=True, modes=(1, 1, 1)):
    """The pose at orientation φ with leg 1 stretched or folded along `heading` (eq. 58).

    A₁ = M₁ + (l₁ ± l₂) e(heading), then (x, y) = A₁ + l₃ e(φ₁) (eq. 54). Leg 1's input is given
    (mode 0): θ₁ = heading, or heading + π for a folded leg with l₁ < l₂. Solved from the pose instead,
    ψ₁ of eq. (53) is the double root of an arccosine, found only to √ε ≈ 1e-8 (whether the rounded
    cosine lands on 1 or just below depends on the floating-point library), not to rounding.

    Parameters
    ----------
    base, l1, l2, l3 : float
        The design.
    phi : float
        Gripper orientation φ (rad).
    heading : float
        Direction (rad) of A₁ seen from M₁.
    stretched : bool
        l₁ and l₂ end to end (True) or folded (False).
    modes : tuple of three int
        Working modes of the legs; leg 1's is not used (its two modes coincide there, θ₁ is given).

    Returns
    -------
    dict
        ``x``, ``y``, ``phi``, ``mode1`` (0), ``theta1``, ``mode2``, ``mode3`` for :func:`planar_3rrr`.
    """
    reach = l1 + l2 if stretched else abs(l1 - l2)
    vertex = motor_centres(base)[0] + reach * np.array([math.cos(heading), math.sin(heading)])
    angle = phi + _VERTEX_OFFSETS[0]
    centre = vertex + l3 * np.array([math.cos(angle), math.sin(angle)])
    elbow_turn = math.pi if not stretched and l1 < l2 else 0.0
    return {"x": float(centre[0]), "y": float(centre[1]), "phi": phi,
            "mode1": 0, "theta1": heading + elbow_turn, "mode2": modes[1], "mode3": modes[2]}


def _elbows_towards(point, base=1.0):
    """θ₁, θ₂, θ₃ (mode 0) that point each proximal link from its motor towards `point` (x, y)."""
    values = {}
    for leg, motor in enumerate(motor_centres(base), start=1):
        values[f"mode{leg}"] = 0
        values[f"theta{leg}"] = math.atan2(point["y"] - motor[1], point["x"] - motor[0])
    return values


#: The default design of :func:`planar_3rrr` (the named configurations are computed for it).
DEFAULT_DESIGN = {name: inspect.signature(planar_3rrr).parameters[name].default
                  for name in ("base", "l1", "l2", "l3")}
#: Kind-III designs, eqs. (64) and (65), with the paper's unit base.
EQ64_DESIGN = {"base": 1.0, "l1": math.sqrt(3.0) / 3, "l2": 0.25, "l3": 0.25}
EQ65_DESIGN = {"base": 1.0, "l1": 0.4, "l2": 0.4, "l3": math.sqrt(3.0) / 3}
#: The base centroid, where the kind-III configurations put the gripper's centroid.
_CENTROID = {"x": 0.5, "y": math.sqrt(3.0) / 6}

ENTRIES = (
    Entry("planar-3rrr", planar_3rrr,
          "Gosselin & Angeles (1990) Fig. 7, eqs. (42)-(65)",
          {
              # Kind I, eq. (58): leg 1 stretched / folded (sin ψ₁ = 0).
              "eq58_leg_stretched": leg_aligned_pose(**DEFAULT_DESIGN, phi=0.2, heading=math.radians(40)),
              "eq58_leg_folded": leg_aligned_pose(**DEFAULT_DESIGN, phi=0.2, heading=math.radians(40),
                                                  stretched=False),
              # Kind II, eq. (61): the distal links' lines meet (Fig. 8) ...
              "eq61_distal_links_concurrent": concurrent_distal_pose(**DEFAULT_DESIGN),
              # ... and eq. (63): the distal links parallel.
              "eq63_distal_links_parallel": parallel_distal_pose(**DEFAULT_DESIGN, direction=math.radians(100)),
              # Kind III, eq. (64): elbows on the base centroid, gripper centroid there too, φ = 0 ...
              # (the legs folded, both working modes meeting: the inputs given, not solved from the pose's
              # double roots)
              "eq64_elbows_at_centroid": {**EQ64_DESIGN, **_CENTROID, "phi": 0.0, **_elbows_towards(_CENTROID)},
              # ... and turned (the gripper turns freely about its centroid with the motors locked).
              "eq64_elbows_at_centroid_turned": {**EQ64_DESIGN, **_CENTROID, "phi": 0.5,
                                                 "mode1": 1, "mode2": 1, "mode3": 1},
              # Kind III, eq. (65): gripper vertices on the motors, φ = 0, θ = (−150°, −30°, 90°).
              "eq65_vertices_on_motors": {**EQ65_DESIGN, **_CENTROID, "phi": 0.0,
                                          "mode1": 0, "mode2": 0, "mode3": 0},
              # ... and with other inputs: the motors turn freely while the gripper stays at rest.
              "eq65_vertices_on_motors_other_inputs": {**EQ65_DESIGN, **_CENTROID, "phi": 0.0,
                                                       "mode1": 0, "mode2": 0, "mode3": 0,
                                                       "theta1": 0.3, "theta2": 1.0, "theta3": -2.0},
          },
          read_only={f"theta{leg}": read_only_with(f"mode{leg}", 0) for leg in (1, 2, 3)}),
)
