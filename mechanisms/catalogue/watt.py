"""Watt's six-bar linkage: Gosselin & Angeles (1990) Fig. 5, eqs. (18)-(41).

Two four-bar loops share a ternary rocker. The ground is the equilateral
triangle of side 1 with the crank pivot (joint 1) at the origin, the rocker
pivot (joint 4) at P = (−1/2, √3/2) and the output pivot (joint 7) at
O = (−1, 0). The input crank l₁ (angle θ, joint 1) drives the coupler l₂
(joints 2-3) which drives the ternary rocker, an equilateral triangle of
side 1 turning about joint 4 with vertices J₃ = P + (cos ψ, sin ψ) and
V = P + (cos(ψ + π/3), sin(ψ + π/3)) (joint 5); V drives the coupler l₄
(joints 5-6) and the output link l₃ (joints 6-7, angle φ).

Our reading (the figure is not in the text): eqs. (22) and (24) are written
with the crank pivot at the origin and joint 4 at (−1/2, √3/2); eqs. (18)-(23)
put the rocker vertex at x₁ = −cos(ψ + π/3), y₁ = √3/2 + sin(ψ + π/3) and the
output pivot at (1/2, 0), a frame mirrored with respect to the first
(x ↦ −x − 1/2). Read in one frame, that is the layout above, and it is the
only one that makes the rocker rigid and matches the statements after
eq. (41): joints 2 and 4 can coincide when l₁ = l₂ = 1 (‖J₁P‖ = 1) and joints
4 and 6 when l₃ = l₄ = 1 (‖OP‖ = 1). The output angle φ here is measured in
the first frame: the paper's φ is π − φ. Singular configurations do not
depend on the frame.
"""

from __future__ import annotations

import inspect
import math

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry, read_only_with

__all__ = ["watt_six_bar", "watt_positions", "watt_singular_configuration", "watt_input_for_rocker", "ENTRIES"]

#: Ground pivots: crank (joint 1), ternary rocker (joint 4), output (joint 7); unit sides.
CRANK_PIVOT = (0.0, 0.0)
ROCKER_PIVOT = (-0.5, math.sqrt(3.0) / 2)
OUTPUT_PIVOT = (-1.0, 0.0)
#: Tolerance (relative to the lengths) on a circle intersection that just fails to meet.
_REACH_TOLERANCE = 1e-9
_EPSILON = 2.0 ** -52
#: A triangle's cosine this close to ±1 (in units of the rounding unit) is that of a flat triangle: the law of
#: cosines computes it from rounded sides to a few units, and through the double root of the arccosine those
#: units would become an angle of about √ε ≈ 1e-8 (a D₁ or D₂ configuration singular only to 1e-8).
_FLAT_TRIANGLE = 16


def _point(origin, length, angle):
    return (origin[0] + length * math.cos(angle), origin[1] + length * math.sin(angle))


def _difference(first, second):
    return (first[0] - second[0], first[1] - second[1])


def _angle(vector):
    return math.atan2(vector[1], vector[0])


def _triangle_angle(adjacent, other, opposite, what):
    """The angle between sides `adjacent` and `other` of a triangle with third side `opposite`.

    Law of cosines, as in G-A eqs. (23)-(24); MechanismError naming `what` when the triangle
    does not exist (beyond a rounding tolerance, clipped); flat (angle 0 or π) when the cosine
    is ±1 to :data:`_FLAT_TRIANGLE` rounding units.
    """
    cosine = (adjacent ** 2 + other ** 2 - opposite ** 2) / (2 * adjacent * other)
    if abs(cosine) > 1 + _REACH_TOLERANCE:
        raise MechanismError(f"watt-six-bar: {what} (cos = {cosine:.6g})")
    if abs(abs(cosine) - 1.0) <= _FLAT_TRIANGLE * _EPSILON:  # flat to rounding: the angle is 0 or π exactly
        cosine = math.copysign(1.0, cosine)
    return math.acos(max(-1.0, min(1.0, cosine)))


def _circle_intersection(first_centre, first_radius, second_centre, second_radius, side, what):
    """The intersection of two circles on the left (side = +1) or right (−1) of centre 1 → centre 2."""
    chord = _difference(second_centre, first_centre)
    distance = math.hypot(*chord)
    turn = _triangle_angle(first_radius, distance, second_radius, what)
    return _point(first_centre, first_radius, _angle(chord) + side * turn)


def watt_positions(*, l1, l2, l3, l4, theta, branch_rocker=1, branch_output=1, psi=0.0):
    """The joint centres of the Watt six-bar at input θ (closed-form, G-A eqs. 18-24).

    Parameters
    ----------
    l1, l2, l3, l4 : float
        Crank, first coupler, output link, second coupler (G-A Fig. 5).
    theta : float
        Input angle θ of the crank (rad).
    branch_rocker : {1, -1, 0}
        ψ = β + branch · arccos((1 + d² − l₂²) / (2d)) (eq. 24), d = ‖J₂ − P‖; 0: ψ is given by
        `psi` instead (needed where J₂ = P, eq. 41 with l₁ = l₂ = 1).
    branch_output : {1, -1}
        φ = α + branch · arccos((l₃² + r² − l₄²) / (2 l₃ r)) (eq. 23), r = ‖V − O‖.
    psi : float
        ψ when ``branch_rocker == 0``.

    Returns
    -------
    dict of str to tuple of float
        ``joint1`` … ``joint7``, ``psi`` and ``phi`` (floats).

    Raises
    ------
    MechanismError
        If a loop cannot close at θ, naming the parameter.
    """
    joint1, joint4, joint7 = CRANK_PIVOT, ROCKER_PIVOT, OUTPUT_PIVOT
    joint2 = _point(joint1, l1, theta)
    to_crank = _difference(joint2, joint4)
    d = math.hypot(*to_crank)
    if branch_rocker == 0:
        joint3 = _point(joint4, 1.0, psi)
        gap = math.hypot(*_difference(joint3, joint2)) - l2
        if abs(gap) > _REACH_TOLERANCE * max(1.0, l2):
            raise MechanismError(f"watt-six-bar: psi = {psi} with branch_rocker = 0: the coupler l2 "
                                 f"does not close (‖J2 J3‖ − l2 = {gap:.3g})")
    else:
        if d < _REACH_TOLERANCE:
            raise MechanismError(f"watt-six-bar: theta = {theta}: joints 2 and 4 coincide, ψ is free; "
                                 "give it with branch_rocker = 0 and psi")
        psi = _angle(to_crank) + branch_rocker * _triangle_angle(
            1.0, d, l2, f"theta = {theta}: the coupler l2 cannot reach the rocker")
        joint3 = _point(joint4, 1.0, psi)
    joint5 = _point(joint4, 1.0, psi + math.pi / 3)
    to_rocker = _difference(joint5, joint7)
    r = math.hypot(*to_rocker)
    if r < _REACH_TOLERANCE:
        raise MechanismError(f"watt-six-bar: theta = {theta}: joints 5 and 7 coincide, φ is undetermined")
    phi = _angle(to_rocker) + branch_output * _triangle_angle(
        l3, r, l4, f"theta = {theta}: the coupler l4 cannot reach the output link")
    joint6 = _point(joint7, l3, phi)
    return {"joint1": joint1, "joint2": joint2, "joint3": joint3, "joint4": joint4,
            "joint5": joint5, "joint6": joint6, "joint7": joint7, "psi": psi, "phi": phi}


def watt_six_bar(*, l1=1.2, l2=1.6, l3=0.6, l4=1.5, theta=0.7, branch_rocker=1, branch_output=1, psi=0.0,
                 end_effector=True):
    """Watt six-bar (G-A Fig. 5) driven by the crank θ, output the angle φ of link l₃.

    Parameters
    ----------
    l1, l2, l3, l4 : float
        l₁ crank (joints 1-2), l₂ coupler (2-3), l₃ output link (6-7), l₄ coupler (5-6), in units
        of the ground and rocker sides (1, G-A eqs. 18-24). The paper gives no numbers; the
        defaults are a design on which all four conditions (37)-(40) occur.
    theta : float
        Input angle θ (rad), eq. (22).
    branch_rocker : {1, -1, 0}
        Branch of ψ (eq. 24): ±1 the sign of sin(ψ − β); 0: ψ given by `psi` (where joints 2 and
        4 coincide, eq. 41 with l₁ = l₂ = 1).
    branch_output : {1, -1}
        Branch of φ (eq. 23): the sign of sin(φ − α) in our frame.
    psi : float
        ψ (rad) when ``branch_rocker == 0``; ignored otherwise (the catalogue entry refuses it set there).
    end_effector : bool
        Whether the orientation of the output link l₃ (the angle φ) is the end-effector.

    Returns
    -------
    Mechanism
        Joints ``joint1`` … ``joint7`` numbered as in the paper: 1 ground-crank (actuated),
        2 crank-coupler, 3 coupler-rocker, 4 ground-rocker, 5 rocker-coupler2, 6 coupler2-output,
        7 ground-output.

    Notes
    -----
    G-A eq. (32): A φ̇ + B θ̇ = 0 with A = D₁D₂, B = N₁N₂. Kind I (B = 0, eq. 37): N₁ = 0, l₁ and
    l₂ aligned; N₂ = 0, l₄ aligned with joints 4-5. Kind II (A = 0, eqs. 38-40): D₁ = 0, l₂
    aligned with joints 3-4; D₂ = 0, l₃ and l₄ aligned. Kind III designs: eq. (41).
    """
    lengths = {"l1": l1, "l2": l2, "l3": l3, "l4": l4}
    for name, value in lengths.items():
        if not value > 0:
            raise MechanismError(f"watt-six-bar: {name} must be positive, got {value}")
    if branch_rocker not in (-1, 0, 1):
        raise MechanismError(f"watt-six-bar: branch_rocker must be 1, -1 or 0, got {branch_rocker}")
    if branch_output not in (-1, 1):
        raise MechanismError(f"watt-six-bar: branch_output must be 1 or -1, got {branch_output}")
    points = watt_positions(**lengths, theta=theta, branch_rocker=branch_rocker,
                            branch_output=branch_output, psi=psi)
    return Mechanism("watt-six-bar", "planar", [
        Joint("joint1", "R", ("ground", "crank"), point=points["joint1"], actuated=True),
        Joint("joint2", "R", ("crank", "coupler"), point=points["joint2"]),
        Joint("joint3", "R", ("coupler", "rocker"), point=points["joint3"]),
        Joint("joint4", "R", ("ground", "rocker"), point=points["joint4"]),
        Joint("joint5", "R", ("rocker", "coupler2"), point=points["joint5"]),
        Joint("joint6", "R", ("coupler2", "output"), point=points["joint6"]),
        Joint("joint7", "R", ("ground", "output"), point=points["joint7"]),
    ], end_effector=EndEffector("output", None, "orientation") if end_effector else None)


def watt_singular_configuration(condition, *, l1, l2, l3, l4, stretched=True, side=1):
    """Input θ and branches at which one factor of G-A eq. (32) vanishes (closed form).

    Parameters
    ----------
    condition : {"N1", "N2", "D1", "D2"}
        N₁ = 0: l₁, l₂ aligned (eq. 37); N₂ = 0: l₄ aligned with joints 4-5 (eq. 37);
        D₁ = 0: l₂ aligned with joints 3-4 (eq. 39); D₂ = 0: l₃, l₄ aligned (eq. 40).
    l1, l2, l3, l4 : float
        The design (as in :func:`watt_six_bar`).
    stretched : bool
        The two aligned segments end to end (True) or folded over each other (False).
    side : {1, -1}
        Which of the two circle intersections locating the aligned joint.

    Returns
    -------
    dict
        ``theta``, ``branch_rocker``, ``branch_output`` for :func:`watt_six_bar`.

    Raises
    ------
    MechanismError
        If the design never reaches that condition.
    """
    pivot, rocker, output = CRANK_PIVOT, ROCKER_PIVOT, OUTPUT_PIVOT
    sign = 1 if stretched else -1

    if condition == "N1":
        joint3 = _circle_intersection(rocker, 1.0, pivot, abs(l1 + sign * l2), side,
                                      f"{condition}: joint 3 cannot be at ‖l1 ± l2‖ from joint 1")
        theta = _angle(joint3) if (stretched or l1 > l2) else _angle(joint3) + math.pi
        output_branch = 1
    elif condition == "D1":
        joint2 = _circle_intersection(pivot, l1, rocker, abs(1.0 + sign * l2), side,
                                      f"{condition}: joint 2 cannot be at ‖1 ± l2‖ from joint 4")
        theta, output_branch = _angle(joint2), 1
    elif condition in ("N2", "D2"):
        if condition == "N2":
            joint6 = _circle_intersection(output, l3, rocker, abs(1.0 + sign * l4), side,
                                          f"{condition}: joint 6 cannot be at ‖1 ± l4‖ from joint 4")
            toward = _angle(_difference(joint6, rocker)) + (0.0 if (stretched or l4 < 1) else math.pi)
            joint5 = _point(rocker, 1.0, toward)
        else:
            joint5 = _circle_intersection(rocker, 1.0, output, abs(l3 + sign * l4), side,
                                          f"{condition}: joint 5 cannot be at ‖l3 ± l4‖ from joint 7")
        psi = _angle(_difference(joint5, rocker)) - math.pi / 3
        theta = watt_input_for_rocker(psi, l1=l1, l2=l2)
        output_branch = None
    else:
        raise MechanismError(f"watt-six-bar: condition must be N1, N2, D1 or D2, got {condition!r}")
    # Assemble θ on each branch and keep the one that has the alignment found above.
    output_branches = (1, -1) if output_branch is None else (output_branch,)
    candidates = [{"theta": theta, "branch_rocker": branch_rocker, "branch_output": branch_output}
                  for branch_rocker in (1, -1) for branch_output in output_branches]
    return min(candidates, key=lambda values: _misalignment(
        condition, watt_positions(l1=l1, l2=l2, l3=l3, l4=l4, **values)))


def watt_input_for_rocker(psi, *, l1, l2, side=1):
    """The input θ that puts the ternary rocker at angle ψ (closed form).

    Parameters
    ----------
    psi : float
        Rocker angle ψ (rad): joint 3 at P + (cos ψ, sin ψ) (G-A eq. 24).
    l1, l2 : float
        Crank and coupler lengths.
    side : {1, -1}
        Joint 2 on the left (+1) or right (−1) of joint 1 → joint 3.

    Returns
    -------
    float
        θ with ‖J₂ − J₃‖ = l₂, J₂ = l₁ (cos θ, sin θ).

    Raises
    ------
    MechanismError
        If l₁ and l₂ cannot reach joint 3.
    """
    joint3 = _point(ROCKER_PIVOT, 1.0, psi)
    joint2 = _circle_intersection(CRANK_PIVOT, l1, joint3, l2, side,
                                  f"psi = {psi}: l1 and l2 cannot reach joint 3")
    return _angle(joint2)


def _cross(first, second):
    return first[0] * second[1] - first[1] * second[0]


def _misalignment(condition, points):
    """‖sin‖ of the angle between the two segments the condition aligns (0 when aligned)."""
    pairs = {"N1": (("joint1", "joint2"), ("joint2", "joint3")),
             "D1": (("joint4", "joint3"), ("joint3", "joint2")),
             "N2": (("joint4", "joint5"), ("joint5", "joint6")),
             "D2": (("joint7", "joint6"), ("joint6", "joint5"))}
    (a, b), (c, d) = pairs[condition]
    first, second = _difference(points[b], points[a]), _difference(points[d], points[c])
    return abs(_cross(first, second)) / (math.hypot(*first) * math.hypot(*second))


#: The default design of :func:`watt_six_bar` (the named configurations are computed for it).
DEFAULT_DESIGN = {name: inspect.signature(watt_six_bar).parameters[name].default
                  for name in ("l1", "l2", "l3", "l4")}
#: Kind-III designs of G-A eq. (41).
EQUAL_CRANK_AND_COUPLER = {"l1": 1.0, "l2": 1.0}
EQUAL_OUTPUT_AND_COUPLER = {"l3": 1.0, "l4": 1.0}


def _aligned(condition, side):
    """The default design's configuration with the given factor of eq. (32) zero (folded alignment)."""
    return watt_singular_configuration(condition, **DEFAULT_DESIGN, stretched=False, side=side)


ENTRIES = (
    Entry("watt-six-bar", watt_six_bar,
          "Gosselin & Angeles (1990) Fig. 5, eqs. (18)-(41)",
          {
              # Kind I, eq. (37): B = N1 N2 = 0 (the folded alignments: the default design cannot
              # stretch them).
              "eq37_n1_crank_and_coupler_aligned": _aligned("N1", -1),
              "eq37_n2_coupler_aligned_with_rocker": _aligned("N2", 1),
              # Kind II, eqs. (38)-(40): A = D1 D2 = 0 (Fig. 6 shows D1 = 0).
              "eq39_d1_coupler_aligned_with_rocker": _aligned("D1", 1),
              "eq40_d2_output_and_coupler_aligned": _aligned("D2", -1),
              # Kind III, eq. (41), l1 = l2 = 1: joints 2 and 4 coincide, ψ turns with θ locked ...
              "eq41_joints_2_4_superimposed": {**EQUAL_CRANK_AND_COUPLER, "theta": 2 * math.pi / 3,
                                               "branch_rocker": 0, "psi": 1.0},
              # ... and where that branch crosses the parallelogram branch ψ = θ (A = B = 0).
              "eq41_joints_2_4_branch_crossing": {**EQUAL_CRANK_AND_COUPLER, "theta": 2 * math.pi / 3,
                                                  "branch_rocker": 0, "psi": 2 * math.pi / 3},
              # Not stated in the paper: with l1 = l2 = 1 joints 1 and 3 can coincide too (ψ = −π/3),
              # a branch on which θ turns with the rocker, hence the output, at rest.
              "eq41_joints_1_3_superimposed": {**EQUAL_CRANK_AND_COUPLER, "theta": 2.5, "branch_rocker": 1},
              # l3 = l4 = 1: joints 4 and 6 coincide, the constant branch φ = π/3 ...
              "eq41_joints_4_6_constant_branch": {**EQUAL_OUTPUT_AND_COUPLER, "theta": 1.0,
                                                  "branch_rocker": 1, "branch_output": -1},
              # ... and where it crosses the parallelogram branch (ψ = 0: joints 7, 4, 5 aligned).
              "eq41_joints_4_6_branch_crossing": {
                  **EQUAL_OUTPUT_AND_COUPLER, "branch_rocker": 1, "branch_output": 1,
                  "theta": watt_input_for_rocker(0.0, l1=DEFAULT_DESIGN["l1"], l2=DEFAULT_DESIGN["l2"])},
          },
          read_only={"psi": read_only_with("branch_rocker", 0)}),
)
