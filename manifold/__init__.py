"""Differential geometry of implicit manifolds in products of joint factors.

Knows nothing about mechanisms: an :class:`AmbientSpace` (ℝ, S¹, SO(3)
factors with recentred charts), an :class:`ImplicitManifold` Φ⁻¹(0) with its
derivatives, projection onto it, rank decisions, sampling and continuation.
"""

from .ambient import FACTORS, AmbientSpace, rotation_exp, rotation_log
from .continuation import CurveCertificate, continue_curve
from .errors import ContinuationError, ManifoldError, ProjectionError
from .implicit import (
    ImplicitManifold,
    constraint_curvature,
    normal_basis,
    project,
    residual,
    scaled_jacobian,
    tangent_basis,
)
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, RankDecision, numerical_rank
from .sampling import LocalRank, largest_rank, local_rank, sample_manifold

__all__ = [
    "FACTORS", "AmbientSpace", "rotation_exp", "rotation_log",
    "CurveCertificate", "continue_curve",
    "ContinuationError", "ManifoldError", "ProjectionError",
    "ImplicitManifold", "constraint_curvature", "normal_basis", "project", "residual", "scaled_jacobian", "tangent_basis",
    "DEFAULT_ATOL", "DEFAULT_RTOL", "RankDecision", "numerical_rank",
    "LocalRank", "largest_rank", "local_rank", "sample_manifold",
]
