"""Line-plane 5-SPU platforms: cofactors, B-point, families, singularity polynomial, rearrangements.

A 5-SPU robot with planar base and linear platform (Borràs, Thomas & Torras
2011, Section II) has its base attachments aᵢ = (xᵢ, yᵢ, 0) in the plane Π
(z = 0) and its platform attachments bᵢ = p + zᵢ i on the line Λ, where p is
the point of Λ with coordinate 0 and i = (u, v, w) the unit direction of Λ.
This module gathers the names of the modules that treat it, one concept each:

* :mod:`classify.line_plane_design`: the design (the five points
  (xᵢ, yᵢ, zᵢ) of the *3-D space of leg attachments*), its checks, the
  normalised design, the cofactors C₁ … C₆ of the 6 × 6 determinant (12)
  and the margin of architectural singularity (Section III-A);
* :mod:`classify.line_plane_pencil`: the pencil of B-lines (14), its vertex
  B (16), the line B∞ (15), the line Λ⁺ (23) and the family of Section IV
  (quartic, cubic, quadratic or architecturally singular), with margins;
* :mod:`classify.line_plane_singularities`: the singularity polynomial
  (17), its margin and its reading (18)-(20) (Section III-C), and the leg
  Jacobian that checks it;
* :mod:`classify.line_plane_rearrangements`: the singularity-invariant
  rearrangements of Section III-B;
* :mod:`classify.line_plane_files`: a design read from a mechanism's joint
  graph.

References
----------
Borràs, Thomas & Torras 2011, eqs. (12)-(17), (21)-(25), Sections III-IV;
equation (2) is lost from the text, its vector forms are (17) and (22).
"""

from __future__ import annotations

from .line_plane_design import (
    FAMILY_RTOL, DesignError, LinePlaneDesign, RearrangementError, architecture_margin, cofactors,
    line_plane_design, normalised, normalised_cofactors)
from .line_plane_files import FILE_RTOL, design_from_mechanism
from .line_plane_pencil import (FAMILIES, Family, b_infinity, b_line, b_line_direction, b_point, family, lambda_plus,
                                oriented_b_line)
from .line_plane_rearrangements import move_base, move_platform
from .line_plane_singularities import (
    SingularityReading, jacobian_determinant, leg_jacobian, singularity_margin, singularity_polynomial,
    singularity_reading)

__all__ = [
    "FAMILIES", "FAMILY_RTOL", "FILE_RTOL", "DesignError", "RearrangementError", "LinePlaneDesign", "Family",
    "SingularityReading", "line_plane_design", "normalised", "cofactors", "normalised_cofactors",
    "architecture_margin",
    "b_point", "b_infinity", "b_line", "oriented_b_line", "b_line_direction", "lambda_plus", "family",
    "singularity_polynomial",
    "singularity_margin", "singularity_reading", "leg_jacobian", "jacobian_determinant", "move_base",
    "move_platform", "design_from_mechanism",
]
