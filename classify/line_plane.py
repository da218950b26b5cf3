"""Line-plane 5-SPU platforms: cofactors, B-point, families, singularity polynomial, rearrangements.

A 5-SPU robot with planar base and linear platform (Borràs, Thomas & Torras
2011, Section II) has its base attachments aᵢ = (xᵢ, yᵢ, 0) in the plane Π
(z = 0) and its platform attachments bᵢ = p + zᵢ i on the line Λ, where p is
the point of Λ with coordinate 0 and i = (u, v, w) the unit direction of Λ.
Everything here depends on the design only through the five points
(xᵢ, yᵢ, zᵢ) of the *3-D space of leg attachments* (Section II):

* the cofactors C₁ … C₆ of the first row of the 6 × 6 determinant (12), the
  coefficients of the B-surface C₁z + C₂x + C₃y + C₄xz + C₅yz + C₆ = 0 (13)
  and of the singularity polynomial (17);
* the pencil of B-lines B_z = {(C₂ + zC₄)x + (C₃ + zC₅)y + C₆ + zC₁ = 0}
  (14), its vertex B (16), the line B∞ (15) and the line Λ⁺ (23);
* the family (Section IV): *quartic* (B finite), *cubic* (B at infinity,
  B∞ finite), *quadratic* (B and B∞ at infinity) or *architecturally
  singular* (all Cⱼ = 0);
* the singularity-invariant rearrangements (Section III-B): a base
  attachment moves along its B-line; a platform attachment moves iff its
  base attachment is at B; no move may make the design architecturally
  singular.

Scale-aware decisions. The cofactors have mixed units (C₁, C₂, C₃ ~ length⁶,
C₄, C₅ ~ length⁵, C₆ ~ length⁷), so every zero test is made on the
*normalised* design: base attachments centred on their centroid, platform
coordinates on their mean, all lengths divided by the characteristic length
L = (mean ‖aᵢ − ā‖² + mean (zᵢ − z̄)²)^½. The normalised quantities are
unchanged by a rotation or translation of the base frame, a shift of the
origin of Λ and a scaling of all lengths, and so is every decision and
margin below:

* architecturally singular: all Cⱼ vanish iff the 5 × 6 matrix of rows
  (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1) has rank below 5 (the Cⱼ are its maximal
  minors); the margin is :func:`architecture_margin`, σ₅/σ₁ in the best of
  five frames each centred on one leg, so that it does not fall when one
  attachment lies far from the others (a move along a B-line multiplies the
  Cⱼ by a growing factor, it does not make them vanish);
* B at infinity: ``|h₃|``/‖h‖ ≤ rtol, h = (C₂, C₃, C₆) × (C₄, C₅, C₁) the
  homogeneous B (16) — B lies farther than L/rtol from the centroid;
* B∞ at infinity: ‖(C₄, C₅)‖/‖(C₄, C₅, C₁)‖ ≤ rtol — B∞ lies farther than
  L/rtol from the centroid.

Each value is reported as a margin (:class:`Family`), so a user sees how
close a call was. The default ``rtol`` is :data:`FAMILY_RTOL`.

References
----------
Borràs, Thomas & Torras 2011, eqs. (12)-(17), (21)-(25), Sections III-IV;
equation (2) is lost from the text, its vector forms are (17) and (22).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

__all__ = [
    "FAMILIES", "FAMILY_RTOL", "FILE_RTOL", "DesignError", "RearrangementError", "LinePlaneDesign", "Family",
    "SingularityReading", "line_plane_design", "normalised", "cofactors", "normalised_cofactors",
    "architecture_margin",
    "b_point", "b_infinity", "b_line", "b_line_direction", "lambda_plus", "family", "singularity_polynomial",
    "singularity_margin", "singularity_reading", "leg_jacobian", "jacobian_determinant", "move_base",
    "move_platform", "design_from_mechanism",
]

#: the families of Section IV, and the degenerate case of Section III-A
FAMILIES = ("quartic", "cubic", "quadratic", "architecturally singular")
#: default relative cut of the family decisions (a point farther than L/rtol is at infinity)
FAMILY_RTOL = 1e-8


class DesignError(ValueError):
    """A design that is not a line-plane 5-SPU of the paper; ``field`` is ``"base"`` or ``"platform"``."""

    def __init__(self, message, field="base"):
        super().__init__(message)
        self.field = field


class RearrangementError(ValueError):
    """A leg rearrangement that would change the singularity locus or make the design architecturally singular."""


@dataclass(frozen=True, eq=False)
class LinePlaneDesign:
    """The leg attachments of a line-plane 5-SPU (build with :func:`line_plane_design`).

    Attributes
    ----------
    base : ndarray, shape=[5, 2]
        (xᵢ, yᵢ): aᵢ = (xᵢ, yᵢ, 0) in the base plane Π.
    platform : ndarray, shape=[5]
        zᵢ: bᵢ = p + zᵢ i on the platform line Λ.
    """

    base: np.ndarray
    platform: np.ndarray

    @property
    def attachments(self):
        """The points (xᵢ, yᵢ, zᵢ) of the 3-D space of leg attachments, shape=[5, 3]."""
        return np.column_stack([self.base, self.platform])

    @property
    def centre(self):
        """(x̄, ȳ, z̄): centroid of the base attachments and mean platform coordinate, shape=[3]."""
        return self.attachments.mean(axis=0)

    @property
    def characteristic_length(self):
        """L = (mean ‖aᵢ − ā‖² + mean (zᵢ − z̄)²)^½ (the unit of the normalised design)."""
        centred = self.attachments - self.centre
        return float(np.sqrt(np.mean(np.sum(centred ** 2, axis=1))))

    def to_dict(self):
        """A JSON-ready mapping."""
        return {"base": self.base.tolist(), "platform": self.platform.tolist()}


@dataclass(frozen=True)
class Family:
    """The family of a design and the margins of its decisions.

    Attributes
    ----------
    name : str
        One of :data:`FAMILIES`.
    architecture_margin : float
        :func:`architecture_margin` (architecturally singular at ≤ rtol).
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


@dataclass(frozen=True)
class SingularityReading:
    """The geometric reading of (17) at a pose (Section III-C).

    Attributes
    ----------
    singular : bool
    margin : float
        :func:`singularity_margin`.
    parallel : bool
        w = 0 (Λ parallel to Π): singular iff Λ lies in Π or is parallel to B∞ (20).
    intersection : ndarray, shape=[2], or None
        A (19): where Λ meets Π (None when parallel).
    z : float or None
        μ = −p_z/w: the coordinate along Λ of A, whose B-line B_μ decides.
    distance : float or None
        Signed distance from A to the B-line B_μ (None when parallel, or B_μ at infinity).
    """

    singular: bool
    margin: float
    parallel: bool
    intersection: object = None
    z: object = None
    distance: object = None


# ------------------------------------------------------------------------------------------------ construction

def line_plane_design(base, platform, rtol=FAMILY_RTOL):
    """A validated line-plane design.

    Parameters
    ----------
    base : array_like, shape=[5, 2]
        Base attachments (xᵢ, yᵢ).
    platform : array_like, shape=[5]
        Platform attachments zᵢ.
    rtol : float
        Relative cut of the collinearity and coincidence tests (lengths over L).

    Returns
    -------
    LinePlaneDesign

    Raises
    ------
    DesignError
        Naming ``base`` or ``platform``: not five legs, non-finite numbers, two
        identical legs (coincident base *and* platform attachments), or four
        collinear base attachments (outside the paper's assumption, Section II:
        a four-leg rigid subassembly).
    """
    try:
        base = np.array(base, dtype=float)
    except (TypeError, ValueError):
        raise DesignError("base: expected five pairs of numbers x,y", "base") from None
    try:
        platform = np.array(platform, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DesignError("platform: expected five numbers z", "platform") from None
    if base.ndim != 2 or base.shape[1] != 2:
        raise DesignError(f"base: expected pairs x,y (shape [5, 2]), got shape {list(base.shape)}", "base")
    if base.shape[0] != 5:
        raise DesignError(f"base: a line-plane 5-SPU has five legs, got {base.shape[0]} base attachments", "base")
    if platform.shape[0] != 5:
        raise DesignError(f"platform: a line-plane 5-SPU has five legs, got {platform.shape[0]} platform "
                          f"attachments", "platform")
    if not np.all(np.isfinite(base)):
        raise DesignError("base: the attachments must be finite numbers", "base")
    if not np.all(np.isfinite(platform)):
        raise DesignError("platform: the attachments must be finite numbers", "platform")
    design = LinePlaneDesign(base, platform)
    if not design.characteristic_length > 0:
        raise DesignError("base: all attachments coincide", "base")
    points = design.attachments
    scale = _typical_distance(points)
    for first, second in combinations(range(5), 2):
        if np.linalg.norm(points[first] - points[second]) <= rtol * scale:
            raise DesignError(f"base: legs {first + 1} and {second + 1} coincide (same base and platform "
                              f"attachments)", "base")
    base_scale = _typical_distance(base)
    for four in combinations(range(5), 4):
        spread = _collinearity(base[list(four)])
        if spread <= rtol * base_scale:
            legs = ", ".join(str(index + 1) for index in four)
            raise DesignError(f"base: attachments {legs} are collinear (a four-leg rigid subassembly, outside "
                              f"the line-plane families; Borràs, Thomas & Torras 2011 Section II)", "base")
    return design


def _typical_distance(points):
    """The median distance between two of the points, shape=[n, d] -> float.

    The unit of the coincidence and collinearity cuts: unlike L, one
    attachment far from the others does not change it, so the cuts keep
    their meaning (Section III-B lets a base attachment slide arbitrarily
    far along its B-line).
    """
    gaps = [np.linalg.norm(points[first] - points[second]) for first, second in combinations(range(len(points)), 2)]
    return float(np.median(gaps))


def _collinearity(points):
    """Smallest singular value of the centred points, shape=[n, 2] -> float (0 when collinear)."""
    return float(np.linalg.svd(points - points.mean(axis=0), compute_uv=False)[-1])


def normalised(design):
    """The design centred (base on its centroid, platform on its mean) and divided by L.

    Returns
    -------
    LinePlaneDesign
    """
    centre, length = design.centre, design.characteristic_length
    return LinePlaneDesign((design.base - centre[:2]) / length, (design.platform - centre[2]) / length)


def _rows(design):
    """The 5 × 6 matrix of rows (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1) of (12)."""
    x, y, z = design.base[:, 0], design.base[:, 1], design.platform
    return np.column_stack([z, x, y, x * z, y * z, np.ones(5)])


def cofactors(design):
    """C₁, …, C₆: the cofactors of the first row of the determinant (12).

    Parameters
    ----------
    design : LinePlaneDesign

    Returns
    -------
    ndarray, shape=[6]
        Cⱼ = (−1)^(j+1) det(T with row 1 and column j deleted), the coefficients
        of C₁z + C₂x + C₃y + C₄xz + C₅yz + C₆ = 0 (13). Defined up to a common
        factor by the geometry: a relabelling of the legs changes their sign.
        For zᵢ = δxᵢ, x₁ = y₁ = 0: (δ²F, −δ³F, 0, 0, 0, 0) with F of (28) (eq. 27).

    References
    ----------
    Borràs, Thomas & Torras 2011 eqs. (12), (13), (27).
    """
    rows = _rows(design)
    return np.array([(-1) ** column * np.linalg.det(np.delete(rows, column, axis=1)) for column in range(6)])


def normalised_cofactors(design):
    """The cofactors of :func:`normalised` (design), divided by their norm, shape=[6] (zeros if all vanish)."""
    values = cofactors(normalised(design))
    norm = np.linalg.norm(values)
    return values / norm if norm > 0 else values


def architecture_margin(design):
    """How far the design is from architectural singularity (all Cⱼ = 0, Section III-A), in [0, 1].

    The Cⱼ are the maximal minors of the 5 × 6 matrix R of rows
    (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1) (12): all vanish iff rank R < 5. Whether they
    do is unchanged by a change of the base frame or of Λ's origin (column
    operations on R), by separate scalings of the base and of Λ (column
    scalings) and by scaling a row, so the rank is tested where R is best
    conditioned: for each leg k, the attachments are taken relative to leg
    k's, the base ones over their median distance to aₖ and the platform ones
    over their median distance to zₖ (robust to one far attachment), each row
    is divided by its norm, and σ₅/σ₁ is computed. The margin is the largest
    of the five ratios: 0 when all Cⱼ vanish, and unchanged by the leg
    numbering, a rigid motion of the base frame, a shift of Λ's origin, a flip
    of i and a scaling.

    Parameters
    ----------
    design : LinePlaneDesign

    Returns
    -------
    float

    References
    ----------
    Borràs, Thomas & Torras 2011 eq. (12), Section III-A.
    """
    best = 0.0
    for leg in range(5):
        base = design.base - design.base[leg]
        platform = design.platform - design.platform[leg]
        base_scale = _median_nonzero(np.linalg.norm(base, axis=1))
        platform_scale = _median_nonzero(np.abs(platform))
        if base_scale == 0 or platform_scale == 0:
            return 0.0      # all base attachments, or all platform attachments, coincide: rank R ≤ 4
        rows = _rows(LinePlaneDesign(base / base_scale, platform / platform_scale))
        rows /= np.linalg.norm(rows, axis=1, keepdims=True)
        singular_values = np.linalg.svd(rows, compute_uv=False)
        best = max(best, float(singular_values[-1] / singular_values[0]))
    return best


def _median_nonzero(values):
    """The median of the nonzero values (0 if there are none)."""
    values = values[values > 0]
    return float(np.median(values)) if values.size else 0.0


# ------------------------------------------------------------------------------------------------ the pencil

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
        ``"architecturally singular"`` if :func:`architecture_margin` ≤ rtol; else ``"quadratic"``
        if B∞ is at infinity (C₄ = C₅ = 0); else ``"cubic"`` if B is at
        infinity (C₂C₅ − C₃C₄ = 0); else ``"quartic"``.

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


def b_point(design, rtol=FAMILY_RTOL):
    """B (16), the vertex of the pencil of B-lines, shape=[2]; None when at infinity (or singular design).

    B = ((C₃C₁ − C₆C₅), −(C₂C₁ − C₄C₆)) / (C₂C₅ − C₄C₃).
    """
    if family(design, rtol).name != "quartic":
        return None
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    denominator = c2 * c5 - c4 * c3
    return np.array([(c3 * c1 - c6 * c5) / denominator, -(c2 * c1 - c4 * c6) / denominator])


def b_infinity(design, rtol=FAMILY_RTOL):
    """B∞ (15): (a, b, c) with a² + b² = 1 of the line ax + by + c = 0 ∝ C₄x + C₅y + C₁; None at infinity.

    The sign of (a, b, c) is fixed by the design, not by the sign of the
    cofactors (hence not by the leg numbering): the normal (a, b) points to
    the side of B∞ that holds the centroid ā of the base attachments.
    """
    if family(design, rtol).name in ("quadratic", "architecturally singular"):
        return None
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    line = np.array([c4, c5, c1]) / np.hypot(c4, c5)
    return _centroid_side(design, line) * line


def b_line(design, z):
    """The B-line B_z (14): coefficients (C₂ + zC₄, C₃ + zC₅, C₆ + zC₁) of ax + by + c = 0, shape=[..., 3].

    Parameters
    ----------
    design : LinePlaneDesign
    z : array_like, shape=[...]
        Platform coordinates; ``numpy.inf`` gives B∞ (C₄, C₅, C₁).
    """
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    z = np.asarray(z, dtype=float)
    infinite = np.isinf(z)
    finite_z = np.where(infinite, 0.0, z)
    lines = np.stack([c2 + finite_z * c4, c3 + finite_z * c5, c6 + finite_z * c1], axis=-1)
    return np.where(infinite[..., None], np.array([c4, c5, c1]), lines)


def b_line_direction(design, index):
    """Unit direction of the B-line through base attachment `index` (0-based), shape=[2].

    The line B_{zᵢ} has normal (C₂ + zᵢC₄, C₃ + zᵢC₅); its direction is that
    normal turned by +90°, signed so that its x component is positive (or, for
    a line parallel to the y axis, its y component).
    """
    line = b_line(design, design.platform[index])
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


def _centroid_side(design, line):
    """+1 or −1: the side of the line ax + by + c = 0 that holds the centroid of the base attachments (+1 on it)."""
    return -1.0 if line[:2] @ design.centre[:2] + line[2] < 0 else 1.0


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
    equally near it and the choice follows the sign of the cofactors.

    References
    ----------
    Borràs, Thomas & Torras 2011 eq. (23), Fig. 8.
    """
    infinity = b_infinity(design, rtol)
    if infinity is None:
        return None
    c1, c2, c3, c4, c5, c6 = cofactors(design)
    norm = np.hypot(c4, c5)
    line = infinity - np.array([0.0, 0.0, abs(c2 * c5 - c3 * c4) / norm ** 2])
    if b_point(design, rtol) is None:
        return line, None
    origin = np.linalg.solve(np.array([line[:2], [c2, c3]]), -np.array([line[2], c6]))
    direction = np.array([line[1], -line[0]])
    # q₀ + z d lies on B_z for every z iff (C₂, C₃)·d + (C₄, C₅)·q₀ + C₁ = 0: true for d or for −d
    along, offset = np.array([c2, c3]) @ direction, np.array([c4, c5]) @ origin + c1
    if abs(offset - along) < abs(offset + along):
        direction = -direction
    return line, origin + design.platform[:, None] * direction


# ------------------------------------------------------------------------------------------------ singularities

def _pose(position, direction):
    position = np.asarray(position, dtype=float)
    direction = np.asarray(direction, dtype=float)
    direction = direction / np.linalg.norm(direction, axis=-1, keepdims=True)
    return position, direction


def _factors(values, position, direction):
    """The two 3-vectors of (17): ℓ = w(C₂, C₃, C₆) − p_z(C₄, C₅, C₁) and a = (pₓw − p_zu, p_yw − p_zv, w)."""
    c1, c2, c3, c4, c5, c6 = values
    p_x, p_y, p_z = np.moveaxis(position, -1, 0)
    u, v, w = np.moveaxis(direction, -1, 0)
    line = w[..., None] * np.array([c2, c3, c6]) - p_z[..., None] * np.array([c4, c5, c1])
    point = np.stack([p_x * w - p_z * u, p_y * w - p_z * v, w], axis=-1)
    return line, point


def singularity_polynomial(design, position, direction):
    """The singularity polynomial (17) at poses (p, i).

    [w (C₂ C₃ C₆) − p_z (C₄ C₅ C₁)] · (pₓw − p_zu, p_yw − p_zv, w)ᵀ

    Parameters
    ----------
    design : LinePlaneDesign
    position : array_like, shape=[..., 3]
        p, the point of Λ with coordinate z = 0.
    direction : array_like, shape=[..., 3]
        i (normalised here).

    Returns
    -------
    ndarray, shape=[...]
        Zero exactly at the parallel singularities (in the units of the raw cofactors).

    References
    ----------
    Borràs, Thomas & Torras 2011 eq. (17), the vector form of the lost (2).
    """
    position, direction = _pose(position, direction)
    line, point = _factors(cofactors(design), position, direction)
    return np.sum(line * point, axis=-1)


def _normalised_pose(design, position, direction):
    """(p, i) in the frame of :func:`normalised`: p' = (p + z̄ i − (x̄, ȳ, 0)) / L."""
    centre, length = design.centre, design.characteristic_length
    return (position + centre[2] * direction - np.array([centre[0], centre[1], 0.0])) / length, direction


def singularity_margin(design, position, direction):
    """``|ℓ·a|`` / (‖ℓ‖‖a‖) of (17), in the normalised design: 0 on the singularity locus, shape=[...].

    ℓ is the B-line B_μ (μ = −p_z/w) and a the point A (19) where Λ meets Π,
    both homogeneous (scaled by w): the margin is the cosine of the angle
    between them, dimensionless and unchanged by a rigid motion of the base
    frame, a shift of the origin of Λ and a scaling of all lengths. It is 0
    when ℓ or a vanishes (Λ in Π).
    """
    position, direction = _pose(position, direction)
    position, direction = _normalised_pose(design, position, direction)
    line, point = _factors(cofactors(normalised(design)), position, direction)
    scale = np.linalg.norm(line, axis=-1) * np.linalg.norm(point, axis=-1)
    value = np.abs(np.sum(line * point, axis=-1))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(scale > 0, value / np.where(scale > 0, scale, 1.0), 0.0)


def singularity_reading(design, position, direction, rtol=1e-9):
    """The geometric reading of (17) at one pose (Section III-C).

    Singular iff the point A (19) where Λ meets Π lies on the B-line of its
    own coordinate μ = −p_z/w along Λ (18); when Λ is parallel to Π (w = 0),
    iff Λ lies in Π or is parallel to B∞ (20).

    Parameters
    ----------
    design : LinePlaneDesign
    position, direction : array_like, shape=[3]
    rtol : float
        Cut on :func:`singularity_margin`; also the cut ``|w|`` ≤ rtol of "parallel".

    Returns
    -------
    SingularityReading
    """
    position, direction = _pose(position, direction)
    margin = float(singularity_margin(design, position, direction))
    singular = margin <= rtol
    p_x, p_y, p_z = position
    u, v, w = direction
    if abs(w) <= rtol:
        return SingularityReading(singular, margin, True)
    mu = -p_z / w
    intersection = np.array([p_x + mu * u, p_y + mu * v])
    line = b_line(design, mu)
    norm = np.linalg.norm(line[:2])
    distance = float((line[:2] @ intersection + line[2]) / norm) if norm > 0 else None
    return SingularityReading(singular, margin, False, intersection, float(mu), distance)


def leg_jacobian(design, position, direction):
    """The 6 × 6 matrix of the legs' line coordinates and the spin about Λ, shape=[..., 6, 6].

    Row k ≤ 5: (dₖ, zₖ i × dₖ), dₖ = bₖ − aₖ, so that lₖ l̇ₖ = dₖ·ṗ + zₖ (i × dₖ)·ω
    for a platform velocity ṗ and an angular velocity ω of Λ (i̇ = ω × i);
    row 6: (0, i), picking out the spin ω·i that no leg sees. Its determinant
    vanishes iff the five leg rows are dependent on the 5-dimensional motions
    of Λ: an independent test of the singularity locus, computed without the
    cofactors.
    """
    position, direction = _pose(position, direction)
    base = np.column_stack([design.base, np.zeros(5)])
    attachments = position[..., None, :] + design.platform[:, None] * direction[..., None, :]
    legs = attachments - base
    moments = design.platform[:, None] * np.cross(direction[..., None, :], legs)
    rows = np.concatenate([legs, moments], axis=-1)
    spin = np.concatenate([np.zeros_like(direction), direction], axis=-1)[..., None, :]
    return np.concatenate([rows, spin], axis=-2)


def jacobian_determinant(design, position, direction, normalise=True):
    """det :func:`leg_jacobian`, shape=[...]; with `normalise`, over the product of its row norms (``|·|`` ≤ 1).

    The normalised value (Hadamard's ratio) is dimensionless and 0 exactly at
    the singularities.
    """
    matrix = leg_jacobian(design, position, direction)
    value = np.linalg.det(matrix)
    if normalise:
        value = value / np.prod(np.linalg.norm(matrix, axis=-1), axis=-1)
    return value


# ------------------------------------------------------------------------------------------------ rearrangements

def _refuse_singular(moved, what, rtol):
    """Raise RearrangementError if `moved` is not a valid, non-architecturally-singular design."""
    try:
        checked = line_plane_design(moved.base, moved.platform)
    except DesignError as error:
        raise RearrangementError(f"{what}: refused: {error}") from None
    result = family(checked, rtol)
    if result.name == "architecturally singular":
        reason = _architecture_reason(checked)
        raise RearrangementError(f"{what}: refused: the design would be architecturally singular (all Cⱼ vanish, "
                                 f"σ₅/σ₁ = {result.architecture_margin:.2e} ≤ {rtol:g}){reason}")
    return checked


def _architecture_reason(design):
    """A known cause of architectural singularity (Section III-B): three attachments on one B-line."""
    for three in combinations(range(5), 3):
        same = np.ptp(design.platform[list(three)]) <= 1e-12 * design.characteristic_length
        if same and _collinearity(design.base[list(three)]) <= 1e-9 * design.characteristic_length:
            legs = ", ".join(str(index + 1) for index in three)
            return f": legs {legs} would share one B-line (same platform attachment, collinear base attachments)"
    return ""


def move_base(design, index, distance, rtol=FAMILY_RTOL):
    """Move base attachment `index` along its B-line (Section III-B, rule 1): the locus is unchanged.

    Parameters
    ----------
    design : LinePlaneDesign
    index : int
        The leg, 0-based.
    distance : float
        Signed distance along the B-line, in the direction of :func:`b_line_direction`.
    rtol : float

    Returns
    -------
    LinePlaneDesign
        The new design; its cofactors are a nonzero multiple of the old ones.

    Raises
    ------
    RearrangementError
        If the new design is architecturally singular (with the reason) or
        not a valid design (coincident legs, four collinear base attachments).
    """
    if family(design, rtol).name == "architecturally singular":
        raise RearrangementError(f"leg {index + 1}: the design is architecturally singular: it has no B-lines")
    direction = b_line_direction(design, index)
    base = design.base.copy()
    base[index] = base[index] + float(distance) * direction
    return _refuse_singular(LinePlaneDesign(base, design.platform.copy()),
                            f"leg {index + 1} moved by {distance:g} along its B-line", rtol)


def move_platform(design, index, z, rtol=FAMILY_RTOL, atol=1e-9):
    """Move platform attachment `index` to zᵢ = `z` (Section III-B, rule 2): allowed iff aᵢ is at B.

    Parameters
    ----------
    design : LinePlaneDesign
    index : int
        The leg, 0-based.
    z : float
        The new platform coordinate.
    rtol : float
        Family cut.
    atol : float
        aᵢ is at B when ‖aᵢ − B‖ ≤ atol·L.

    Returns
    -------
    LinePlaneDesign

    Raises
    ------
    RearrangementError
        If aᵢ is not at B (the locus would change; the message gives the
        distance), if B is at infinity (cubic, quadratic designs: no base
        attachment is at B), or if the new design is architecturally singular.
    """
    what = f"leg {index + 1}: platform attachment moved to z = {z:g}"
    point = b_point(design, rtol)
    if point is None:
        raise RearrangementError(f"{what}: refused: B is at infinity ({family(design, rtol).name} design), so no "
                                 f"base attachment is at B and every platform move changes the singularity locus")
    gap = float(np.linalg.norm(design.base[index] - point))
    if gap > atol * design.characteristic_length:
        raise RearrangementError(f"{what}: refused: base attachment {index + 1} is not at B (distance {gap:.3g}; "
                                 f"a platform attachment may move only when its base attachment is at B)")
    platform = design.platform.copy()
    platform[index] = float(z)
    return _refuse_singular(LinePlaneDesign(design.base.copy(), platform), what, rtol)


# ------------------------------------------------------------------------------------------------ from a mechanism

#: relative cut of the plane and line tests of :func:`design_from_mechanism`: a mechanism file written by hand
#: carries about six significant digits, i.e. errors up to 5e-7 of its largest coordinate; 1e-5 leaves a margin
FILE_RTOL = 1e-5


def design_from_mechanism(mechanism, rtol=FILE_RTOL):
    """The line-plane design and home pose of a 5-SPU joint graph (as the catalogue's ``5-spu`` builds it).

    Each leg is a chain ground –S– cylinder –P– piston –U (or R)– platform,
    the five legs ending on one platform link. The S centres are the base
    attachments and must be coplanar (Π); the U (R) centres at home are the
    platform attachments and must be collinear (Λ). The design is read in
    the frame of Π: the file's frame when Π is its plane z = 0, else the
    file's frame moved by the least rotation that turns the normal of Π to
    +z, and shifted along that normal, so that Π is z = 0. The origin p of Λ
    is the end-effector point when it lies on Λ, else the platform
    attachment of the first leg; i is the second axis of the first U joint
    (in the order of the legs) when it lies along Λ, else the direction
    from the first leg's platform attachment towards the last one's.

    Parameters
    ----------
    mechanism : Mechanism
    rtol : float
        Relative cut of the plane and line tests: a distance from the fitted
        plane or line at most rtol × the largest coordinate (or the spread of
        the attachments, if larger) is rounding (:data:`FILE_RTOL`).

    Returns
    -------
    design : LinePlaneDesign
    position : ndarray, shape=[3]
        p at home, in the frame of Π.
    direction : ndarray, shape=[3]
        i at home, in the frame of Π.

    Raises
    ------
    DesignError
        Naming the joint or the field, when the graph is not a line-plane 5-SPU.
    """
    if mechanism.space != "spatial":
        raise DesignError(f"mechanism: a line-plane 5-SPU is spatial, got a {mechanism.space} mechanism", "mechanism")
    joints = mechanism.joints
    ground = mechanism.ground

    def joints_on(link, kind, exclude):
        return [joint for joint in joints if joint is not exclude and link in joint.links and joint.type in kind]

    base, attachments, platforms, axes = [], [], set(), []
    for spherical in (joint for joint in joints if joint.type == "S" and ground in joint.links):
        cylinder = spherical.links[1] if spherical.links[0] == ground else spherical.links[0]
        sliders = joints_on(cylinder, ("P",), spherical)
        if len(sliders) != 1:
            raise DesignError(f"mechanism: joint {spherical.name}: expected one prismatic joint on link "
                              f"{cylinder!r} (a leg S-P-U)", "mechanism")
        slider = sliders[0]
        piston = slider.links[1] if slider.links[0] == cylinder else slider.links[0]
        ends = joints_on(piston, ("U", "R"), slider)
        if len(ends) != 1:
            raise DesignError(f"mechanism: joint {slider.name}: expected one U (or R) joint on link {piston!r} "
                              f"(a leg S-P-U)", "mechanism")
        end = ends[0]
        platforms.add(end.links[1] if end.links[0] == piston else end.links[0])
        base.append(np.array(spherical.point, dtype=float))
        attachments.append(np.array(end.point, dtype=float))
        axes.append(np.array(end.axes[1], dtype=float) if end.type == "U" else None)
    if len(base) != 5:
        raise DesignError(f"mechanism: a line-plane 5-SPU has five S-P-U legs from the ground, found {len(base)}",
                          "mechanism")
    if len(platforms) != 1:
        raise DesignError(f"mechanism: the five legs must end on one platform link, found {sorted(platforms)}",
                          "mechanism")
    base, attachments = np.array(base), np.array(attachments)
    scale = max(float(np.max(np.abs(np.concatenate([base, attachments])))),
                float(np.ptp(base, axis=0).max()), float(np.ptp(attachments, axis=0).max()), 1e-300)
    frame = _base_frame(base, rtol * scale)
    base, attachments = frame(base), frame(attachments)
    centre = attachments.mean(axis=0)
    _, singular_values, rows = np.linalg.svd(attachments - centre)
    direction = rows[0]
    if singular_values[1] > rtol * scale:
        raise DesignError(f"mechanism: the platform attachments (U joints) must be collinear (the line Λ): they lie "
                          f"{singular_values[1]:.3g} from the best line, more than {rtol:g} × {scale:.3g}",
                          "mechanism")
    along = [frame(axis, vector=True) for axis in axes if axis is not None]
    # along Λ: sine of the angle ≤ 1e-3 (a rounded file is off by ~1e-6; an axis not along Λ is far off)
    if along and np.linalg.norm(np.cross(along[0], direction)) <= 1e-3 * np.linalg.norm(along[0]):
        direction = along[0] / np.linalg.norm(along[0])
    else:
        steps = (attachments - centre) @ direction
        direction = direction if steps[-1] >= steps[0] else -direction
    origin = attachments[0]
    effector = mechanism.end_effector
    if effector is not None and effector.point is not None and effector.link in platforms:
        point = frame(np.array(effector.point, dtype=float))
        if np.linalg.norm(np.cross(point - centre, direction)) <= rtol * scale:
            origin = point
    platform = (attachments - origin) @ direction
    design = line_plane_design(base[:, :2], platform)
    return design, origin, direction


def _base_frame(base, tolerance):
    """The change of frame that puts the plane of the base attachments at z = 0: points -> points, shape=[..., 3].

    The identity when the attachments already lie within `tolerance` of
    z = 0; else the least rotation turning the fitted normal n (n_z ≥ 0) to
    +z, after a shift along n. With ``vector=True`` the rotation alone.
    """
    if np.max(np.abs(base[:, 2])) <= tolerance:
        return lambda points, vector=False: np.asarray(points, dtype=float)
    centre = base.mean(axis=0)
    _, singular_values, rows = np.linalg.svd(base - centre)
    if singular_values[2] > tolerance:
        raise DesignError(f"mechanism: the S joints (base attachments) must be coplanar (the base plane Π): they lie "
                          f"{singular_values[2]:.3g} from the best plane, more than the cut {tolerance:.3g}",
                          "mechanism")
    normal = rows[2] if rows[2][2] >= 0 else -rows[2]
    axis = np.cross(normal, [0.0, 0.0, 1.0])
    skew = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    rotation = np.eye(3) + skew + skew @ skew / (1.0 + normal[2])      # Rodrigues, n -> +z
    shift = (normal @ centre) * normal

    def frame(points, vector=False):
        points = np.asarray(points, dtype=float)
        return points @ rotation.T if vector else (points - shift) @ rotation.T
    return frame
