"""The design of a line-plane 5-SPU: its leg attachments, their checks, the normalised design and the cofactors.

A 5-SPU robot with planar base and linear platform (Borràs, Thomas & Torras
2011, Section II) has its base attachments aᵢ = (xᵢ, yᵢ, 0) in the plane Π
(z = 0) and its platform attachments bᵢ = p + zᵢ i on the line Λ, where p is
the point of Λ with coordinate 0 and i = (u, v, w) the unit direction of Λ.
Everything depends on the design only through the five points
(xᵢ, yᵢ, zᵢ) of the *3-D space of leg attachments* (Section II), and first
through the cofactors C₁ … C₆ of the first row of the 6 × 6 determinant
(12), the coefficients of the B-surface C₁z + C₂x + C₃y + C₄xz + C₅yz + C₆ = 0
(13) and of the singularity polynomial (17).

Scale-aware decisions. The cofactors have mixed units (C₁, C₂, C₃ ~ length⁶,
C₄, C₅ ~ length⁵, C₆ ~ length⁷), so every zero test is made on the
*normalised* design: base attachments centred on their centroid, platform
coordinates on their mean, all lengths divided by the characteristic length
L = (mean ‖aᵢ − ā‖² + mean (zᵢ − z̄)²)^½. The normalised quantities are
unchanged by a rotation or translation of the base frame, a shift of the
origin of Λ and a scaling of all lengths. Architecturally singular: all Cⱼ
vanish iff the 5 × 6 matrix of rows (zᵢ, xᵢ, yᵢ, xᵢzᵢ, yᵢzᵢ, 1) has rank
below 5 (the Cⱼ are its maximal minors); the margin is
:func:`architecture_margin`, σ₅/σ₁ in the best of five frames each centred
on one leg, so that it does not fall when one attachment lies far from the
others (a move along a B-line multiplies the Cⱼ by a growing factor, it does
not make them vanish).

References
----------
Borràs, Thomas & Torras 2011, eqs. (12), (13), (27), Sections II, III-A.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

__all__ = ["FAMILY_RTOL", "DesignError", "RearrangementError", "LinePlaneDesign", "line_plane_design", "normalised",
           "cofactors", "normalised_cofactors", "architecture_margin"]

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
