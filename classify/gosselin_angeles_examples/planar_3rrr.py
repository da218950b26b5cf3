"""Gosselin–Angeles relation of the planar 3-RRR manipulator, Gosselin & Angeles 1990 eqs. 42–65.

Section V of Gosselin & Angeles: three legs with equal proximal links l₁ and
distal links l₂ (eq. 42), fixed motors at (x_oi, y_oi) driving θ = (θ₁, θ₂, θ₃),
and a gripper, an equilateral triangle with circumradius l₃ and centroid
(x, y), turned by φ. The velocity relation ``A ṡ + B θ̇ = 0`` (eq. 43),
ṡ = (ẋ, ẏ, φ̇), has B = diag(dᵢ) (eq. 44) and A with rows (aᵢ, bᵢ, cᵢ):

    aᵢ = 2 l₁ y₂ᵢ ρᵢ sin ψᵢ + γᵢ Eᵢ x₂ᵢ                                           (eq. 45)
    bᵢ = −2 l₁ x₂ᵢ ρᵢ sin ψᵢ + γᵢ Eᵢ y₂ᵢ                                          (eq. 46)
    cᵢ = 2 l₁ l₃ ρᵢ sin ψᵢ (x₂ᵢ cos φᵢ + y₂ᵢ sin φᵢ) + γᵢ Eᵢ l₃ (x₂ᵢ sin φᵢ − y₂ᵢ cos φᵢ)  (eq. 47)
    dᵢ = 2 l₁ ρᵢ³ sin ψᵢ                                                         (eq. 48)

with ρᵢ = √(x₂ᵢ² + y₂ᵢ²), Eᵢ = l₂² − l₁² + ρᵢ² (eq. 49), φ₁ = φ + π/6,
φ₂ = φ + 5π/6, φ₃ = φ − π/2 (eqs. 50–52), ψᵢ = cos⁻¹((l₁² − l₂² + ρᵢ²)/(2 l₁ ρᵢ))
(eq. 53), x₂ᵢ = x − l₃ cos φᵢ − x_oi, y₂ᵢ = y − l₃ sin φᵢ − y_oi (eqs. 54–55)
— the vector from motor i to gripper vertex i — and γᵢ = ±1 the branch of
leg i's inverse kinematics (eq. 56).

Conventions (checked against the mechanism's velocities in the tests):

* The inverse kinematics these formulas differentiate is
  θᵢ = atan2(y₂ᵢ, x₂ᵢ) + γᵢ ψᵢ with ψᵢ ∈ [0, π]; with it, eqs. 45–48 satisfy
  ``A ṡ + B θ̇ = 0`` exactly, with the paper's signs. So γᵢ = +1 puts the
  elbow on the left of the line motor → vertex (the catalogue's ``mode``).
* **γᵢ is read from the configuration**: γᵢ = sign sin(θᵢ − atan2(y₂ᵢ, x₂ᵢ))
  (+1 where that sine is 0, at a stretched or folded leg, where both signs
  describe the leg), so the relation holds in every working mode and along
  paths that change mode through a kind-I singularity; a fixed γ can be
  given instead (``modes``). The inputs θ enter A and B only through γᵢ.
* ψᵢ enters only through sin ψᵢ = sin cos⁻¹(cᵢ) = √(1 − cᵢ²) with cᵢ the
  argument of eq. 53 (ψᵢ ∈ [0, π]); it is written √|1 − cᵢ²|, equal where
  ‖cᵢ‖ ≤ 1, so that at a stretched or folded leg (eq. 59), where rounding can
  put ‖cᵢ‖ a few ulps above 1, sin ψᵢ comes out √ε-small instead of nan (the
  catalogue's folds fix ψᵢ only to √ε anyway).
* The motor centres (x_oi, y_oi), l₁, l₂, l₃ are read from the mechanism's
  joints, so the relation holds for the eq. 64 and 65 designs as well as
  for the catalogue default; the unit base of the paper is not assumed.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
import sympy

from mechanisms import link_pose

from ..gosselin_angeles import relation_from_sympy
from ._rotations import planar_angle

__all__ = ["Planar3RRRGeometry", "planar_3rrr_geometry", "planar_3rrr_coordinates", "planar_3rrr_matrices",
           "planar_3rrr_relation"]

REFERENCE = "Gosselin & Angeles (1990) Section V, eqs. 42-65"

#: φᵢ − φ of eqs. 50-52
VERTEX_OFFSETS = (math.pi / 6, 5 * math.pi / 6, -math.pi / 2)
#: relative tolerance on the symmetric layout the paper assumes (eq. 42, eqs. 50-55)
_LAYOUT_TOLERANCE = 1e-9

THETAS = sympy.symbols("theta1:4", real=True)
POSE = sympy.symbols("x y phi", real=True)
PROXIMAL, DISTAL, GRIPPER = sympy.symbols("l1 l2 l3", positive=True)
MOTOR_X = sympy.symbols("x_o1:4", real=True)
MOTOR_Y = sympy.symbols("y_o1:4", real=True)
MODES = sympy.symbols("gamma1:4", real=True)


@dataclass(frozen=True)
class Planar3RRRGeometry:
    """Dimensions and home values of a planar 3-RRR built like the catalogue's.

    Attributes
    ----------
    l1, l2, l3 : float
        Proximal and distal link lengths (equal in every leg, eq. 42), gripper circumradius.
    motors : ndarray, shape=[3, 2]
        Motor centres (x_oi, y_oi).
    centroid : ndarray, shape=[2]
        The gripper's centroid at home (mean of the three gripper joints).
    theta_home : ndarray, shape=[3]
        θᵢ at home: the angles of elbow i − motor i (rad).
    phi_home : float
        φ at home: the angle of centroid − vertex 1, minus π/6 (eqs. 50, 54–55).
    """

    l1: float
    l2: float
    l3: float
    motors: np.ndarray
    centroid: np.ndarray
    theta_home: np.ndarray
    phi_home: float

    @property
    def parameters(self):
        """SymPy parameters of the relation: l₁, l₂, l₃, x_oi, y_oi."""
        values = {PROXIMAL: self.l1, DISTAL: self.l2, GRIPPER: self.l3}
        for leg in range(3):
            values[MOTOR_X[leg]] = float(self.motors[leg, 0])
            values[MOTOR_Y[leg]] = float(self.motors[leg, 1])
        return values


def _angle(vector):
    return math.atan2(float(vector[1]), float(vector[0]))



def planar_3rrr_geometry(mechanism):
    """The dimensions and home values of a planar 3-RRR (G–A Fig. 7).

    Parameters
    ----------
    mechanism : Mechanism
        Joints ``motor{i}``, ``elbow{i}``, ``wrist{i}`` and links ``proximal{i}``,
        ``gripper`` (i = 1, 2, 3) as in :func:`mechanisms.catalogue.planar_3rrr.planar_3rrr`.

    Returns
    -------
    Planar3RRRGeometry

    Raises
    ------
    ValueError
        If a joint is missing, the legs are not equal (eq. 42), or the gripper joints are not
        the vertices (x, y) − l₃ (cos φᵢ, sin φᵢ) of eqs. 50–55.
    """
    try:
        motors, elbows, wrists = (np.array([mechanism.joint(f"{kind}{leg}").point for leg in (1, 2, 3)], dtype=float)
                                  for kind in ("motor", "elbow", "wrist"))
    except (KeyError, TypeError) as error:
        raise ValueError(f"{mechanism.name}: not a planar 3-RRR with joints motor1-3, elbow1-3, wrist1-3 "
                         f"({error})") from None
    proximal = np.linalg.norm(elbows - motors, axis=1)
    distal = np.linalg.norm(wrists - elbows, axis=1)
    centroid = wrists.mean(axis=0)
    radius = np.linalg.norm(wrists - centroid, axis=1)
    scale = float(max(proximal.max(), distal.max(), radius.max()))
    for label, values in (("proximal links l1", proximal), ("distal links l2", distal)):
        if np.ptp(values) > _LAYOUT_TOLERANCE * scale:
            raise ValueError(f"{mechanism.name}: the {label} differ ({values.tolist()}); G-A eq. 42 takes them equal")
    l3 = float(radius.mean())
    phi_home = _angle(centroid - wrists[0]) - VERTEX_OFFSETS[0]
    vertices = centroid - l3 * np.array([[math.cos(phi_home + offset), math.sin(phi_home + offset)]
                                         for offset in VERTEX_OFFSETS])
    if np.max(np.linalg.norm(vertices - wrists, axis=1)) > _LAYOUT_TOLERANCE * scale:
        raise ValueError(f"{mechanism.name}: the gripper joints are not the vertices of eqs. 50-55")
    theta_home = np.array([_angle(elbow - motor) for elbow, motor in zip(elbows, motors)])
    return Planar3RRRGeometry(float(proximal.mean()), float(distal.mean()), l3, motors, centroid, theta_home,
                              phi_home)


def planar_3rrr_coordinates(mechanism, geometry=None):
    """The map ``point -> (θ, s)``, θ = (θ₁, θ₂, θ₃), s = (x, y, φ), from the link poses.

    Parameters
    ----------
    mechanism : Mechanism
    geometry : Planar3RRRGeometry, optional
        Default :func:`planar_3rrr_geometry` of `mechanism`.

    Returns
    -------
    callable
        ``coordinates(point) -> (theta, pose)``, ndarrays of shape [3]: θᵢ = θᵢ,home + the
        rotation of link ``proximal{i}`` from home; (x, y) the home centroid carried by the
        gripper's pose; φ = φ_home + the gripper's rotation from home.
    """
    geometry = planar_3rrr_geometry(mechanism) if geometry is None else geometry
    centroid_home = np.append(geometry.centroid, 1.0)

    def coordinates(point):
        theta = geometry.theta_home + np.array([planar_angle(link_pose(mechanism, f"proximal{leg}", point))
                                                for leg in (1, 2, 3)])
        gripper = link_pose(mechanism, "gripper", point)
        centre = (gripper @ centroid_home)[:2]
        return theta, np.array([centre[0], centre[1], geometry.phi_home + planar_angle(gripper)])
    return coordinates


def planar_3rrr_matrices(modes=None):
    """The paper's B = diag(dᵢ) and A = [aᵢ bᵢ cᵢ] (eqs. 44–56) as SymPy 3×3 matrices.

    Parameters
    ----------
    modes : sequence of three int in {1, −1}, optional
        Fixed γᵢ (eq. 56). Default: γᵢ = sign sin(θᵢ − atan2(y₂ᵢ, x₂ᵢ)), +1 at 0 (module doc).

    Returns
    -------
    input_jacobian, output_jacobian : sympy.Matrix, shape=[3, 3]
        B and A; free symbols θᵢ (``theta1``–``theta3``, only through γᵢ), x, y, φ (``phi``),
        l₁, l₂, l₃, x_oi, y_oi.
    """
    if modes is not None:
        modes = tuple(modes)
        for leg, mode in enumerate(modes):
            if mode not in (1, -1):
                raise ValueError(f"modes: gamma{leg + 1} must be +1 or -1 (eq. 56), got {mode!r}")
    input_jacobian, output_jacobian = _matrices(modes)
    return input_jacobian.copy(), output_jacobian.copy()


@functools.lru_cache(maxsize=None)
def _matrices(modes):
    """:func:`planar_3rrr_matrices` for a tuple of modes or None (built once)."""
    x, y, phi = POSE
    diagonal, rows = [], []
    for leg in range(3):
        angle = phi + VERTEX_OFFSETS[leg]  # eqs. 50-52
        x2 = x - GRIPPER * sympy.cos(angle) - MOTOR_X[leg]  # eq. 54
        y2 = y - GRIPPER * sympy.sin(angle) - MOTOR_Y[leg]  # eq. 55
        reach = sympy.sqrt(x2 ** 2 + y2 ** 2)
        energy = DISTAL ** 2 - PROXIMAL ** 2 + reach ** 2  # eq. 49
        cosine = (PROXIMAL ** 2 - DISTAL ** 2 + reach ** 2) / (2 * PROXIMAL * reach)
        sine = sympy.sqrt(sympy.Abs(1 - cosine ** 2))  # sin ψᵢ = sin cos⁻¹(cosine), eq. 53 (module doc)
        if modes is None:
            gamma = 2 * sympy.Heaviside(sympy.sin(THETAS[leg] - sympy.atan2(y2, x2)), 1) - 1
        else:
            gamma = modes[leg]
        rows.append([
            2 * PROXIMAL * y2 * reach * sine + gamma * energy * x2,  # eq. 45
            -2 * PROXIMAL * x2 * reach * sine + gamma * energy * y2,  # eq. 46
            2 * PROXIMAL * GRIPPER * reach * sine * (x2 * sympy.cos(angle) + y2 * sympy.sin(angle))
            + gamma * energy * GRIPPER * (x2 * sympy.sin(angle) - y2 * sympy.cos(angle)),  # eq. 47
        ])
        diagonal.append(2 * PROXIMAL * reach ** 3 * sine)  # eq. 48
    return sympy.diag(*diagonal), sympy.Matrix(rows)


def planar_3rrr_relation(mechanism, modes=None):
    """The paper's velocity relation ``A ṡ + B θ̇ = 0`` (G–A eqs. 43–56) for a catalogue 3-RRR.

    Kinds: I where a leg is stretched or folded, sin ψᵢ = 0 (eqs. 57–59); II where the
    lines of the distal links meet, c₁ = c₂ = c₃ = 0 (eq. 61, Fig. 8), or they are
    parallel (eq. 63); III for the designs l₁ = √3/3, l₂ = l₃ (eq. 64) and l₁ = l₂,
    l₃ = √3/3 (eq. 65).

    Parameters
    ----------
    mechanism : Mechanism
        A planar 3-RRR as in :func:`planar_3rrr_geometry`.
    modes : sequence of three int in {1, −1}, optional
        Fixed working modes γᵢ; default read from the configuration (module doc).

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``("theta1", "theta2", "theta3")``, outputs ``("x", "y", "phi")``; no residual.
    coordinates : callable
        :func:`planar_3rrr_coordinates`.
    """
    geometry = planar_3rrr_geometry(mechanism)
    # The dimensions are put in with xreplace rather than relation_from_sympy's `parameters`
    # (Matrix.subs, several times slower on these expressions); the result is the same.
    values = {symbol: sympy.Float(value) for symbol, value in geometry.parameters.items()}
    input_jacobian, output_jacobian = (matrix.xreplace(values) for matrix in planar_3rrr_matrices(modes))
    relation = relation_from_sympy(THETAS, POSE, input_jacobian=input_jacobian, output_jacobian=output_jacobian,
                                   name="eq44", reference=REFERENCE,
                                   units=("angle",) * 3 + ("length", "length", "angle"))
    return relation, planar_3rrr_coordinates(mechanism, geometry)
