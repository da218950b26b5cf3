"""The singularity-invariant leg rearrangements of a line-plane 5-SPU.

A base attachment moves along its B-line; a platform attachment moves iff
its base attachment is at B; no move may make the design architecturally
singular (Borràs, Thomas & Torras 2011, Section III-B).

References
----------
Borràs, Thomas & Torras 2011, Section III-B, Figs. 6-7.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

from .line_plane_design import (
    FAMILY_RTOL, DesignError, LinePlaneDesign, RearrangementError, _collinearity, line_plane_design)
from .line_plane_pencil import b_line_direction, b_point, family

__all__ = ["move_base", "move_platform"]


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
        Signed distance along the B-line, in the direction of :func:`~classify.line_plane_pencil.b_line_direction`.
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
