"""The line-plane 5-SPU: Borràs, Thomas & Torras, Section II and Section V.

Five legs from a planar base to a linear platform (Borràs, Thomas & Torras 2011
Figs. 1, 2): leg i has a spherical joint at the base attachment
aᵢ = (xᵢ, yᵢ, 0) in the plane Π (z = 0), an actuated prismatic joint along
the leg, and a universal joint at the platform attachment bᵢ = p + zᵢ i on the
line Λ, where p = (pₓ, p_y, p_z) is a point of Λ and i = (u, v, w) its unit
direction (Section II). One revolute axis of every universal joint lies along
Λ, so the five revolutes are aligned and the tool turns freely about Λ (the
paper's Fig. 1 caption). The end-effector is the axisymmetric tool itself
(``output: tool``: the point p and the direction i of Λ, in ℝ³ × S²), which
that spin does not move: the classifier reports the spin as an idle freedom,
not as an architecture singularity. Blocking one of the aligned revolutes
(the paper's alternative, Section I) removes it.

The singular configurations are the zeros of (17),
[w (C₂ C₃ C₆) − p_z (C₄ C₅ C₁)] · (pₓ w − p_z u, p_y w − p_z v, w)ᵀ = 0, with
Cⱼ the cofactors of the first row of the determinant (12); for the
quadratically solvable designs zᵢ = δ xᵢ (26), x₁ = y₁ = 0, they reduce to
δ² w F [δ w pₓ − (δ u − 1) p_z] = 0 (33).
"""

from __future__ import annotations

import numpy as np

from ..errors import MechanismError
from ..joints import EndEffector, Joint
from ..mechanism import Mechanism
from ._entry import Entry

__all__ = ["five_spu", "cofactors", "singularity_polynomial", "ENTRIES"]

#: default design: a quadratically solvable one, zᵢ = δ xᵢ with δ = 1/2 and x₁ = y₁ = 0 (eq. 26)
_DELTA = 0.5
_X = (0.0, 2.0, -1.0, 1.5, -2.0)
_Y = (0.0, 1.0, 2.0, -1.5, -1.0)
_Z = tuple(_DELTA * x for x in _X)
#: default pose: p and the (unnormalised) direction of Λ
_P = (1.0, 0.5, 3.0)
_I = (0.3, -0.2, 1.0)


def five_spu(*, x1=_X[0], y1=_Y[0], z1=_Z[0], x2=_X[1], y2=_Y[1], z2=_Z[1], x3=_X[2], y3=_Y[2], z3=_Z[2],
             x4=_X[3], y4=_Y[3], z4=_Z[3], x5=_X[4], y5=_Y[4], z5=_Z[4],
             p_x=_P[0], p_y=_P[1], p_z=_P[2], u=_I[0], v=_I[1], w=_I[2],
             spin="free", end_effector="tool"):
    """5-SPU with planar base and linear platform, assembled at the line pose (p, i).

    Parameters
    ----------
    x1, y1, ..., x5, y5 : float
        Base attachments aᵢ = (xᵢ, yᵢ, 0) in the plane Π (Section II). The
        defaults are a quadratically solvable design (Section V): x₁ = y₁ = 0,
        no four attachments collinear, F = 225 ≠ 0 in (28).
    z1, ..., z5 : float
        Platform attachments: the coordinate zᵢ of bᵢ = p + zᵢ i along Λ.
        Defaults zᵢ = δ xᵢ with δ = 1/2 (eq. 26).
    p_x, p_y, p_z : float
        p, the point of Λ with coordinate z = 0 (Section II).
    u, v, w : float
        Direction i = (u, v, w) of Λ; normalised by the builder (the paper's
        i is the unit vector), so only the direction counts.
    spin : {"free", "locked"}
        "free": every universal joint has its second revolute along Λ, so the
        tool spins freely about Λ (an idle freedom; dof 6). "locked": that
        revolute is blocked in leg 1, whose universal joint becomes a single
        revolute about n₁ = d₁ × i (d₁ the leg direction) — the paper's
        alternative (Section I); dof 5. A blocked S-P-R leg transmits, besides
        its actuated force, a force along n₁ through a₁, whose moment about Λ
        is −‖d₁ × i‖ ≠ 0, so it fixes the spin and adds no singularity: the
        five leg lines are dependent exactly when the six wrenches are.
    end_effector : {"tool", "pose", "position", "none"}
        The tool on Λ, the point p and the direction i (``tool``, ℝ³ × S²:
        the spin about Λ does not move it), the platform frame at p (pose:
        with the spin free, the spin moves it and the design is
        architecturally singular), the point p alone, or no end-effector.

    Returns
    -------
    Mechanism
        Links ``ground``, ``cylinder1..5`` (S side), ``piston1..5`` (U side),
        ``platform``; joints ``S1..S5`` (ground-cylinderᵢ at aᵢ), ``P1..P5``
        (cylinderᵢ-pistonᵢ along bᵢ − aᵢ, actuated), ``U1..U5``
        (pistonᵢ-platform at bᵢ, axes (nᵢ, i) with nᵢ = dᵢ × i / ‖dᵢ × i‖
        fixed in the piston and i fixed in the platform) — or ``R1`` instead of
        ``U1`` when the spin is locked.

    Raises
    ------
    MechanismError
        If i = 0, a leg has zero length (aᵢ = bᵢ) or lies along Λ (its
        universal joint's axes would be parallel), or for an unknown option.

    References
    ----------
    Borràs, Thomas & Torras 2011 Figs. 1, 2, Section II (attachments and
    pose), Section V eq. (26) (the quadratically solvable design).
    """
    if spin not in ("free", "locked"):
        raise MechanismError(f"5-spu: spin must be 'free' or 'locked', got {spin!r}")
    if end_effector not in ("tool", "pose", "position", "none"):
        raise MechanismError(f"5-spu: end_effector must be 'tool', 'pose', 'position' or 'none', "
                             f"got {end_effector!r}")
    direction = np.array([u, v, w], dtype=float)
    norm = float(np.linalg.norm(direction))
    if not norm > 1e-12:
        raise MechanismError(f"5-spu: u, v, w: the direction of the platform line is zero ({u}, {v}, {w})")
    direction /= norm
    point = np.array([p_x, p_y, p_z], dtype=float)
    base = [(x1, y1), (x2, y2), (x3, y3), (x4, y4), (x5, y5)]
    along = [z1, z2, z3, z4, z5]
    joints = []
    for index, ((x, y), z) in enumerate(zip(base, along), start=1):
        a = np.array([x, y, 0.0])
        b = point + z * direction
        leg = b - a
        length = float(np.linalg.norm(leg))
        if length < 1e-9 * max(1.0, float(np.linalg.norm(a))):
            raise MechanismError(f"5-spu: leg {index} has zero length (x{index}, y{index}, z{index}: "
                                 f"a{index} = b{index} = {tuple(a.round(12))})")
        normal = np.cross(leg / length, direction)
        if np.linalg.norm(normal) < 1e-9:
            raise MechanismError(f"5-spu: leg {index} lies along the platform line (x{index}, y{index}, z{index}): "
                                 f"its universal joint's axes would be parallel")
        normal /= np.linalg.norm(normal)
        cylinder, piston = f"cylinder{index}", f"piston{index}"
        joints += [
            Joint(f"S{index}", "S", ("ground", cylinder), point=tuple(a)),
            Joint(f"P{index}", "P", (cylinder, piston), axis=tuple(leg / length), actuated=True),
        ]
        if spin == "locked" and index == 1:
            joints.append(Joint("R1", "R", (piston, "platform"), point=tuple(b), axis=tuple(normal)))
        else:
            joints.append(Joint(f"U{index}", "U", (piston, "platform"), point=tuple(b),
                                axes=(tuple(normal), tuple(direction))))
    output = None
    if end_effector == "tool":
        output = EndEffector("platform", tuple(point), "tool", tuple(direction))
    elif end_effector == "pose":
        output = EndEffector("platform", tuple(point), "pose")
    elif end_effector == "position":
        output = EndEffector("platform", tuple(point), "position")
    return Mechanism("5-spu", "spatial", joints, end_effector=output)


def cofactors(x, y, z):
    """The coefficients C₁, …, C₆ of the singularity polynomial of a design.

    Cⱼ is the cofactor of the j-th element of the first row of the 6 × 6
    determinant (12), whose other rows are (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1); by
    Laplace expansion (13) they are the coefficients of the B-surface
    C₁z + C₂x + C₃y + C₄xz + C₅yz + C₆ = 0.

    Parameters
    ----------
    x, y : sequence of 5 float
        Base attachments aᵢ = (xᵢ, yᵢ, 0).
    z : sequence of 5 float
        Platform attachments bᵢ = p + zᵢ i.

    Returns
    -------
    ndarray, shape=[6]
        (C₁, …, C₆). All zero for an architecturally singular design; for
        zᵢ = δ xᵢ, x₁ = y₁ = 0: (δ²F, −δ³F, 0, 0, 0, 0) (eq. 27).

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (12), (13), (27).
    """
    rows = np.array([[zi, xi, yi, xi * zi, yi * zi, 1.0] for xi, yi, zi in zip(x, y, z)])
    if rows.shape != (5, 6):
        raise ValueError(f"cofactors: expected five attachments, got {len(rows)}")
    return np.array([(-1) ** column * np.linalg.det(np.delete(rows, column, axis=1)) for column in range(6)])


def singularity_polynomial(*, x1=_X[0], y1=_Y[0], z1=_Z[0], x2=_X[1], y2=_Y[1], z2=_Z[1], x3=_X[2], y3=_Y[2],
                           z3=_Z[2], x4=_X[3], y4=_Y[3], z4=_Z[3], x5=_X[4], y5=_Y[4], z5=_Z[4],
                           p_x=_P[0], p_y=_P[1], p_z=_P[2], u=_I[0], v=_I[1], w=_I[2], **options):
    """The paper's singularity polynomial (17) at a pose, for any design.

    [w (C₂ C₃ C₆) − p_z (C₄ C₅ C₁)] · (pₓ w − p_z u, p_y w − p_z v, w)ᵀ,
    where Cⱼ is the cofactor of the j-th element of the first row of (12),
    whose rows are (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1). (u, v, w) is normalised, as
    in :func:`five_spu`; its options ``spin`` and ``end_effector`` are
    accepted and ignored, so a builder's parameter set can be passed whole.

    Parameters
    ----------
    x1, ..., z5, p_x, p_y, p_z, u, v, w : float
        As in :func:`five_spu`.

    Returns
    -------
    float
        Zero exactly at the parallel (actuator) singularities.

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (12), (13), (17); (2) is lost in the
    text, (17) is its vector form.
    """
    unknown = set(options) - {"spin", "end_effector"}
    if unknown:
        raise TypeError(f"singularity_polynomial: unexpected parameter(s) {sorted(unknown)}")
    c1, c2, c3, c4, c5, c6 = cofactors((x1, x2, x3, x4, x5), (y1, y2, y3, y4, y5), (z1, z2, z3, z4, z5))
    direction = np.array([u, v, w], dtype=float)
    u, v, w = direction / np.linalg.norm(direction)
    intersection = np.array([p_x * w - p_z * u, p_y * w - p_z * v, w])
    return float((w * np.array([c2, c3, c6]) - p_z * np.array([c4, c5, c1])) @ intersection)


def _unit(vector):
    vector = np.asarray(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def _on_second_factor(u, v, w, p_z, delta=_DELTA):
    """pₓ on the second factor of (33), δ w pₓ − (δ u − 1) p_z = 0, for a direction and height."""
    u, v, w = _unit((u, v, w))
    return float((delta * u - 1.0) * p_z / (delta * w))


ENTRIES = (
    Entry("5-spu", five_spu,
          "Borràs, Thomas & Torras (2011) Figs. 1, 2, Section II, eqs. (17), (26), "
          "(33)-(35)",
          {
              "regular": {},
              "regular_locked": {"spin": "locked"},
              "eq33_w_zero": {"u": 0.8, "v": 0.6, "w": 0.0},
              "eq33_second_factor": {"p_x": _on_second_factor(*_I, _P[2])},
              "eq35_vertical_tool": {"u": 0.0, "v": 0.0, "w": 1.0, "p_x": -_P[2] / _DELTA},
              "sec3c_line_in_base": {"u": 0.8, "v": 0.6, "w": 0.0, "p_z": 0.0},
              "eq33_w_zero_locked": {"u": 0.8, "v": 0.6, "w": 0.0, "spin": "locked"},
              "eq33_second_factor_locked": {"p_x": _on_second_factor(*_I, _P[2]), "spin": "locked"},
          }),
)
