"""The three-dof hybrid manipulator: Chablat, Wenger & Angeles Fig. 6, eqs. (14)-(30).

The symmetric five-bar of Fig. 1 (``five_bar.py``) turned about the line AB of
its fixed revolutes by a third actuated revolute (Chablat, Wenger & Angeles 1998
Sec. 4). AB is the Y axis: A at the origin, B = (0, L0, 0). In Chablat, Wenger & Angeles 1998's notation
for this manipulator θ1 is the angle of the base revolute about Y, θ2 and θ3
the actuated angles of the five-bar at A and B, θ4 and θ5 the angles of the
distal links P − C and P − D, all five-bar angles measured from the direction
AB in the plane of the five-bar, so that the distance of P to the Y axis is
d1 = L1 sin θ2 + L2 sin θ4 (eq. 27).

Singularities (eqs. 22, 24, 30): the direct-kinematics matrix A (eq. 22a) is
singular iff θ4 − θ5 = kπ (eqs. 24-25); the inverse-kinematics matrix B
(eq. 22b) iff d1 = 0 (P on the axis of the base revolute), θ2 = θ4 + kπ or
θ3 = θ5 + kπ (eq. 30).
"""

from __future__ import annotations

import math

from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry, read_only_with
from .five_bar import circle_intersection, five_bar_inputs, five_bar_points

__all__ = ["hybrid", "hybrid_points", "ENTRIES"]

_LOOP = (("A", ("frame", "proximal_left")), ("C", ("proximal_left", "distal_left")),
         ("P", ("distal_left", "distal_right")), ("D", ("distal_right", "proximal_right")),
         ("B", ("proximal_right", "frame")))
#: The hybrid's names of the five-bar's angles (:func:`five_bar_points`), for its error messages.
_FIVE_BAR_NAMES = {"theta1": "theta2", "theta2": "theta3", "theta3": "theta4"}


def hybrid_points(*, base=6.0, proximal=8.0, distal=5.0, theta1=0.4, theta2=1.8, theta3=1.3, assembly=1,
                  theta4=0.0):
    """Joint centres A, C, P, D, B of the hybrid manipulator and the normal of the five-bar's plane.

    Parameters
    ----------
    base, proximal, distal : float
        L0 = ‖AB‖, L1 = ‖AC‖ = ‖BD‖, L2 = ‖CP‖ = ‖DP‖ (Chablat, Wenger & Angeles 1998, Figs. 1, 6).
    theta1 : float
        θ1, the angle (rad) of the base revolute about the Y axis (line AB).
    theta2, theta3 : float
        θ2 and θ3, the actuated angles of the five-bar at A and B (rad), from AB.
    assembly : {1, -1, 0}
        The five-bar's direct-kinematics branch (``five_bar_points``); 0: C = D,
        P placed by `theta4`.
    theta4 : float
        θ4, the angle of P − C from AB; read only with ``assembly=0``.

    Returns
    -------
    points : dict of str to tuple of float, shape=[3]
    normal : tuple of float, shape=[3]
        The axis of the five-bar's revolutes, normal to its plane.

    Notes
    -----
    A point (u, v) of the five-bar's plane (u along AB) is u j + v e with
    e = (cos θ1, 0, −sin θ1), the x axis turned by θ1 about Y; the normal is j × e.
    """
    planar = five_bar_points(base=base, proximal=proximal, distal=distal, theta1=theta2, theta2=theta3,
                             assembly=assembly, theta3=theta4, label="hybrid", names=_FIVE_BAR_NAMES)
    across = (math.cos(theta1), 0.0, -math.sin(theta1))
    points = {name: (v * across[0], u, v * across[2]) for name, (u, v) in planar.items()}
    normal = (-math.sin(theta1), 0.0, -math.cos(theta1))
    return points, normal


def hybrid(*, base=6.0, proximal=8.0, distal=5.0, theta1=0.4, theta2=1.8, theta3=1.3, assembly=1, theta4=0.0,
           end_effector=True):
    """The 3-dof hybrid manipulator of Chablat, Wenger & Angeles 1998, Fig. 6: a five-bar turned about AB, at inputs θ1, θ2, θ3.

    Parameters
    ----------
    base, proximal, distal : float
        L0, L1 = L3, L2 = L4 (Chablat, Wenger & Angeles 1998, Sec. 3.4 design: 6, 8, 5).
    theta1 : float
        θ1, the base revolute's angle about AB (the Y axis), rad.
    theta2, theta3 : float
        θ2, θ3, the five-bar's actuated angles at A and B (rad), from AB.
    assembly : {1, -1, 0}
        The five-bar's direct-kinematics branch: P left (+1) or right (−1) of
        C→D in the plane's (AB, e) frame; 0: coincident elbows, P placed by `theta4`.
    theta4 : float
        θ4, the angle of P − C; read only with ``assembly=0`` (the catalogue entry refuses it set otherwise).
    end_effector : bool
        Whether the position of P (carried by the link CP) is the end-effector.

    Returns
    -------
    Mechanism
        Spatial joints ``base`` (ground-frame, about Y, driven), ``A``, ``C``,
        ``P``, ``D``, ``B`` (the five-bar on the frame; A and B driven).

    Notes
    -----
    Chablat, Wenger & Angeles 1998, eq. (22): A ṗ = B θ˙ with A = [L2 kᵀ; (p − c)ᵀ; (p − d)ᵀ] and
    B = L1 L2 diag(sin θ2 + λ1 sin θ4, sin(θ2 − θ4), sin(θ3 − θ5)), λ1 = L2/L1.
    det A = 0 iff θ4 − θ5 = kπ (eq. 24): actuator singularity; B singular iff
    d1 = L1 sin θ2 + L2 sin θ4 = 0, θ2 = θ4 + kπ or θ3 = θ5 + kπ (eq. 30):
    end-effector singularity.

    References
    ----------
    Chablat, Wenger, Angeles, 1998, Fig. 6, eqs. (14)-(30).
    """
    points, normal = hybrid_points(base=base, proximal=proximal, distal=distal, theta1=theta1, theta2=theta2,
                                   theta3=theta3, assembly=assembly, theta4=theta4)
    joints = [Joint("base", "R", ("ground", "frame"), point=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), actuated=True)]
    joints += [Joint(name, "R", links, point=points[name], axis=normal, actuated=name in ("A", "B"))
               for name, links in _LOOP]
    tool = EndEffector("distal_left", points["P"], "position") if end_effector else None
    return Mechanism("hybrid", "spatial", joints, end_effector=tool)


def _planar(x, y, working_mode="-+"):
    """Hybrid inputs θ2, θ3 and branch reaching P = (x, y) (x along AB, y across) in Chablat, Wenger & Angeles 1998's design."""
    inputs = five_bar_inputs(x, y, working_mode=working_mode)
    return {"theta2": inputs["theta1"], "theta3": inputs["theta2"], "assembly": inputs["assembly"]}


def _distal_aligned(theta2, side=1):
    """θ4 − θ5 = π (eqs. 24-25): ‖CD‖ = 2 L2, D on the circle of radius L1 about B."""
    c = (8.0 * math.cos(theta2), 8.0 * math.sin(theta2))
    d = circle_intersection(c, 10.0, (6.0, 0.0), 8.0, side)
    return {"theta2": theta2, "theta3": math.atan2(d[1], d[0] - 6.0)}


ENTRIES = (
    Entry("hybrid", hybrid,
          "Chablat, Wenger & Angeles (1998) Fig. 6, eqs. (14)-(30)",
          {
              "regular": {},
              # eq. 30, d1 = 0: P on the Y axis (the base revolute's axis), beyond A.
              "eq30_on_the_axis": _planar(-5.0, 0.0),
              # eq. 30, θ2 = θ4 + kπ: the leg at A stretched (k = 0) or folded (k = 1).
              "eq30_left_leg_stretched": _planar(13.0 * math.cos(1.2), 13.0 * math.sin(1.2)),
              "eq30_left_leg_folded": _planar(3.0 * math.cos(2.2), 3.0 * math.sin(2.2)),
              # eq. 30, θ3 = θ5 + kπ: the leg at B stretched or folded.
              "eq30_right_leg_stretched": _planar(6.0 + 13.0 * math.cos(1.9), 13.0 * math.sin(1.9)),
              "eq30_right_leg_folded": _planar(6.0 + 3.0 * math.cos(1.0), 3.0 * math.sin(1.0)),
              # eq. 25, θ4 − θ5 = π: the distal links aligned.
              "eq25_distal_aligned": _distal_aligned(1.2),
              # eq. 25 with k = 0, θ4 = θ5: the elbows C and D coincide and P turns freely about them.
              "eq25_elbows_coincide": {"theta2": math.atan2(math.sqrt(55.0), 3.0),
                                       "theta3": math.atan2(math.sqrt(55.0), -3.0), "assembly": 0, "theta4": 2.8},
          },
          read_only={"theta4": read_only_with("assembly", 0)}),
)
