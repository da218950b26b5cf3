"""The pencil of B-lines of a line-plane 5-SPU, its vertex B, the line B∞, the line Λ⁺ and the family.

From the cofactors C₁ … C₆ of the design
(:func:`classify.line_plane_design.cofactors`; Borràs, Thomas & Torras 2011):

* the pencil of B-lines B_z = {(C₂ + zC₄)x + (C₃ + zC₅)y + C₆ + zC₁ = 0}
  (14), its vertex B (16), the line B∞ (15) and the line Λ⁺ (23);
* the family (Section IV): *quartic* (B finite), *cubic* (B at infinity,
  B∞ finite), *quadratic* (B and B∞ at infinity) or *architecturally
  singular* (all Cⱼ = 0).

Scale-aware decisions, made on the normalised design
(:func:`classify.line_plane_design.normalised`: centred, lengths over L), so
that every decision and margin is unchanged by a rotation or translation of
the base frame, a shift of the origin of Λ and a scaling of all lengths:

* architecturally singular:
  :func:`classify.line_plane_design.architecture_margin` ≤ rtol;
* B at infinity: ``|h₃|``/‖h‖ ≤ rtol, h = (C₂, C₃, C₆) × (C₄, C₅, C₁) the
  homogeneous B (16) — B lies farther than L/rtol from the centroid;
* B∞ at infinity: ‖(C₄, C₅)‖/‖(C₄, C₅, C₁)‖ ≤ rtol — B∞ lies farther than
  L/rtol from the centroid.

Each value is reported as a margin (:class:`Family`), so a user sees how
close a call was. The default ``rtol`` is
:data:`classify.line_plane_design.FAMILY_RTOL`.

References
----------
Borràs, Thomas & Torras 2011, eqs. (14)-(16), (21)-(25), Sections III-IV.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .line_plane_design import (
    FAMILY_RTOL, RearrangementError, architecture_margin, cofactors, normalised, normalised_cofactors)

__all__ = ["FAMILIES", "Family", "family", "b_point", "b_infinity", "b_line", "oriented_b_line", "b_line_direction",
           "lambda_plus"]

#: the families of Section IV, and the degenerate case of Section III-A
FAMILIES = ("quartic", "cubic", "quadratic", "architecturally singular")


@dataclass(frozen=True)
class Family:
    """The family of a design and the margins of its decisions.

    Attributes
    ----------
    name : str
        One of :data:`FAMILIES`.
    architecture_margin : float
        :func:`~classify.line_plane_design.architecture_margin` (architecturally singular at ≤ rtol).
    b_margin : float
        ``|h₃|``/‖h‖ of the normalised homogeneous B (B at infinity at ≤ rtol).
    b_infinity_margin : float
        ‖(C₄, C₅)‖/‖(C₄, C₅, C₁)‖, normalised (B∞ at infinity at ≤ rtol).
    rtol : float
    """

    name: str
    architecture_margin: float
    b_margin: float
    b_infinity_margin: float
    rtol: float

    @property
    def degree(self):
        """Degree of the forward-kinematics polynomial (10): 4, 3, 2 (None when architecturally singular)."""
        return {"quartic": 4, "cubic": 3, "quadratic": 2}.get(self.name)

    @property
    def margin(self):
        """The margin of the deciding cut: the value :func:`family` compared with rtol last.

        The architecture margin for an architecturally singular design, the
        B∞ margin for a quadratic one, the B margin for a cubic (B∞ finite, B
        at infinity) or quartic one.
        """
        if self.name == "architecturally singular":
            return self.architecture_margin
        if self.name == "quadratic":
            return self.b_infinity_margin
        return self.b_margin

    def to_dict(self):
        return {"name": self.name, "degree": self.degree, "rtol": self.rtol,
                "margins": {"architecture": self.architecture_margin, "B": self.b_margin,
                            "B_inf": self.b_infinity_margin}}


def _homogeneous_b(values):
    """h = (C₂, C₃, C₆) × (C₄, C₅, C₁): B (16) in homogeneous coordinates (x, y, 1)·h₃."""
    c1, c2, c3, c4, c5, c6 = values
    return np.cross([c2, c3, c6], [c4, c5, c1])


def family(design, rtol=FAMILY_RTOL):
    """The family of a design (Section IV-B, C) with its margins.

    Parameters
    ----------
    design : LinePlaneDesign
    rtol : float
        Relative cut of the three decisions (see the module notes).

    Returns
    -------
    Family
        ``"architecturally singular"`` if
        :func:`~classify.line_plane_design.architecture_margin` ≤ rtol; else
        ``"quadratic"`` if B∞ is at infinity (C₄ = C₅ = 0); else ``"cubic"`` if
        B is at infinity (C₂C₅ − C₃C₄ = 0); else ``"quartic"``.

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (15), (16), (24), (25); Section IV-C
    (the leading coefficients n₄, n₃ of (10) vanish in the cubic and
    quadratic cases).
    """
    architecture = architecture_margin(design)
    values = normalised_cofactors(design)
    h = _homogeneous_b(values)
    norm_h = np.linalg.norm(h)
    b_margin = float(abs(h[2]) / norm_h) if norm_h > 0 else 0.0
    line = np.array([values[3], values[4], values[0]])
    norm_line = np.linalg.norm(line)
    b_inf_margin = float(np.linalg.norm(line[:2]) / norm_line) if norm_line > 0 else 0.0
    if architecture <= rtol:
        name = "architecturally singular"
    elif b_inf_margin <= rtol:
        name = "quadratic"
    elif b_margin <= rtol:
        name = "cubic"
    else:
        name = "quartic"
    return Family(name, architecture, b_margin, b_inf_margin, rtol)


def _frame(design):
    """The normalised frame: (centre (x̄, ȳ, z̄), L, the cofactors C′ of :func:`~.normalised` (design)).

    Every point, line and distance of the pencil is computed from C′ in the
    normalised frame (x′ = (x − x̄)/L, y′ = (y − ȳ)/L, z′ = (z − z̄)/L), where the
    cofactors do not cancel, and mapped back: the raw B-surface (13) is
    f(x, y, z) = L⁷ f′(x′, y′, z′) (the rows of (12) change by a triangular
    matrix of determinant L⁷), so the raw cofactors are never needed and the
    results move with the base frame and Λ's origin to rounding.
    """
    return design.centre, design.characteristic_length, cofactors(normalised(design))


def _unframe_line(line, centre, length):
    """A line (a′, b′, c′) of the normalised frame in the design's frame: (a′, b′, Lc′ − a′x̄ − b′ȳ), shape=[..., 3]."""
    line = np.asarray(line, dtype=float)
    return np.concatenate([line[..., :2], (length * line[..., 2] - line[..., 0] * centre[0]
                                            - line[..., 1] * centre[1])[..., None]], axis=-1)


def _orientation(line, base):
    """+1 or −1 per line (a′, b′, c′), shape=[..., 3], of the normalised frame: the side of the base centroid.

    The centroid is the origin there, so the sign of c′; when it lies on the
    line (``|c′|`` ≤ 64ε ‖(a′, b′)‖), the side of the base attachment farthest
    from it (`base`, shape=[5, 2], normalised), which no numbering changes.
    """
    line = np.asarray(line, dtype=float)
    normal = np.linalg.norm(line[..., :2], axis=-1)
    values = np.einsum("...k,nk->...n", line[..., :2], base) + line[..., 2:3]
    farthest = np.take_along_axis(values, np.argmax(np.abs(values), axis=-1)[..., None], axis=-1)[..., 0]
    on = np.abs(line[..., 2]) <= 64 * np.finfo(float).eps * normal
    return np.where(np.where(on, farthest, line[..., 2]) < 0, -1.0, 1.0)


def b_point(design, rtol=FAMILY_RTOL):
    """B (16), the vertex of the pencil of B-lines, shape=[2]; None when at infinity (or singular design).

    B = ((C₃C₁ − C₆C₅), −(C₂C₁ − C₄C₆)) / (C₂C₅ − C₄C₃), evaluated on the
    cofactors of the normalised design and mapped back (x̄, ȳ) + L B′, so that it
    moves with the base frame and Λ's origin (the raw cofactors cancel far from
    the origin).
    """
    if family(design, rtol).name != "quartic":
        return None
    centre, length, (c1, c2, c3, c4, c5, c6) = _frame(design)
    denominator = c2 * c5 - c4 * c3
    point = np.array([(c3 * c1 - c6 * c5) / denominator, -(c2 * c1 - c4 * c6) / denominator])
    return centre[:2] + length * point


def b_infinity(design, rtol=FAMILY_RTOL):
    """B∞ (15): (a, b, c) with a² + b² = 1 of the line ax + by + c = 0 ∝ C₄x + C₅y + C₁; None at infinity.

    The sign of (a, b, c) is fixed by the design, not by the sign of the
    cofactors (hence not by the leg numbering): the normal (a, b) points to
    the side of B∞ that holds the centroid ā of the base attachments (when ā
    lies on B∞, the side of the base attachment farthest from it). Computed in
    the normalised frame and mapped back.
    """
    if family(design, rtol).name in ("quadratic", "architecturally singular"):
        return None
    centre, length, (c1, c2, c3, c4, c5, c6) = _frame(design)
    line = np.array([c4, c5, c1]) / np.hypot(c4, c5)
    line = _orientation(line, normalised(design).base) * line
    return _unframe_line(line, centre, length)


def b_line(design, z):
    """The B-line B_z (14): coefficients (C₂ + zC₄, C₃ + zC₅, C₆ + zC₁) of ax + by + c = 0, shape=[..., 3].

    Evaluated in the normalised frame and mapped back (the identity
    f = L⁷ f′ of the B-surface gives these coefficients as L⁶ times the mapped
    normalised ones), so that the line moves with the base frame and Λ's
    origin; the sign is the cofactors', which a renumbering of the legs flips
    (:func:`oriented_b_line` has a sign of its own).

    Parameters
    ----------
    design : LinePlaneDesign
    z : array_like, shape=[...]
        Platform coordinates; ``numpy.inf`` gives B∞ (C₄, C₅, C₁).
    """
    centre, length, _ = _frame(design)
    z = np.asarray(z, dtype=float)
    lines = _normalised_b_line(design, z)
    scale = np.where(np.isinf(z), length ** 5, length ** 6)[..., None]
    return scale * _unframe_line(lines, centre, length)


def _normalised_b_line(design, z):
    """B_z′ of the normalised design, z′ = (z − z̄)/L (B∞′ at z = ±∞), shape=[..., 3]."""
    centre, length, (c1, c2, c3, c4, c5, c6) = _frame(design)
    z = np.asarray(z, dtype=float)
    infinite = np.isinf(z)
    finite_z = (np.where(infinite, centre[2], z) - centre[2]) / length
    lines = np.stack([c2 + finite_z * c4, c3 + finite_z * c5, c6 + finite_z * c1], axis=-1)
    return np.where(infinite[..., None], np.array([c4, c5, c1]), lines)


def oriented_b_line(design, z, rtol=FAMILY_RTOL):
    """The B-line B_z as (a, b, c) with a² + b² = 1, signed as :func:`b_infinity`, shape=[..., 3].

    The normal (a, b) points to the side of B_z that holds the centroid ā of
    the base attachments (when ā lies on B_z, the side of the base attachment
    farthest from it), so that the coefficients do not change with the leg
    numbering or the sign of i, and move with the base frame. NaN where B_z is
    at infinity, ‖(a′, b′)‖ ≤ rtol ‖(a′, b′, c′)‖ in the normalised frame.

    Parameters
    ----------
    design : LinePlaneDesign
    z : array_like, shape=[...]
        Platform coordinates.
    rtol : float
    """
    centre, length, _ = _frame(design)
    lines = _oriented_normalised_b_line(design, z, rtol)
    return _unframe_line(lines, centre, length)


def _oriented_normalised_b_line(design, z, rtol=FAMILY_RTOL):
    """:func:`oriented_b_line` in the normalised frame (unit normal, signed), NaN at infinity, shape=[..., 3]."""
    lines = _normalised_b_line(design, z)
    normal = np.hypot(lines[..., 0], lines[..., 1])
    finite = normal > rtol * np.linalg.norm(lines, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = lines / np.where(finite, normal, 1.0)[..., None]
    unit = _orientation(unit, normalised(design).base)[..., None] * unit
    return np.where(finite[..., None], unit, np.nan)


def b_line_direction(design, index):
    """Unit direction of the B-line through base attachment `index` (0-based), shape=[2].

    The line B_{zᵢ} has normal (C₂ + zᵢC₄, C₃ + zᵢC₅) (normalised frame: the
    same direction); its direction is that normal turned by +90°, signed so
    that its x component is positive (or, for a line parallel to the y axis,
    its y component).
    """
    line = _normalised_b_line(design, design.platform[index])
    direction = np.array([-line[1], line[0]])
    norm = np.linalg.norm(direction)
    if not norm > 0:
        raise RearrangementError(f"leg {index + 1}: its B-line is undefined (the design is architecturally "
                                 f"singular)")
    direction /= norm
    scale = max(abs(direction[0]), abs(direction[1]))
    if direction[0] < -1e-12 * scale or (abs(direction[0]) <= 1e-12 * scale and direction[1] < 0):
        direction = -direction
    return direction


def lambda_plus(design, rtol=FAMILY_RTOL):
    """Λ⁺ (23): the copy of Λ in Π, parallel to B∞, on which each attachment lies on its B-line (Fig. 8).

    Returns
    -------
    line : ndarray, shape=[3]
        (a, b, c) with a² + b² = 1 of ax + by + c = 0, signed as
        :func:`b_infinity`: c = c∞ − ``|C₂C₅ − C₃C₄|``/(C₄² + C₅²), with
        (a, b, c∞) the line B∞ — the copy on the side of B∞ of the centroid ā
        of the base attachments (see Notes).
    points : ndarray, shape=[5, 2], or None
        b⁺ᵢ = q₀ + zᵢ d, q₀ = Λ⁺ ∩ B₀, d the unit direction of Λ⁺ along which
        each b⁺ᵢ lies on its B-line B_{zᵢ}: the platform attachments copied
        onto Λ⁺, spaced as on Λ. None when B is at infinity (cubic designs:
        Λ⁺ is then B∞ itself, which meets no finite B-line).
    None (instead of the pair) when B∞ is at infinity (quadratic or
    architecturally singular designs).

    Notes
    -----
    Two lines have the property of Fig. 8: with β the signed distance to B∞
    and κ = (C₂C₅ − C₃C₄)/(C₄² + C₅²), the lines β = κ and β = −κ, mirror
    images in B∞ (and in B), carrying the copies in opposite directions. The
    half-turn about B maps every B-line onto itself, so it maps the B-surface
    (13), hence the singularity locus, onto itself, and swaps the two copies:
    nothing in the locus tells them apart. The printed (23) picks one by the
    sign of the cofactors, which the order of the rows of (12) fixes: an odd
    renumbering of the legs, or a flip of i, picks the other. The paper's
    formula is therefore ambiguous, and this function takes, by convention,
    the copy on the side of B∞ where ā lies, β = sign(β(ā))``|κ|``: it does not
    depend on the leg numbering, the sign of i, the base frame or the unit.
    Its mirror image in B∞ is the other copy; when ā lies on B∞ the two are
    equally near it and the choice follows the side of the base attachment
    farthest from B∞. Computed in the normalised frame and mapped back, so
    that it moves with the base frame and Λ's origin.

    References
    ----------
    Borràs, Thomas & Torras 2011 eq. (23), Fig. 8.
    """
    if b_infinity(design, rtol) is None:
        return None
    centre, length, (c1, c2, c3, c4, c5, c6) = _frame(design)
    norm = np.hypot(c4, c5)
    primed = np.array([c4, c5, c1]) / norm
    primed = _orientation(primed, normalised(design).base) * primed - np.array([0.0, 0.0, abs(c2 * c5 - c3 * c4)
                                                                                 / norm ** 2])
    line = _unframe_line(primed, centre, length)
    if b_point(design, rtol) is None:
        return line, None
    origin = np.linalg.solve(np.array([primed[:2], [c2, c3]]), -np.array([primed[2], c6]))
    direction = np.array([primed[1], -primed[0]])
    # q₀ + z d lies on B_z for every z iff (C₂, C₃)·d + (C₄, C₅)·q₀ + C₁ = 0: true for d or for −d
    along, offset = np.array([c2, c3]) @ direction, np.array([c4, c5]) @ origin + c1
    if abs(offset - along) < abs(offset + along):
        direction = -direction
    # b⁺ᵢ = (x̄, ȳ) + L(q₀′ + zᵢ′ d), zᵢ′ = (zᵢ − z̄)/L, in the design's frame
    return line, centre[:2] + length * origin + (design.platform - centre[2])[:, None] * direction
