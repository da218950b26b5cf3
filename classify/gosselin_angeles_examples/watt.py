"""Gosselin–Angeles relation of Watt's six-bar linkage, Gosselin & Angeles 1990 eqs. 18–41.

Section IV of Gosselin & Angeles: the input is the crank angle θ, the output
the angle φ of the output link l₃; the ternary rocker (an equilateral triangle
of side 1 turning about joint 4 by ψ) couples the two four-bar loops. The
velocity relation ``A φ̇ + B θ̇ = 0`` (eq. 31) has ``A = D₁ D₂`` and
``B = N₁ N₂`` (eq. 32) with::

    N₁ = (l₁ cos θ − √3 l₁ sin θ + l₁² + l₂²)(½ l₁ sin θ + √3/2 l₁ cos θ)
         + 2 sin(ψ − β)(l₁² + ½ l₁ cos θ − √3/2 l₁ sin θ) √(1 − √3 l₁ sin θ + l₁ cos θ + l₁²)   (eq. 33)
    N₂ = sin ψ (x₁'² + y₁² + l₄² − l₃²) + 2 l₃ sin(α − φ)(1 + cos ψ) √(x₁'² + y₁²)                  (eq. 34)
    D₁ = 2 sin(ψ − β)(1 − √3 l₁ sin θ + l₁ cos θ + l₁²)^{3/2}                                        (eq. 35)
    D₂ = 2 l₃ sin(α − φ)(x₁'² + y₁²)^{3/2}                                                           (eq. 36)

and x₁ = −cos(ψ + π/3), y₁ = √3/2 + sin(ψ + π/3) (eqs. 18–19),
α = tan⁻¹(y₁/x₁') (eq. 20), x₁' = x₁ − ½ (eq. 21),
β = tan⁻¹((l₁ sin θ − √3/2)/(l₁ cos θ + ½)) (eq. 22), both tan⁻¹ taken in the
quadrant of their numerator and denominator (atan2).

Corrections and readings (see :mod:`mechanisms.catalogue.watt` and
``tests/catalogue/test_catalogue_watt.py``):

* eq. 33 prints √2/2 in its second factor; the derivative of β (eq. 27, where
  the same factor appears over the same denominator) has √3/2, and only √3/2
  makes N₁/D₁ = dψ/dθ (checked in the tests against the mechanism's own
  velocities). Eq. 26 (C₁) is misprinted too — its numerator should be
  (l₁ cos θ − √3 l₁ sin θ + l₁² + l₂²)(½ l₁ sin θ + √3/2 l₁ cos θ), the first
  term of N₁; C₁ is not used here.
* The frames: eqs. 22 and 24 put the crank pivot (joint 1) at the origin and
  the rocker pivot (joint 4) at P = (−½, √3/2); eqs. 18–23 use the mirror
  image x ↦ −x − ½ of that frame (output pivot, joint 7, at (½, 0)). The
  catalogue mechanism is built in the first frame with joint 7 at (−1, 0),
  so its output angle φ_c (of joint 6 − joint 7) is the mirror of the paper's:
  **the relation's output is the paper's φ = π − φ_c**, and its θ and ψ are
  the catalogue's (ψ is unchanged by the mirror: x₁, y₁ are joint 5 mirrored).

With these, eqs. 25–30 give ψ̇ = (N₁/D₁) θ̇ and φ̇ = −(N₂/D₂) ψ̇, i.e. exactly
``D₁D₂ φ̇ + N₁N₂ θ̇ = 0`` (eq. 31) — the relation's sign is the paper's.

Why a callable relation (:func:`classify.gosselin_angeles.relation_from_callables`)
rather than SymPy: A and B depend on the rocker angle ψ, which is not a
closed-form function of (θ, φ) — it is the common root of the two loop
closures (eq. 24 from θ, eq. 23 from φ), each with two roots
(:func:`watt_rocker_angle`). The factors themselves are written as printed
(:func:`watt_factors`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechanisms import link_pose

from ..gosselin_angeles import relation_from_callables
from ._rotations import planar_angle

__all__ = ["WattGeometry", "watt_geometry", "watt_coordinates", "watt_rocker_angle", "watt_factors",
           "watt_relation"]

REFERENCE = "Gosselin & Angeles (1990) Section IV, eqs. 18-41 (eq. 33: sqrt(3)/2 for sqrt(2)/2)"

SQRT3 = math.sqrt(3.0)
#: ground pivots of G–A eqs. 22-24 (joint 1, joint 4) and joint 7 in the same frame
_CRANK_PIVOT = np.array([0.0, 0.0])
_ROCKER_PIVOT = np.array([-0.5, SQRT3 / 2])
_OUTPUT_PIVOT = np.array([-1.0, 0.0])
#: relative tolerance on the layout the paper's equations assume (unit sides, equilateral rocker)
_LAYOUT_TOLERANCE = 1e-9
#: a circle–circle distance below this (relative) leaves ψ undetermined by that loop
_COINCIDENT = 1e-12


@dataclass(frozen=True)
class WattGeometry:
    """Link lengths and home angles of a Watt six-bar built like the catalogue's.

    Attributes
    ----------
    l1, l2, l3, l4 : float
        Crank (joints 1–2), coupler (2–3), output link (6–7), second coupler (5–6),
        read from the joints' home positions.
    theta_home : float
        θ at home: the angle of joint 2 − joint 1 (rad).
    output_home : float
        φ_c at home: the angle of joint 6 − joint 7 in the catalogue's frame (rad); the
        paper's φ is π − φ_c.
    """

    l1: float
    l2: float
    l3: float
    l4: float
    theta_home: float
    output_home: float


def _angle(vector):
    return math.atan2(float(vector[1]), float(vector[0]))



def watt_geometry(mechanism):
    """The link lengths and home angles of a Watt six-bar (G–A Fig. 5).

    Parameters
    ----------
    mechanism : Mechanism
        Joints ``joint1`` … ``joint7`` and links ``crank``, ``output`` as in
        :func:`mechanisms.catalogue.watt.watt_six_bar`.

    Returns
    -------
    WattGeometry

    Raises
    ------
    ValueError
        If a joint is missing, or the ground pivots and the rocker are not the layout of
        eqs. 18–24 (joints 1, 4, 7 at (0, 0), (−½, √3/2), (−1, 0); joints 3 and 5 at unit
        distance from joint 4, joint 5 at +π/3 from joint 3).
    """
    try:
        joints = {index: np.asarray(mechanism.joint(f"joint{index}").point, dtype=float) for index in range(1, 8)}
    except (KeyError, TypeError) as error:
        raise ValueError(f"{mechanism.name}: not a Watt six-bar with joints joint1 ... joint7 ({error})") from None
    for index, expected in ((1, _CRANK_PIVOT), (4, _ROCKER_PIVOT), (7, _OUTPUT_PIVOT)):
        if np.linalg.norm(joints[index] - expected) > _LAYOUT_TOLERANCE:
            raise ValueError(f"{mechanism.name}: joint{index} at {joints[index].tolist()}, G-A eqs. 18-24 put it "
                             f"at {expected.tolist()}")
    rocker = joints[3] - joints[4]
    turned = np.array([[0.5, -SQRT3 / 2], [SQRT3 / 2, 0.5]]) @ rocker
    if abs(np.linalg.norm(rocker) - 1.0) > _LAYOUT_TOLERANCE or \
            np.linalg.norm(turned - (joints[5] - joints[4])) > _LAYOUT_TOLERANCE:
        raise ValueError(f"{mechanism.name}: the rocker is not the unit equilateral triangle of eqs. 18-19")
    return WattGeometry(
        l1=float(np.linalg.norm(joints[2] - joints[1])), l2=float(np.linalg.norm(joints[3] - joints[2])),
        l3=float(np.linalg.norm(joints[6] - joints[7])), l4=float(np.linalg.norm(joints[6] - joints[5])),
        theta_home=_angle(joints[2] - joints[1]), output_home=_angle(joints[6] - joints[7]))


def watt_coordinates(mechanism, geometry=None):
    """The map ``point -> (θ, φ)``: the crank angle and the paper's output angle.

    Parameters
    ----------
    mechanism : Mechanism
    geometry : WattGeometry, optional
        Default :func:`watt_geometry` of `mechanism`.

    Returns
    -------
    callable
        ``coordinates(point) -> (theta, phi)``, each an ndarray of shape [1]:
        θ = θ_home + the crank link's rotation from home, φ = π − (φ_c,home + the output
        link's rotation from home) (the mirror of the catalogue's frame, module doc).
    """
    geometry = watt_geometry(mechanism) if geometry is None else geometry

    def coordinates(point):
        theta = geometry.theta_home + planar_angle(link_pose(mechanism, "crank", point))
        output = geometry.output_home + planar_angle(link_pose(mechanism, "output", point))
        return np.array([theta]), np.array([math.pi - output])
    return coordinates


def _wrapped(angle):
    return math.remainder(angle, 2 * math.pi)


def _loop_candidates(centre_angle, distance, far_length):
    """Angles at joint 4 of the unit rocker arm closing a loop (law of cosines, eqs. 23-24).

    The arm (unit length, from joint 4) and a link of length `far_length` meet a point at
    `distance` from joint 4 in direction `centre_angle`; returns the two candidate arm
    angles and |cos| of the angle between arm and that direction (1 at a fold), or
    (None, None) where the point is on joint 4 (the loop leaves the arm free).
    """
    if distance < _COINCIDENT:
        return None, None
    cosine = (1.0 + distance ** 2 - far_length ** 2) / (2.0 * distance)
    turn = math.acos(max(-1.0, min(1.0, cosine)))
    return (centre_angle + turn, centre_angle - turn), abs(cosine)


def watt_rocker_angle(theta, phi, geometry):
    """The rocker angle ψ at input θ and (paper's) output φ: the common root of both loops.

    Eq. 24 gives ψ = β ± arccos((1 + d² − l₂²)/(2d)), d = ‖joint 2 − joint 4‖, from θ; eq. 23,
    read from the other end, gives ψ + π/3 = δ ± arccos((1 + q² − l₄²)/(2q)) with δ, q the
    angle and length of joint 6 − joint 4, from φ. Generically exactly one root is shared;
    the pair closest on the circle is taken, and of that pair the root of the
    better-conditioned loop (its arccos argument farther from ±1: the other loop may be at
    a fold, D₁ = 0 or N₂ = 0, where its root is known only to √ε).

    Where one loop leaves ψ free (joint 2 on joint 4, l₁ = l₂ = 1, or joint 6 on joint 4,
    l₃ = l₄ = 1: the kind-III designs of eq. 41), the other loop's first root is taken; the
    paper's factors do not depend on that choice there (D₁ and N₁ both vanish with d = 0;
    N₂ vanishes on the whole constant branch).

    Parameters
    ----------
    theta, phi : float
        θ and the paper's φ (rad).
    geometry : WattGeometry

    Returns
    -------
    float
        ψ (rad), in (−π, π].
    """
    crank_end = np.array([geometry.l1 * math.cos(theta), geometry.l1 * math.sin(theta)])
    to_crank = crank_end - _ROCKER_PIVOT
    from_input, input_cosine = _loop_candidates(_angle(to_crank), float(np.linalg.norm(to_crank)), geometry.l2)
    output = math.pi - phi
    output_end = _OUTPUT_PIVOT + geometry.l3 * np.array([math.cos(output), math.sin(output)])
    to_output = output_end - _ROCKER_PIVOT
    from_output, output_cosine = _loop_candidates(_angle(to_output), float(np.linalg.norm(to_output)), geometry.l4)
    if from_output is not None:
        from_output = tuple(value - math.pi / 3 for value in from_output)
    if from_input is None and from_output is None:
        raise ValueError(f"watt: θ = {theta}, φ = {phi}: both loops leave the rocker free")
    if from_input is None:
        return _wrapped(from_output[0])
    if from_output is None:
        return _wrapped(from_input[0])
    _, first, second = min((abs(_wrapped(a - b)), a, b) for a in from_input for b in from_output)
    return _wrapped(first if input_cosine <= output_cosine else second)


def watt_factors(theta, phi, psi, geometry):
    """N₁, N₂, D₁, D₂ of G–A eqs. 33–36 as printed (eq. 33 with √3/2 for √2/2).

    Parameters
    ----------
    theta, phi, psi : float
        θ, the paper's φ and ψ (rad).
    geometry : WattGeometry

    Returns
    -------
    dict of str to float
        ``N1``, ``N2``, ``D1``, ``D2``; also ``alpha``, ``beta`` (eqs. 20, 22), ``x1p``, ``y1``
        (eqs. 19, 21).
    """
    l1, l2, l3, l4 = geometry.l1, geometry.l2, geometry.l3, geometry.l4
    sine, cosine = math.sin(theta), math.cos(theta)
    x1 = -math.cos(psi + math.pi / 3)  # eq. 18
    y1 = SQRT3 / 2 + math.sin(psi + math.pi / 3)  # eq. 19
    x1p = x1 - 0.5  # eq. 21
    alpha = math.atan2(y1, x1p)  # eq. 20
    beta = math.atan2(l1 * sine - SQRT3 / 2, l1 * cosine + 0.5)  # eq. 22
    crank_square = 1 - SQRT3 * l1 * sine + l1 * cosine + l1 ** 2  # ‖joint 2 − joint 4‖², eqs. 24, 33, 35
    rocker_square = x1p ** 2 + y1 ** 2  # ‖joint 5 − joint 7‖², eqs. 23, 34, 36
    with np.errstate(invalid="ignore"):
        crank_length = float(np.sqrt(crank_square))
    rocker_length = math.sqrt(rocker_square)
    n1 = ((l1 * cosine - SQRT3 * l1 * sine + l1 ** 2 + l2 ** 2) * (0.5 * l1 * sine + SQRT3 / 2 * l1 * cosine)
          + 2 * math.sin(psi - beta) * (l1 ** 2 + 0.5 * l1 * cosine - SQRT3 / 2 * l1 * sine) * crank_length)
    n2 = (math.sin(psi) * (rocker_square + l4 ** 2 - l3 ** 2)
          + 2 * l3 * math.sin(alpha - phi) * (1 + math.cos(psi)) * rocker_length)
    d1 = 2 * math.sin(psi - beta) * crank_length ** 3
    d2 = 2 * l3 * math.sin(alpha - phi) * rocker_length ** 3
    return {"N1": n1, "N2": n2, "D1": d1, "D2": d2, "alpha": alpha, "beta": beta, "x1p": x1p, "y1": y1}


def watt_relation(mechanism):
    """The paper's velocity relation ``A φ̇ + B θ̇ = 0``, A = D₁D₂, B = N₁N₂ (G–A eqs. 31–36).

    Kinds: I where N₁ = 0 (l₁, l₂ aligned) or N₂ = 0 (l₄ aligned with joints 4–5) (eq. 37);
    II where D₁ = 0 (l₂ aligned with joints 3–4, Fig. 6) or D₂ = 0 (l₃, l₄ aligned)
    (eqs. 38–40); III for the designs l₁ = l₂ = 1 or l₃ = l₄ = 1 (eq. 41).

    Parameters
    ----------
    mechanism : Mechanism
        A Watt six-bar as in :func:`watt_geometry`.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``("theta",)``, outputs ``("phi",)`` (the paper's φ, module doc); callables
        of (θ, φ) through ψ = :func:`watt_rocker_angle`; no residual (the paper prints the
        velocity relation).
    coordinates : callable
        :func:`watt_coordinates`.
    """
    geometry = watt_geometry(mechanism)

    def factors(theta, phi):
        theta, phi = float(np.ravel(theta)[0]), float(np.ravel(phi)[0])
        return watt_factors(theta, phi, watt_rocker_angle(theta, phi, geometry), geometry)

    def input_jacobian(theta, phi):
        values = factors(theta, phi)
        return np.array([[values["N1"] * values["N2"]]])

    def output_jacobian(theta, phi):
        values = factors(theta, phi)
        return np.array([[values["D1"] * values["D2"]]])

    relation = relation_from_callables(("theta",), ("phi",), input_jacobian, output_jacobian,
                                       name="eq32", reference=REFERENCE, units=("angle", "angle"))
    return relation, watt_coordinates(mechanism, geometry)
