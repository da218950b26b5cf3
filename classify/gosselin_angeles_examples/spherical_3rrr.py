"""Gosselin–Angeles relations of the spherical 3-RRR wrist (Gosselin & Angeles 1990, eqs. 66–70).

Section VI of Gosselin & Angeles: three legs, each a motor (fixed axis uᵢ),
an intermediate revolute pair (axis wᵢ) and a revolute pair on the gripper
(axis vᵢ), every axis through the centre of the sphere, with link angles
α₁ = ∠(uᵢ, wᵢ) and α₂ = ∠(wᵢ, vᵢ), the same in every leg (eq. 66). The
velocity relation is ``A ω + B θ̇ = 0`` (eq. 67) with A rows (wᵢ × vᵢ)ᵀ
(eq. 68) and ``B = diag((wᵢ × uᵢ)·vᵢ)`` (eq. 69).

Two relations of the catalogue wrist (:mod:`mechanisms.catalogue.spherical_3rrr`)
in the same variables:

* :func:`spherical_3rrr_relation`: the closure of each leg as a position
  relation, ``Fᵢ(θ, r) = wᵢ(θᵢ)·vᵢ(r) − cos α₂ = 0``, differentiated
  symbolically (eq. 3);
* :func:`eq68_relation`: the paper's A and B (eqs. 68–69) as printed.

Variables. The inputs θᵢ are motor angles measured as in the catalogue: wᵢ =
cos α₁ uᵢ + sin α₁ (cos θᵢ tᵢ + sin θᵢ sᵢ) with tᵢ = n × uᵢ/‖n × uᵢ‖ in the
plane of the motors (normal n = u₁ × u₂/‖u₁ × u₂‖) and sᵢ = uᵢ × tᵢ (= n for
the paper's coplanar motors): θᵢ is the angle of the proximal link from the
base plane, so that the paper's θ₁ = θ₂ = θ₃ = 0 or π/2 (Section VI) are these
angles. The outputs are the gripper orientation Q in a rotation-vector chart
r: ``Q = expm([r]×) Q_reference`` with Q_reference = 1 in the gripper frame of
the paper's symmetric layout, where the gripper axes are vᵢ = Q uᵢ (as in the
catalogue), so that r is the catalogue's (rotation_x, rotation_y, rotation_z)
and vᵢ(r) = expm([r]×) uᵢ; the home Q is recovered from the joint axes
(:func:`spherical_3rrr_geometry`), and r = log Q (‖r‖ ≤ π). The paper's A
multiplies the angular velocity ω (eq. 67), and ω = J_left(r) ṙ
(:func:`left_jacobian`), so in the chart ``A_chart = A_paper J_left(r)``; the
ranks are those of the paper's A (J_left is invertible for ‖r‖ < 2π).

Signs: differentiating Fᵢ gives (uᵢ × wᵢ)·vᵢ θ̇ᵢ + (vᵢ × wᵢ)·ω = 0, so the
symbolic B and A are minus eqs. 69 and 68 (times J_left): both describe the
same velocities, and the kinds are the same.

Rodrigues' formula is written with the entire functions gₘ(s) of
:class:`RodriguesSeries` (s = ‖r‖²) so that the relation and its symbolic
derivatives are finite at r = 0 (e.g. the folded legs of Section VI, Q = 1).
The relations depend on the design only (α₁, α₂, uᵢ) and are cached per
design: building one takes about a second.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import sympy

from manifold import rotation_log
from mechanisms import link_pose, to_displacements

from ..gosselin_angeles import relation_from_sympy
from ._rotations import RodriguesSeries, orientation_from_vectors, rotated, row_times_left_jacobian

__all__ = [
    "SphericalGeometry", "spherical_3rrr_geometry", "spherical_3rrr_relation",
    "eq68_relation",
]

#: largest spread of α₁ (resp. α₂) over the legs, and largest residual of vᵢ = Q uᵢ, for the
#: symmetric design of eq. 66
_SYMMETRY_TOLERANCE = 1e-9

#: decimals of the design values (uᵢ, α₁, α₂): the wrists of one design share one relation
_KEY_DIGITS = 12

REFERENCE = "Gosselin & Angeles (1990) Section VI, eqs. 66-70"


@dataclass(frozen=True, eq=False)
class SphericalGeometry:
    """The geometry of a spherical 3-RRR wrist read from its joints at home (G–A eq. 66, Fig. 9).

    Attributes
    ----------
    motor_axes : ndarray, shape=[3, 3]
        uᵢ (rows), unit, in the base frame.
    gripper_axes : ndarray, shape=[3, 3]
        vᵢ in the gripper frame (rows), unit: the motor axes, as in the
        paper's symmetric layout (Section VI) and the catalogue (vᵢ = Q uᵢ).
    alpha1, alpha2 : float
        α₁ = ∠(uᵢ, wᵢ) and α₂ = ∠(wᵢ, vᵢ) (rad), the same in every leg (eq. 66).
    normal : ndarray, shape=[3]
        n, the unit normal of the plane of u₁, u₂.
    tangents, binormals : ndarray, shape=[3, 3]
        tᵢ = n × uᵢ/‖n × uᵢ‖ and sᵢ = uᵢ × tᵢ: wᵢ = cos α₁ uᵢ + sin α₁
        (cos θᵢ tᵢ + sin θᵢ sᵢ).
    home_input_angles : ndarray, shape=[3]
        θᵢ at home.
    home_orientation : ndarray, shape=[3, 3]
        Q at home: vᵢ(home) = Q uᵢ.
    gripper_link : str
    """

    motor_axes: np.ndarray
    gripper_axes: np.ndarray
    alpha1: float
    alpha2: float
    normal: np.ndarray
    tangents: np.ndarray
    binormals: np.ndarray
    home_input_angles: np.ndarray
    home_orientation: np.ndarray
    gripper_link: str


def _unit_axes(mechanism, prefix):
    vectors = np.array([mechanism.joint(f"{prefix}{index}").axis for index in (1, 2, 3)], dtype=float)
    return vectors / np.linalg.norm(vectors, axis=1, keepdims=True)


def _common_angle(first, second, name):
    angles = np.arccos(np.clip(np.einsum("ij,ij->i", first, second), -1.0, 1.0))
    if np.ptp(angles) > _SYMMETRY_TOLERANCE * max(1.0, float(np.max(angles))):
        raise ValueError(f"spherical 3-RRR: {name} differs between the legs ({np.degrees(angles)} degrees); "
                         f"eq. 66 assumes the same link angles in every leg")
    return float(np.mean(angles))


def _rounded(values):
    """Design values rounded to ``_KEY_DIGITS`` decimals (one cached relation per design)."""
    return np.round(np.asarray(values, dtype=float), _KEY_DIGITS)


def _frames(motors):
    """n, tᵢ = n × uᵢ/‖n × uᵢ‖ and sᵢ = uᵢ × tᵢ from the motor axes uᵢ (shape=[3, 3])."""
    normal = np.cross(motors[0], motors[1])
    normal /= np.linalg.norm(normal)
    tangents = np.cross(normal, motors)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    return normal, tangents, np.cross(motors, tangents)


def spherical_3rrr_geometry(mechanism):
    """Read uᵢ, α₁, α₂, the home motor angles and the home orientation Q from a catalogue wrist.

    The design values (uᵢ, α₁, α₂) are rounded to 12 decimals, so that the
    wrists of one design share one relation (the relations use exactly these
    values).

    Parameters
    ----------
    mechanism : Mechanism
        A ``spherical-3rrr`` catalogue mechanism (joints ``motor{i}``,
        ``elbow{i}``, ``wrist{i}``).

    Returns
    -------
    SphericalGeometry

    Raises
    ------
    ValueError
        If the link angles differ between legs (eq. 66), or if the gripper
        axes at home are not the motor axes turned by one rotation (the
        paper's symmetric layout).
    """
    motors, elbows, wrists = (_unit_axes(mechanism, prefix) for prefix in ("motor", "elbow", "wrist"))
    alpha1 = float(_rounded(_common_angle(motors, elbows, "alpha1 = angle(u, w)")))
    alpha2 = float(_rounded(_common_angle(elbows, wrists, "alpha2 = angle(w, v)")))
    orientation, residual = orientation_from_vectors(motors, wrists)
    if residual > _SYMMETRY_TOLERANCE:
        raise ValueError(f"spherical 3-RRR: the gripper axes at home are not the motor axes turned by one "
                         f"rotation (residual {residual:.3g}); Section VI's symmetric layout has vᵢ = Q uᵢ")
    motors = _rounded(motors)
    normal, tangents, binormals = _frames(motors)
    angles = np.arctan2(np.einsum("ij,ij->i", elbows, binormals), np.einsum("ij,ij->i", elbows, tangents))
    link = mechanism.end_effector.link if mechanism.end_effector is not None else "gripper"
    return SphericalGeometry(motors, motors.copy(), alpha1, alpha2, normal, tangents, binormals, angles,
                             orientation, link)


def _design_key(geometry):
    """The design (α₁, α₂, uᵢ, vᵢ in the gripper frame) as a hashable key."""
    return ((geometry.alpha1, geometry.alpha2), tuple(np.ravel(geometry.motor_axes)),
            tuple(np.ravel(geometry.gripper_axes)))


def _variables():
    return sympy.symbols("theta1 theta2 theta3"), sympy.symbols("r1 r2 r3")


def _design_vectors(key):
    (alpha1, alpha2), motors, grippers = key
    motors = np.reshape(motors, (3, 3))
    _, tangents, binormals = _frames(motors)
    return alpha1, alpha2, motors, tangents, binormals, np.reshape(grippers, (3, 3))


def _elbow_dot(vector, angle, motor, tangent, binormal, alpha1):
    """wᵢ(θᵢ)·a with wᵢ = cos α₁ uᵢ + sin α₁ (cos θᵢ tᵢ + sin θᵢ sᵢ), a numeric or SymPy (shape=[3])."""
    vector = sympy.Matrix(list(vector))
    return (sympy.cos(alpha1) * vector.dot(list(motor))
            + sympy.sin(alpha1) * (sympy.cos(angle) * vector.dot(list(tangent))
                                   + sympy.sin(angle) * vector.dot(list(binormal))))


@functools.lru_cache(maxsize=None)
def _closure_relation(key):
    alpha1_value, alpha2_value, motors, tangents, binormals, grippers = _design_vectors(key)
    inputs, outputs = _variables()
    alpha1, alpha2 = sympy.symbols("alpha1 alpha2")
    axis = sympy.Matrix(outputs)
    square = sum(component ** 2 for component in outputs)
    equations = []
    for index, angle in enumerate(inputs):
        legs = (angle, motors[index], tangents[index], binormals[index], alpha1)
        gripper = sympy.Matrix(grippers[index].tolist())
        # wᵢ·expm([r]×)vᵢ' = g₀ wᵢ·v' + g₁ wᵢ·(r × v') + g₂ (wᵢ·r)(r·v') (Rodrigues, :func:`rotated`)
        equations.append(RodriguesSeries(0, 0, square) * _elbow_dot(gripper, *legs)
                         + RodriguesSeries(1, 0, square) * _elbow_dot(axis.cross(gripper), *legs)
                         + RodriguesSeries(2, 0, square) * _elbow_dot(axis, *legs) * axis.dot(gripper)
                         - sympy.cos(alpha2))
    return relation_from_sympy(inputs, outputs, equations=equations,
                               parameters={alpha1: alpha1_value, alpha2: alpha2_value},
                               name="spherical 3-RRR leg closure w_i.v_i = cos alpha2",
                               reference=REFERENCE + " (leg closure; A, B = -eqs. 68-69 times J_left)",
                               units=("angle",) * 6)


@functools.lru_cache(maxsize=None)
def _velocity_relation(key):
    alpha1_value, _, motors, tangents, binormals, grippers = _design_vectors(key)
    inputs, outputs = _variables()
    alpha1 = sympy.Symbol("alpha1")
    rows, diagonal = [], []
    for index, angle in enumerate(inputs):
        motor, tangent, binormal = (sympy.Matrix(vector[index].tolist()) for vector in (motors, tangents, binormals))
        elbow = sympy.cos(alpha1) * motor + sympy.sin(alpha1) * (sympy.cos(angle) * tangent
                                                                  + sympy.sin(angle) * binormal)
        wrist = rotated(grippers[index].tolist(), outputs)
        rows.append(row_times_left_jacobian(elbow.cross(wrist), outputs))  # (wᵢ × vᵢ)ᵀ J_left, eq. 68
        diagonal.append(elbow.cross(motor).dot(wrist))  # (wᵢ × uᵢ)·vᵢ, eq. 69
    return relation_from_sympy(inputs, outputs, input_jacobian=sympy.diag(*diagonal),
                               output_jacobian=sympy.Matrix.vstack(*rows), parameters={alpha1: alpha1_value},
                               name="spherical 3-RRR eqs. 68-69", reference=REFERENCE + " (eqs. 67-69)",
                               units=("angle",) * 6)


def _coordinates_function(mechanism, geometry):
    motors = [f"motor{index}" for index in (1, 2, 3)]

    def coordinates(point):
        """(θ, r) at `point`: motor angles, shape=[3], and r = log Q, shape=[3]."""
        displacements = to_displacements(mechanism, point)
        theta = geometry.home_input_angles + np.array([displacements[name] for name in motors])
        orientation = link_pose(mechanism, geometry.gripper_link, point) @ geometry.home_orientation
        return theta, rotation_log(orientation)
    return coordinates


def spherical_3rrr_relation(mechanism):
    """The leg closures Fᵢ = wᵢ(θᵢ)·vᵢ(r) − cos α₂ = 0 of a spherical 3-RRR, differentiated symbolically.

    Parameters
    ----------
    mechanism : Mechanism
        A ``spherical-3rrr`` catalogue mechanism.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``theta1..3`` (motor angles, module doc), outputs ``r1..3``
        (Q = expm([r]×)); F, shape=[3]; B = ∂F/∂θ, shape=[3, 3], diagonal,
        equal to −diag((wᵢ × uᵢ)·vᵢ) (eq. 69); A = ∂F/∂r, shape=[3, 3], equal to
        −[(wᵢ × vᵢ)ᵀ] J_left(r) (eq. 68 times the chart factor). Shared by
        the wrists of one design (cached).
    coordinates : callable
        ``coordinates(point) -> (theta, r)``, arrays of shape [3], read from the
        motor displacements (plus the home angles) and the gripper's pose.

    References
    ----------
    Gosselin & Angeles 1990 Section VI, eqs. 66–70; the constraint
    ∠(wᵢ, vᵢ) = α₂ is the definition of the distal links of Fig. 9.
    """
    geometry = spherical_3rrr_geometry(mechanism)
    return _closure_relation(_design_key(geometry)), _coordinates_function(mechanism, geometry)


def eq68_relation(mechanism):
    """The paper's velocity relation A ω + B θ̇ = 0 (eqs. 67–69) of a spherical 3-RRR, in the chart r.

    Parameters
    ----------
    mechanism : Mechanism
        A ``spherical-3rrr`` catalogue mechanism.

    Returns
    -------
    relation : InputOutputRelation
        Inputs ``theta1..3``, outputs ``r1..3`` (as :func:`spherical_3rrr_relation`);
        A = [(wᵢ × vᵢ)ᵀ] J_left(r) (eq. 68 with ω = J_left(r) ṙ), shape=[3, 3];
        B = diag((wᵢ × uᵢ)·vᵢ) (eq. 69), shape=[3, 3]; no residual (the paper
        prints only the velocity relation). Shared by the wrists of one design.
    coordinates : callable
        ``coordinates(point) -> (theta, r)``, arrays of shape [3].

    References
    ----------
    Gosselin & Angeles 1990 Section VI, eqs. 67–69.
    """
    geometry = spherical_3rrr_geometry(mechanism)
    return _velocity_relation(_design_key(geometry)), _coordinates_function(mechanism, geometry)
