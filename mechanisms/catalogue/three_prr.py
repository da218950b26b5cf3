"""The planar 3-PRR parallel manipulator: Chablat, Caro, Wenger & Angeles, Fig. 1, eqs. (1)-(4).

Chablat, Caro, Wenger & Angeles 2002 §2: three PRR legs; the prismatic joints (the
actuators, displacements ρᵢ) slide along the sides of the base triangle
A₁A₂A₃ (equilateral, centre O, circumradius R); a leg BᵢCᵢ of length l joins
the slider Bᵢ to the platform pivot Cᵢ; the pivots form an equilateral
triangle of centre P (the operation point) and circumradius r. Design of
Figs. 6-8: r = 100 mm, R = 200 mm, l = 200 mm (lengths here in mm).

The figure is not in the text; our reading of it (stated, and consistent with
§3.3-3.4: the isotropic configuration "AᵢBᵢ collinear with BᵢCᵢ, BᵢCᵢ ⊥ CᵢP"
exists exactly when r = R/2, i.e. when the pivots can lie on the rails):

* Aᵢ = R (cos aᵢ, sin aᵢ) with a₁, a₂, a₃ = 210°, 330°, 90°;
* rail i runs from Aᵢ towards Aᵢ₊₁: αᵢ at 0°, 120°, 240°, Bᵢ = Aᵢ + ρᵢ αᵢ;
* Cᵢ = P + r (cos(φ + aᵢ), sin(φ + aᵢ)): at φ = 0 the platform triangle is
  parallel to the base triangle (φ is the paper's θ, the platform orientation).

Working modes (§3.5): the sign pattern of the diagonal mᵢ = (cᵢ − bᵢ)ᵀαᵢ of B
(eq. 4b), i.e. of the branch of the inverse kinematics of each leg.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry

__all__ = ["three_prr", "three_prr_at_inputs", "WORKING_MODES", "ENTRIES"]

#: Working mode (Fig. 5 numbering, our reading) -> signs of (m₁, m₂, m₃). Mode 1: all positive, mode 5
#: all negative (§3.5: "1 is similar to 5"); modes 2, 3, 4: one leg reversed, turned by 0°, 120°, 240°;
#: modes 6, 7, 8: their opposites (§3.5: "2-6, 3-7 and 4-8 likewise").
WORKING_MODES = {
    1: (1, 1, 1), 2: (-1, 1, 1), 3: (1, -1, 1), 4: (1, 1, -1),
    5: (-1, -1, -1), 6: (1, -1, -1), 7: (-1, 1, -1), 8: (-1, -1, 1),
}
_VERTEX_ANGLES = np.radians([210.0, 330.0, 90.0])   # aᵢ: the vertices Aᵢ and, at φ = 0, the pivots Cᵢ
_RAIL_ANGLES = np.radians([0.0, 120.0, 240.0])       # αᵢ: rail i from Aᵢ towards Aᵢ₊₁


def _unit(angles):
    return np.stack([np.cos(angles), np.sin(angles)], axis=-1)


def base_vertices(base_radius):
    """The vertices Aᵢ of the base triangle, shape=[3, 2]."""
    return base_radius * _unit(_VERTEX_ANGLES)


def rail_directions():
    """The unit vectors αᵢ of the prismatic joints, shape=[3, 2]."""
    return _unit(_RAIL_ANGLES)


def platform_pivots(platform_radius, x, y, phi):
    """The pivots Cᵢ of the platform at the pose (x, y, φ), shape=[3, 2]."""
    return np.array([x, y]) + platform_radius * _unit(_VERTEX_ANGLES + phi)


def _check_design(platform_radius, base_radius, leg_length):
    for name, value in (("platform_radius", platform_radius), ("base_radius", base_radius),
                        ("leg_length", leg_length)):
        if not (math.isfinite(value) and value > 0):
            raise MechanismError(f"3-PRR: {name} must be a positive length, got {value!r}")


def _assemble(platform_radius, base_radius, leg_length, pose, sliders, actuated, end_effector):
    """The joint graph at the pose (x, y, φ) with the sliders Bᵢ, shape=[3, 2]."""
    x, y, phi = pose
    pivots = platform_pivots(platform_radius, x, y, phi)
    joints = []
    for index, (axis, slider, pivot) in enumerate(zip(rail_directions(), sliders, pivots), start=1):
        joints += [
            Joint(f"rail{index}", "P", ("ground", f"carriage{index}"), axis=tuple(axis),
                  actuated=actuated),
            Joint(f"B{index}", "R", (f"carriage{index}", f"leg{index}"), point=tuple(slider)),
            Joint(f"C{index}", "R", (f"leg{index}", "platform"), point=tuple(pivot)),
        ]
    return Mechanism("3-prr", "planar", joints,
                     end_effector=EndEffector("platform", (float(x), float(y)), "pose") if end_effector else None)


def three_prr(*, platform_radius=100.0, base_radius=200.0, leg_length=200.0,
              x=0.0, y=0.0, phi=math.pi / 3, working_mode=1, actuated=True, end_effector=True):
    """3-PRR assembled at the platform pose (x, y, φ) in a working mode (Chablat et al. Fig. 1).

    Parameters
    ----------
    platform_radius, base_radius, leg_length : float
        r = ‖CᵢP‖, R = ‖AᵢO‖ and l = ‖BᵢCᵢ‖ (§2; Figs. 6-8: 100, 200, 200 mm).
    x, y : float
        The operation point P = (x, y), the centre of the platform triangle.
    phi : float
        Platform orientation θ (rad); at φ = 0 the platform triangle is parallel to the base
        triangle. The default (0, 0, π/3) is the isotropic configuration of Fig. 4a (γ = π/2,
        AᵢBᵢ collinear with BᵢCᵢ, possible because r = R/2).
    working_mode : int
        1 to 8, the signs of the diagonal entries mᵢ = (cᵢ − bᵢ)ᵀαᵢ of B (eq. 4b, §3.5), as in
        :data:`WORKING_MODES` (our numbering of Fig. 5, which is not in the text).
    actuated : bool
        Whether the prismatic joints (the inputs ρᵢ of the paper) are actuated.
    end_effector : bool
        Whether the platform pose (planar ``pose`` output at P) is the end-effector.

    Returns
    -------
    Mechanism
        Joints ``rail1..3`` (P, ground-carriageᵢ, along αᵢ), ``B1..3`` (R, carriageᵢ-legᵢ at Bᵢ),
        ``C1..3`` (R, legᵢ-platform at Cᵢ).

    Raises
    ------
    MechanismError
        For a bad design, an unknown working mode, or a pose out of reach of a leg (the distance
        from Cᵢ to rail i exceeds l).

    Notes
    -----
    Inverse kinematics of leg i: with dᵢ = cᵢ − aᵢ and νᵢ = Eαᵢ,

        ρᵢ = αᵢᵀdᵢ − sᵢ √(l² − (νᵢᵀdᵢ)²),   so   mᵢ = (cᵢ − bᵢ)ᵀαᵢ = sᵢ √(l² − (νᵢᵀdᵢ)²),

    sᵢ = ±1 the sign of mode `working_mode`. mᵢ = 0 (AᵢBᵢ ⊥ BᵢCᵢ) is a serial singularity (§2.3);
    where ‖l² − (νᵢᵀdᵢ)²‖ ≤ 1e-12 l² (roundoff of the pose) the leg is assembled square to its rail,
    since the square root would turn that roundoff into a 1e-6 l error.

    References
    ----------
    Chablat, Caro, Wenger & Angeles 2002 §2 (Fig. 1, eqs. 1-4), §3.4 (Fig. 4a), §3.5 (Fig. 5).
    """
    _check_design(platform_radius, base_radius, leg_length)
    if working_mode not in WORKING_MODES:
        raise MechanismError(f"3-PRR: working_mode must be an integer from 1 to 8, got {working_mode!r}")
    signs = np.array(WORKING_MODES[working_mode], dtype=float)
    pivots = platform_pivots(platform_radius, x, y, phi)
    directions = rail_directions()
    offsets = pivots - base_vertices(base_radius)
    along = np.einsum("ij,ij->i", offsets, directions)
    across = np.einsum("ij,ij->i", offsets, directions @ np.array([[0.0, 1.0], [-1.0, 0.0]]))
    reach = leg_length ** 2 - across ** 2
    roundoff = 1e-12 * leg_length ** 2
    for index in np.flatnonzero(reach < -roundoff):
        raise MechanismError(f"3-PRR: pose (x, y, phi) = ({x}, {y}, {phi}): pivot C{index + 1} is "
                             f"{abs(across[index]):.6g} from rail {index + 1}, beyond the leg length "
                             f"l = {leg_length}")
    reach[np.abs(reach) <= roundoff] = 0.0   # on a serial singularity up to roundoff: the leg square to its rail
    inputs = along - signs * np.sqrt(reach)
    sliders = base_vertices(base_radius) + inputs[:, None] * directions
    return _assemble(platform_radius, base_radius, leg_length, (x, y, phi), sliders, actuated, end_effector)


def three_prr_at_inputs(*, platform_radius=100.0, base_radius=200.0, leg_length=200.0,
                        rho1=-26.794919243112275, rho2=-26.794919243112275, rho3=-26.794919243112275,
                        x=0.0, y=0.0, phi=math.pi / 3, actuated=True, end_effector=True):
    """3-PRR assembled at the actuator inputs (ρ₁, ρ₂, ρ₃): the direct-kinematics solution nearest a guess.

    Parameters
    ----------
    platform_radius, base_radius, leg_length : float
        r, R, l as in :func:`three_prr`.
    rho1, rho2, rho3 : float
        The actuated displacements ρᵢ = ‖AᵢBᵢ‖ (signed, along αᵢ); Bᵢ = Aᵢ + ρᵢαᵢ. The default,
        R(√3/2 − 1) each, is the isotropic configuration of Fig. 4a.
    x, y, phi : float
        The initial guess of the pose; the direct kinematics has several solutions (assembly
        modes) and the one a Gauss-Newton solve reaches from the guess is assembled.
    actuated, end_effector : bool
        As in :func:`three_prr`.

    Returns
    -------
    Mechanism

    Raises
    ------
    MechanismError
        When no pose closes the legs from the guess (``rho1..3`` out of reach, or a poor guess).

    Notes
    -----
    Solves ‖cᵢ(x, y, φ) − bᵢ(ρᵢ)‖² = l², i = 1, 2, 3 (scipy ``least_squares``), then checks closure
    to 1e-9 l.

    References
    ----------
    Chablat, Caro, Wenger & Angeles 2002 §2, §2.2 (direct kinematics, matrix A).
    """
    from scipy.optimize import least_squares  # imported when used: the other builders do not need it

    _check_design(platform_radius, base_radius, leg_length)
    sliders = base_vertices(base_radius) + np.array([rho1, rho2, rho3])[:, None] * rail_directions()

    def residual(pose):
        legs = platform_pivots(platform_radius, pose[0], pose[1], pose[2]) - sliders
        return (np.einsum("ij,ij->i", legs, legs) - leg_length ** 2) / leg_length

    solution = least_squares(residual, [x, y, phi], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    if np.max(np.abs(residual(solution.x))) > 1e-9 * leg_length:
        raise MechanismError(f"3-PRR: inputs (rho1, rho2, rho3) = ({rho1}, {rho2}, {rho3}): no pose closes "
                             f"the legs from the guess (x, y, phi) = ({x}, {y}, {phi})")
    pose = tuple(float(value) for value in solution.x)
    return _assemble(platform_radius, base_radius, leg_length, pose, sliders, actuated, end_effector)


_CENTRED_CONCURRENCY = math.acos(200.0 / (2 * (100.0 + 200.0)))   # (r + l) cos(φ − π/3) = R/2
_PARALLEL_DIRECTION = math.radians(10.0)                            # δ of the parallel legs

ENTRIES = (
    Entry("3-prr", three_prr,
          "Chablat, Caro, Wenger & Angeles (2002) Fig. 1, eqs. (3)-(4), "
          "§2.2-2.3 (Figs. 2-3), §3.4 (Fig. 4a), §3.5 (Fig. 5)",
          {
              # Fig. 4a: isotropic, γ = π/2, AᵢBᵢ collinear with BᵢCᵢ (the defaults)
              "fig4a_isotropic": {},
              # Fig. 2: lines BᵢCᵢ concurrent at P (P = O, legs radial: (r + l) cos(φ − π/3) = R/2)
              "fig2_concurrent_at_centre": {"phi": math.pi / 3 - _CENTRED_CONCURRENCY},
              # Fig. 2, "possibly at infinity": legs parallel to (cos δ, sin δ), P = l (cos δ, sin δ),
              # φ = π/3 (exists because r = R/2; mᵢ = l cos(δ − αᵢ) gives signs +, −, −)
              "fig2_parallel_legs": {"x": 200.0 * math.cos(_PARALLEL_DIRECTION),
                                     "y": 200.0 * math.sin(_PARALLEL_DIRECTION),
                                     "working_mode": 6},
              # Fig. 3: A₁B₁ ⊥ B₁C₁ (C₁ at distance l from rail 1)
              "fig3_serial_leg1": {"y": 200.0},
          }),
    Entry("3-prr-inputs", three_prr_at_inputs,
          "Chablat, Caro, Wenger & Angeles (2002) Fig. 1, eqs. (3)-(4)",
          {"fig4a_isotropic": {}}),
)
