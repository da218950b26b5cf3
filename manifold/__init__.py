"""Differential geometry of implicit manifolds in products of joint factors.

Knows nothing about mechanisms: an :class:`AmbientSpace` (ℝ, S¹, SO(3)
factors with recentred charts), an :class:`ImplicitManifold` Φ⁻¹(0) with its
derivatives, projection onto it, rank decisions, sampling and continuation.

The names below are imported on first use (PEP 562): importing
:mod:`manifold.errors` alone costs nothing more.
"""

from ._lazy import attach

#: exported name → the submodule that defines it (imported when the name is first used)
_SOURCES = {
    **dict.fromkeys(("FACTORS", "AmbientSpace", "rotation_exp", "rotation_log"), ".ambient"),
    **dict.fromkeys(("JacobianPattern",), ".blocks"),
    **dict.fromkeys(("CurveCertificate", "continue_curve"), ".continuation"),
    **dict.fromkeys(("ManifoldError", "ProjectionError"), ".errors"),
    **dict.fromkeys(("ImplicitManifold", "constraint_curvature", "handled_by_blocks", "hessian_form", "jacobian_rank",
                     "jacobian_ranks", "minimum_norm_steps", "normal_basis", "project", "project_each", "project_many",
                     "residual", "scaled_jacobian", "scaled_singular_values", "settle_blocks", "sparse_tangent_basis",
                     "takes_stacks", "tangent_basis"), ".implicit"),
    **dict.fromkeys(("DEFAULT_ATOL", "DEFAULT_RTOL", "RankDecision", "numerical_rank", "rank_of_values",
                      "check_rtol"), ".rank"),
    **dict.fromkeys(("EXTENT_CUT", "LocalRank", "largest_rank", "local_rank", "sample_manifold", "TangentExtent",
                     "tangent_extent", "tangent_extents"),
                    ".sampling"),
}

__getattr__, __dir__, __all__ = attach(__name__, _SOURCES)
