"""Gosselin–Angeles relations of the Gough–Stewart platform (Gosselin & Angeles 1990, eqs. 71–87).

Section VII of Gosselin & Angeles: six legs of lengths cᵢ (the inputs) join
base points bᵢ = R_B (cos θᵢ, sin θᵢ, 0) (eqs. 71–72) to platform points
with coordinates p′ᵢ = R_P (cos ηᵢ, sin ηᵢ, 0) in the platform frame (eqs.
73–74); the platform pose is its centre x = (x, y, z) and orientation Q. The
inverse kinematics is cᵢ = √(Uᵢ² + Vᵢ² + Wᵢ²) (eq. 75) with
(Uᵢ, Vᵢ, Wᵢ) = wᵢ = x + Q p′ᵢ − bᵢ (eqs. 76–78, 80), and the velocity relation
``A ẏ + B ċ = 0`` (eq. 79), ẏ = (ẋ, ω), has rows aᵢ = [wᵢᵀ, ((Q p′ᵢ) × wᵢ)ᵀ]
(eqs. 81–82) and B = diag(cᵢ) (eq. 83).

Two relations of the catalogue platform (:mod:`mechanisms.catalogue.gough_stewart`)
in the same variables:

* :func:`eq75_relation`: ``Fᵢ = cᵢ − √(Uᵢ² + Vᵢ² + Wᵢ²)`` differentiated
  symbolically; not differentiable where a leg has zero length (eq. 84);
* :func:`eq81_relation`: the paper's A and B (eqs. 81–83).

Variables. The inputs are the leg lengths cᵢ: the catalogue's prismatic joint
``P{i}`` is displaced from its home, so cᵢ = ‖Pᵢ − bᵢ‖ at home plus the
displacement (positive along the leg, from the base to the platform). The
outputs are x and a rotation-vector chart r of the orientation,
``Q = expm([r]×) Q_reference`` with Q_reference = 1, so that r is the
catalogue's (rotation_x, rotation_y, rotation_z); the home Q is recovered from
the platform points and p′ᵢ (:func:`gough_stewart_geometry`). The paper's A
multiplies ω (eq. 79) and ω = J_left(r) ṙ, so the rotational columns of the
chart's A are those of eq. 82 times J_left(r).

Sign of eq. 81. From cᵢ² = wᵢ·wᵢ, cᵢ ċᵢ = wᵢ·ẋ + ((Q p′ᵢ) × wᵢ)·ω, i.e.
``−aᵢ·ẏ + cᵢ ċᵢ = 0``: with B = diag(cᵢ) as printed (eq. 83) the rows of A
that annihilate the platform's velocities are −aᵢ, not the printed aᵢ
(eq. 82) — the paper's pair satisfies ``A ẏ − B ċ = 0``. Ranks (and so the
kinds) do not depend on it; the consistency check of
:func:`classify.comparison.compare` does, so :func:`eq81_relation` uses −aᵢ.

A leg of zero length (eq. 84). Eq. 81 has the zero row [cᵢ, −aᵢ] = 0 there:
kinds I and II (and III). Eq. 75 is not differentiable there; its evaluated
derivative is not finite only where wᵢ vanishes exactly in floating point —
where wᵢ vanishes to rounding (the catalogue preset) −wᵢ/‖wᵢ‖ is a finite
direction of rounding noise, and compare reports ``inconsistent_relation``.

The relations depend on the design only (bᵢ, p′ᵢ) and are cached per design:
building one takes a few seconds.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import sympy

from manifold import rotation_log
from mechanisms import end_effector, to_displacements
from mechanisms.catalogue.gough_stewart import platform_points

from ..gosselin_angeles import relation_from_sympy
from ._rotations import orientation_from_vectors, rotated, row_times_left_jacobian

__all__ = ["GoughStewartGeometry", "gough_stewart_geometry", "eq75_relation", "eq81_relation"]

REFERENCE = "Gosselin & Angeles (1990) Section VII, eqs. 71-87"
#: the relations' variables, θ then x: the leg lengths c, the platform's position, the rotation vector r
#: (:attr:`classify.gosselin_angeles.InputOutputRelation.units`)
UNITS = ("length",) * 9 + ("angle",) * 3

#: largest relative residual of the platform points against eqs. 73-74 turned by Q
_LAYOUT_TOLERANCE = 1e-9

#: decimals of the design values (bᵢ, p′ᵢ): the platforms of one design share one relation
_KEY_DIGITS = 12

_LEGS = tuple(range(1, 7))


@dataclass(frozen=True, eq=False)
class GoughStewartGeometry:
    """The geometry of a Gough–Stewart platform read from its joints at home (G–A eqs. 71–74).

    Attributes
    ----------
    base_points : ndarray, shape=[6, 3]
        bᵢ in the base frame (eq. 71).
    platform_points : ndarray, shape=[6, 3]
        p′ᵢ in the platform frame (eq. 73).
    platform_radius, platform_angle : float
        R_P and φ_P (eq. 74), inferred from the platform points.
    home_centre : ndarray, shape=[3]
        x at home.
    home_orientation : ndarray, shape=[3, 3]
        Q at home: Pᵢ = x + Q p′ᵢ.
    home_lengths : ndarray, shape=[6]
        cᵢ at home (eq. 75).
    """

    base_points: np.ndarray
    platform_points: np.ndarray
    platform_radius: float
    platform_angle: float
    home_centre: np.ndarray
    home_orientation: np.ndarray
    home_lengths: np.ndarray


def gough_stewart_geometry(mechanism):
    """Read bᵢ, p′ᵢ, the home pose and the home leg lengths from a catalogue platform.

    R_P is the distance of the platform joints from the centre and φ_P half
    the angle between p′₆ and p′₁ (ηᵢ of eq. 74: η₁ = φ_P, η₆ = −φ_P); the home
    Q is the rotation taking p′ᵢ to Pᵢ − x (least squares). bᵢ and p′ᵢ are
    rounded to 12 decimals, so that the platforms of one design share one
    relation (the relations use exactly these values).

    Parameters
    ----------
    mechanism : Mechanism
        A ``gough-stewart`` catalogue mechanism (joints ``U{i}`` at bᵢ,
        ``P{i}`` along the legs, ``S{i}`` at the platform points; end-effector
        at the platform centre).

    Returns
    -------
    GoughStewartGeometry

    Raises
    ------
    ValueError
        If the platform points do not follow eqs. 73–74 (up to a rotation).
    """
    bases = np.array([mechanism.joint(f"U{index}").point for index in _LEGS], dtype=float)
    platforms = np.array([mechanism.joint(f"S{index}").point for index in _LEGS], dtype=float)
    centre = np.array(mechanism.end_effector.point, dtype=float)
    relative = platforms - centre
    radius = float(np.mean(np.linalg.norm(relative, axis=1)))
    first, sixth = relative[0], relative[5]
    angle = 0.5 * float(np.arctan2(np.linalg.norm(np.cross(sixth, first)), sixth @ first))
    body = platform_points(radius, angle)
    orientation, residual = orientation_from_vectors(body, relative)
    if residual > _LAYOUT_TOLERANCE * max(1.0, radius):
        raise ValueError(f"gough-stewart: the platform joints do not follow eqs. 73-74 turned by one rotation "
                         f"(residual {residual:.3g} with R_P = {radius:.6g}, phi_P = {angle:.6g})")
    return GoughStewartGeometry(np.round(bases, _KEY_DIGITS), np.round(body, _KEY_DIGITS), radius, angle, centre,
                                orientation, np.linalg.norm(platforms - bases, axis=1))


def _design_key(geometry):
    """The design (bᵢ, p′ᵢ) as a hashable key."""
    return tuple(np.ravel(geometry.base_points)), tuple(np.ravel(geometry.platform_points))


def _variables():
    return sympy.symbols("c1:7"), sympy.symbols("x y z r1 r2 r3")


def _legs(key, outputs):
    """Symbolic Q p′ᵢ and wᵢ = x + Q p′ᵢ − bᵢ = (Uᵢ, Vᵢ, Wᵢ) (eqs. 76–78, 80), each shape=[3, 1]."""
    bases, platforms = (np.reshape(values, (6, 3)) for values in key)
    centre, rotation = sympy.Matrix(outputs[:3]), outputs[3:]
    turned = [rotated(platform.tolist(), rotation) for platform in platforms]
    return turned, [centre + point - sympy.Matrix(base.tolist()) for point, base in zip(turned, bases)]


@functools.lru_cache(maxsize=None)
def _eq75_relation(key):
    inputs, outputs = _variables()
    _, legs = _legs(key, outputs)
    equations = [length - sympy.sqrt(leg.dot(leg)) for length, leg in zip(inputs, legs)]
    return relation_from_sympy(inputs, outputs, equations=equations, name="Gough-Stewart eq. 75",
                               reference=REFERENCE + " (eqs. 75-78, F_i = c_i - sqrt(U_i^2 + V_i^2 + W_i^2))",
                               units=UNITS)


@functools.lru_cache(maxsize=None)
def _eq81_relation(key):
    inputs, outputs = _variables()
    turned, legs = _legs(key, outputs)
    # −aᵢ (eq. 82, the sign of the module doc), rotational part times J_left(r)
    rows = [-leg.T.row_join(row_times_left_jacobian(point.cross(leg), outputs[3:]))
            for point, leg in zip(turned, legs)]
    return relation_from_sympy(inputs, outputs, input_jacobian=sympy.diag(*inputs),
                               output_jacobian=sympy.Matrix.vstack(*rows), name="Gough-Stewart eqs. 81-83",
                               reference=REFERENCE + " (eqs. 79-83, rows -a_i)", units=UNITS)


def _coordinates_function(mechanism, geometry):
    prismatic = [f"P{index}" for index in _LEGS]

    def coordinates(point):
        """(c, y) at `point`: leg lengths, shape=[6], and (x, y, z, r) with Q = expm([r]×), shape=[6]."""
        displacements = to_displacements(mechanism, point)
        lengths = geometry.home_lengths + np.array([displacements[name] for name in prismatic])
        frame = end_effector(mechanism, point)
        orientation = frame[:3, :3] @ geometry.home_orientation
        return lengths, np.concatenate([frame[:3, 3], rotation_log(orientation)])
    return coordinates


def eq75_relation(mechanism):
    """The inverse kinematics Fᵢ = cᵢ − √(Uᵢ² + Vᵢ² + Wᵢ²) = 0 (eqs. 75–78), differentiated symbolically.

    Parameters
    ----------
    mechanism : Mechanism
        A ``gough-stewart`` catalogue mechanism.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``c1..c6`` (leg lengths), outputs ``x, y, z, r1, r2, r3``
        (Q = expm([r]×)); F, shape=[6]; B = ∂F/∂c = 1, shape=[6, 6];
        A = ∂F/∂y, shape=[6, 6], with rows −(1/‖wᵢ‖)[wᵢᵀ, ((Q p′ᵢ) × wᵢ)ᵀ J_left(r)]:
        −diag(1/cᵢ) times eq. 82 (with the chart factor). Not finite where a
        leg has zero length (eq. 84): √ is not differentiable at 0. Shared by
        the platforms of one design (cached).
    coordinates : callable
        ``coordinates(point) -> (c, y)``, arrays of shape [6].

    References
    ----------
    Gosselin & Angeles 1990 Section VII, eqs. 71–78.
    """
    geometry = gough_stewart_geometry(mechanism)
    return _eq75_relation(_design_key(geometry)), _coordinates_function(mechanism, geometry)


def eq81_relation(mechanism):
    """The paper's velocity relation (eqs. 79–83) of a Gough–Stewart platform, in the chart (x, r).

    Parameters
    ----------
    mechanism : Mechanism
        A ``gough-stewart`` catalogue mechanism.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``c1..c6``, outputs ``x, y, z, r1, r2, r3`` (as
        :func:`eq75_relation`); B = diag(cᵢ) (eq. 83), shape=[6, 6]; A, shape=[6, 6],
        rows −[wᵢᵀ, ((Q p′ᵢ) × wᵢ)ᵀ J_left(r)]: eq. 82 with ω = J_left(r) ṙ and
        the sign that makes ``A ẏ + B ċ = 0`` hold (module doc); no residual.
        Shared by the platforms of one design (cached).
    coordinates : callable
        ``coordinates(point) -> (c, y)``, arrays of shape [6].

    References
    ----------
    Gosselin & Angeles 1990 Section VII, eqs. 79–83.
    """
    geometry = gough_stewart_geometry(mechanism)
    return _eq81_relation(_design_key(geometry)), _coordinates_function(mechanism, geometry)
