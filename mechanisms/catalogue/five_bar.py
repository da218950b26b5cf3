"""The planar five-bar (5R): Chablat, Wenger & Angeles Fig. 1, eqs. (1)-(13); Park & Kim eq. (8).

Fixed revolutes A at the origin and B = (L0, 0); proximal links AC (L1) and
BD (L3), distal links CP (L2) and DP (L4) meeting at the revolute centre P,
the end-effector point (Chablat, Wenger & Angeles 1998 Fig. 1, eqs. 1-3). The
actuated angles θ1 (of C − A) and θ2 (of D − B) and the coupler angles θ3 (of
P − C) and θ4 (of P − D) are measured from the direction of AB. Park & Kim
(1999 eq. 8, Figs. 1, 6, 13) give no dimensions: our reading of their figures
is the symmetric L0 = 2, L1 = L2 = 1 (Fig. 13: a non-symmetric design).

The singular configurations of Chablat, Wenger & Angeles 1998: the direct-kinematics matrix A (eq. 3b) is
singular iff θ3 − θ4 = kπ (eq. 9); the inverse-kinematics matrix B (eq. 3c) iff
θ3 − θ1 = kπ or θ4 − θ2 = kπ (eqs. 10-13). The working modes (Section 3.3,
Fig. 2) are the sign patterns of B's diagonal, sin(θ3 − θ1) and sin(θ4 − θ2).
"""

from __future__ import annotations

import math

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry, read_only_with

__all__ = ["five_bar", "five_bar_points", "five_bar_inputs", "circle_intersection", "WORKING_MODES", "ENTRIES"]

#: The five joints of the loop, in order, with the links they join.
_LOOP = (("A", ("ground", "proximal_left")), ("C", ("proximal_left", "distal_left")),
         ("P", ("distal_left", "distal_right")), ("D", ("distal_right", "proximal_right")),
         ("B", ("proximal_right", "ground")))
#: Relative tolerance under which a squared distance counts as zero (rounding of the inputs).
_ROUNDING = 1e-12
WORKING_MODES = ("++", "+-", "-+", "--")


def _direction(angle):
    return (math.cos(angle), math.sin(angle))


def _cross(first, second):
    return first[0] * second[1] - first[1] * second[0]


def circle_intersection(centre1, radius1, centre2, radius2, side, where="circle_intersection"):
    """The point at distance `radius1` from `centre1` and `radius2` from `centre2`.

    Parameters
    ----------
    centre1, centre2 : tuple of float, shape=[2]
    radius1, radius2 : float
    side : {1, -1}
        +1: the point to the left of the directed line from `centre1` to `centre2`
        (``cross(centre2 − centre1, point − centre1) > 0``); −1: to the right.
    where : str
        What to name in the error message.

    Returns
    -------
    tuple of float, shape=[2]

    Raises
    ------
    MechanismError
        When the circles do not meet or are concentric. A squared height within
        rounding (``1e-12 · radius1²``) of zero is taken as zero: the two
        solutions merge (the circles touch).
    """
    chord = (centre2[0] - centre1[0], centre2[1] - centre1[1])
    distance = math.hypot(*chord)
    scale = max(radius1, radius2, distance)
    if distance <= _ROUNDING * scale:
        raise MechanismError(f"{where}: the two centres coincide; the intersection is not determined")
    along = (radius1 ** 2 - radius2 ** 2 + distance ** 2) / (2 * distance)
    height_squared = radius1 ** 2 - along ** 2
    if height_squared < -_ROUNDING * scale ** 2:
        raise MechanismError(f"{where}: the circles do not meet (distance {distance:.6g} of centres outside "
                             f"[{abs(radius1 - radius2):.6g}, {radius1 + radius2:.6g}])")
    height = side * math.sqrt(height_squared) if height_squared > _ROUNDING * scale ** 2 else 0.0
    unit = (chord[0] / distance, chord[1] / distance)
    return (centre1[0] + along * unit[0] - height * unit[1], centre1[1] + along * unit[1] + height * unit[0])


def _lengths(base, proximal, distal, proximal_right, distal_right, label="five-bar"):
    """(L0, L1, L2, L3, L4), with L3 = L1 and L4 = L2 when given as 0 (the symmetric design); `label` starts
    the error message."""
    lengths = (base, proximal, distal, proximal_right or proximal, distal_right or distal)
    for name, value in zip(("base", "proximal", "distal", "proximal_right", "distal_right"), lengths):
        if not value > 0:
            raise MechanismError(f"{label}: {name} must be positive, got {value}")
    return lengths


def five_bar_points(*, base=6.0, proximal=8.0, distal=5.0, proximal_right=0.0, distal_right=0.0,
                    theta1=1.8, theta2=1.3, assembly=1, theta3=0.0, label="five-bar", names=None):
    """Joint centres A, C, P, D, B of the five-bar at inputs θ1, θ2 (the direct kinematics).

    Parameters
    ----------
    base, proximal, distal : float
        L0 = ‖AB‖, L1 = ‖AC‖, L2 = ‖CP‖ (Chablat, Wenger & Angeles 1998, Fig. 1).
    proximal_right, distal_right : float
        L3 = ‖BD‖, L4 = ‖DP‖; 0 means L3 = L1, L4 = L2 (the symmetric design of Chablat, Wenger & Angeles 1998).
    theta1, theta2 : float
        Actuated angles (rad): C = L1 (cos θ1, sin θ1), D = B + L3 (cos θ2, sin θ2).
    assembly : {1, -1, 0}
        The direct-kinematics branch: P to the left (+1) or right (−1) of the
        directed line C→D; the two branches meet where θ3 − θ4 = π (or 0, eq. 9).
        0: the elbows coincide (C = D, needs L2 = L4) and P = C + L2 (cos θ3, sin θ3):
        the branch of degenerate configurations where P turns freely (Chablat, Wenger & Angeles 1998, Sec. 3.4,
        Park & Kim Figs. 1c, 1d, 6b).
    theta3 : float
        θ3, the angle of P − C; read only with ``assembly=0``.
    label : str
        What starts the error messages (a mechanism built on this five-bar names itself).
    names : mapping of str to str, optional
        The caller's names of ``theta1``, ``theta2``, ``theta3`` in the error messages (default: these);
        the other parameters keep their names.

    Returns
    -------
    dict of str to tuple of float
        ``{"A": ..., "C": ..., "P": ..., "D": ..., "B": ...}``, each shape=[2].

    Raises
    ------
    MechanismError
        Naming theta1/theta2 when the distal links cannot close the loop, or
        `assembly` when it does not fit the inputs.
    """
    names = {"theta1": "theta1", "theta2": "theta2", "theta3": "theta3", **(names or {})}
    base, proximal, distal, proximal_right, distal_right = _lengths(base, proximal, distal, proximal_right,
                                                                     distal_right, label)
    if assembly not in (1, -1, 0):
        raise MechanismError(f"{label}: assembly must be 1, -1 or 0, got {assembly!r}")
    inputs = f"{names['theta1']} = {theta1}, {names['theta2']} = {theta2}"
    a, b = (0.0, 0.0), (base, 0.0)
    c = tuple(proximal * value for value in _direction(theta1))
    d = tuple(b[i] + proximal_right * _direction(theta2)[i] for i in range(2))
    gap = math.hypot(d[0] - c[0], d[1] - c[1])
    coincide = gap <= _ROUNDING * (base + proximal + proximal_right)
    if assembly == 0:
        if not coincide:
            raise MechanismError(f"{label}: assembly = 0 needs the elbows C and D to coincide; at "
                                 f"{inputs} they are {gap:.6g} apart")
        if not math.isclose(distal, distal_right, rel_tol=1e-12):
            raise MechanismError(f"{label}: assembly = 0 needs equal distal links (distal = distal_right)")
        p = tuple(c[i] + distal * _direction(theta3)[i] for i in range(2))
        return {"A": a, "C": c, "P": p, "D": c, "B": b}
    if coincide:
        raise MechanismError(f"{label}: at {inputs} the elbows C and D coincide and P is free on a circle: "
                             f"use assembly = 0 with {names['theta3']}")
    p = circle_intersection(c, distal, d, distal_right, assembly, where=f"{label}: {inputs}")
    return {"A": a, "C": c, "P": p, "D": d, "B": b}


def five_bar_inputs(x, y, *, working_mode="++", base=6.0, proximal=8.0, distal=5.0, proximal_right=0.0,
                    distal_right=0.0):
    """The inverse kinematics: inputs reaching P = (x, y) in a working mode of Chablat, Wenger & Angeles 1998 (Sec. 3.3).

    Parameters
    ----------
    x, y : float
        The position of P.
    working_mode : {"++", "+-", "-+", "--"}
        Signs of sin(θ3 − θ1) and sin(θ4 − θ2), the diagonal of B (Chablat, Wenger & Angeles 1998, eq. 3c).
    base, proximal, distal, proximal_right, distal_right : float
        As in :func:`five_bar_points`.

    Returns
    -------
    dict
        ``{"theta1": float, "theta2": float, "assembly": int}``: the parameters of
        :func:`five_bar` that build this posture (assembly 1 when P lies on C→D).

    Raises
    ------
    MechanismError
        When P is out of reach of a leg.
    """
    if working_mode not in WORKING_MODES:
        raise MechanismError(f"five-bar: working_mode must be one of {', '.join(WORKING_MODES)}, "
                             f"got {working_mode!r}")
    base, proximal, distal, proximal_right, distal_right = _lengths(base, proximal, distal, proximal_right,
                                                                     distal_right)
    p, b = (float(x), float(y)), (base, 0.0)
    # cross(C − A, P − C) = −side · height · ‖P − A‖ (see circle_intersection), hence side = −sign.
    left, right = (1 if sign == "+" else -1 for sign in working_mode)
    c = circle_intersection((0.0, 0.0), proximal, p, distal, -left, where=f"five-bar: P = ({x}, {y}), left leg")
    d = circle_intersection(b, proximal_right, p, distal_right, -right,
                            where=f"five-bar: P = ({x}, {y}), right leg")
    side = _cross((d[0] - c[0], d[1] - c[1]), (p[0] - c[0], p[1] - c[1]))
    return {"theta1": math.atan2(c[1], c[0]), "theta2": math.atan2(d[1], d[0] - base),
            "assembly": 1 if side >= 0 else -1}


def five_bar(*, base=6.0, proximal=8.0, distal=5.0, proximal_right=0.0, distal_right=0.0,
             theta1=1.8, theta2=1.3, assembly=1, theta3=0.0, actuated="A,B", end_effector="distal_left"):
    """Planar five-bar (5R) assembled at actuated angles θ1, θ2 on the chosen branch.

    Parameters
    ----------
    base, proximal, distal : float
        L0 = ‖AB‖, L1 = ‖AC‖, L2 = ‖CP‖ (Chablat, Wenger & Angeles 1998, Fig. 1; defaults: the example of Chablat, Wenger & Angeles 1998
        Sec. 3.4, L0 = 6, L1 = 8, L2 = 5). Park & Kim's design: 2, 1, 1.
    proximal_right, distal_right : float
        L3 = ‖BD‖, L4 = ‖DP‖; 0 (default) means L3 = L1, L4 = L2, the symmetric
        manipulator Chablat, Wenger & Angeles 1998 study.
    theta1, theta2 : float
        The actuated angles θ1 of C − A and θ2 of D − B (rad), from the direction AB.
    assembly : {1, -1, 0}
        The direct-kinematics branch (see :func:`five_bar_points`): P left (+1) or
        right (−1) of C→D; 0: coincident elbows C = D, P placed by `theta3`. The
        working mode of Chablat, Wenger & Angeles 1998 (the inverse-kinematics branch) follows from the
        posture; :func:`five_bar_inputs` gives the inputs of a posture in a mode.
    theta3 : float
        θ3, the angle of P − C; read only with ``assembly=0`` (the catalogue entry refuses it set otherwise).
    actuated : str
        Comma-separated names of the driven joints among A, C, P, D, B (default
        the base joints A, B as in both papers).
    end_effector : {"distal_left", "distal_right", "none"}
        The link carrying the end-effector point P (position output), or none.

    Returns
    -------
    Mechanism
        Joints ``A`` (ground-proximal_left), ``C`` (proximal_left-distal_left),
        ``P`` (distal_left-distal_right), ``D`` (distal_right-proximal_right),
        ``B`` (proximal_right-ground); Park & Kim's J1..J5.

    Notes
    -----
    With p − c = L2 (cos θ3, sin θ3) and p − d = L4 (cos θ4, sin θ4), Chablat, Wenger & Angeles 1998's
    A p˙ = B θ˙ has A = [(p − c)ᵀ; (p − d)ᵀ] and B = diag(L1 L2 sin(θ3 − θ1),
    L3 L4 sin(θ4 − θ2)) (eqs. 3b-c): A is singular iff θ3 − θ4 = kπ (the
    actuator singularities of Park & Kim), B iff θ3 − θ1 = kπ or θ4 − θ2 = kπ
    (end-effector singularities).

    References
    ----------
    Chablat, Wenger, Angeles, 1998, Fig. 1, eqs. (1)-(13);
    Park & Kim, 1999, eq. (8), Figs. 1, 6, 13.
    """
    names = [name.strip() for name in actuated.split(",") if name.strip()]
    unknown = sorted(set(names) - {name for name, _ in _LOOP})
    if unknown or len(set(names)) != len(names):
        raise MechanismError(f"five-bar: actuated must list distinct joints among A, C, P, D, B, got {actuated!r}")
    if end_effector not in ("distal_left", "distal_right", "none"):
        raise MechanismError(f"five-bar: end_effector must be 'distal_left', 'distal_right' or 'none', "
                             f"got {end_effector!r}")
    points = five_bar_points(base=base, proximal=proximal, distal=distal, proximal_right=proximal_right,
                             distal_right=distal_right, theta1=theta1, theta2=theta2, assembly=assembly,
                             theta3=theta3)
    joints = [Joint(name, "R", links, point=points[name], actuated=name in names) for name, links in _LOOP]
    tool = None if end_effector == "none" else EndEffector(end_effector, points["P"], "position")
    return Mechanism("five-bar", "planar", joints, end_effector=tool)


# ----------------------------------------------------------------------------- named configurations

_PARK_KIM = {"base": 2.0, "proximal": 1.0, "distal": 1.0}
#: Fig. 13 (Park & Kim): A = (0, 0), C = (0, 1), P = (0, 2), D = (0, 3), B = (2, 3), turned so that AB is
#: the x axis: ‖AB‖ = √13, the left leg stretched along a line through D.
_FIG13_TURN = math.atan2(3.0, 2.0)
_FIG13 = {"base": math.sqrt(13.0), "proximal": 1.0, "distal": 1.0, "proximal_right": 2.0, "distal_right": 1.0,
          "theta1": math.pi / 2 - _FIG13_TURN, "theta2": math.pi - _FIG13_TURN}


def _distal_aligned(theta1, side, base=6.0, proximal=8.0, distal=5.0):
    """Inputs with θ3 − θ4 = π (Chablat, Wenger & Angeles 1998, eq. 9): ‖CD‖ = 2 L2, D on the circle of radius L1 about B."""
    c = (proximal * math.cos(theta1), proximal * math.sin(theta1))
    d = circle_intersection(c, 2 * distal, (base, 0.0), proximal, side)
    return {"theta1": theta1, "theta2": math.atan2(d[1], d[0] - base)}


def _leg_singular(leg, stretched, angle, working_mode):
    """Inputs of Chablat, Wenger & Angeles 1998's design with one leg stretched (θ3 = θ1) or folded (θ3 = θ1 + π), eq. 3c.

    P is on the circle of radius L1 ± L2 about the leg's base joint, at `angle` from AB; the other
    leg's sign is that of `working_mode` (the stretched leg's sign is moot).
    """
    reach = 8.0 + 5.0 if stretched else 8.0 - 5.0
    centre = (0.0, 0.0) if leg == "left" else (6.0, 0.0)
    return five_bar_inputs(centre[0] + reach * math.cos(angle), centre[1] + reach * math.sin(angle),
                           working_mode=working_mode)


def _elbows_coincide():
    """Inputs of Chablat, Wenger & Angeles 1998's design with C = D: C on the circles of radius L1 = 8 about A and about B."""
    c = circle_intersection((0.0, 0.0), 8.0, (6.0, 0.0), 8.0, 1)
    return {"theta1": math.atan2(c[1], c[0]), "theta2": math.atan2(c[1], c[0] - 6.0), "assembly": 0}


#: A generic posture of Chablat, Wenger & Angeles 1998's design, P = (3, 7), in each of its four working modes (Fig. 2).
_WORKING_MODES = {f"fig2_working_mode_{mode.replace('+', 'p').replace('-', 'm')}":
                  five_bar_inputs(3.0, 7.0, working_mode=mode) for mode in WORKING_MODES}

ENTRIES = (
    Entry("five-bar", five_bar,
          "Chablat, Wenger & Angeles (1998) Fig. 1, eqs. (1)-(13), Figs. 2, 5; "
          "Park & Kim (1999) eq. (8), Figs. 1, 6, 13",
          {
              # Park & Kim Fig. 1: all five joints collinear (C-space singularities).
              "fig1a_collinear": {**_PARK_KIM, "theta1": 0.0, "theta2": 0.0},
              "fig1b_collinear": {**_PARK_KIM, "theta1": math.pi, "theta2": math.pi},
              "fig1c_collinear": {**_PARK_KIM, "theta1": 0.0, "theta2": math.pi, "assembly": 0,
                                  "theta3": math.pi},
              "fig1d_collinear": {**_PARK_KIM, "theta1": 0.0, "theta2": math.pi, "assembly": 0, "theta3": 0.0},
              # Park & Kim Fig. 6a: distal links aligned; Fig. 6b: the elbows coincide.
              "fig6a_distal_aligned": {**_PARK_KIM, "theta1": math.pi / 2, "theta2": math.pi / 2},
              "fig6b_elbows_coincide": {**_PARK_KIM, "theta1": 0.0, "theta2": math.pi, "assembly": 0,
                                        "theta3": math.pi / 2},
              # Park & Kim Fig. 13: left leg stretched and distal links aligned.
              "fig13_combined": _FIG13,
              # Chablat, Wenger & Angeles 1998, design L0 = 6, L1 = 8, L2 = 5 (Sec. 3.4).
              **_WORKING_MODES,
              "eq9_distal_aligned": _distal_aligned(1.2, 1),
              "sec34_elbows_coincide": {**_elbows_coincide(), "theta3": 2.8},
              "eq3c_left_leg_stretched": _leg_singular("left", True, 1.2, "++"),
              "eq3c_left_leg_folded": _leg_singular("left", False, 2.2, "++"),
              "eq3c_right_leg_stretched": _leg_singular("right", True, 1.9, "++"),
              "eq3c_right_leg_folded": _leg_singular("right", False, 1.9, "++"),
          },
          read_only={"theta3": read_only_with("assembly", 0)}),
)
