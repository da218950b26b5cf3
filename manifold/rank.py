"""Numerical rank with a documented, scale-aware tolerance and its margin.

Every rank decision of the project goes through :func:`numerical_rank`. The
cut is relative: a singular value σᵢ counts when ``σᵢ > rtol · s`` where s
is a reference scale, by default σ₁ (the largest singular value). A matrix
restricted to a subspace (G = Tᵀ E T, J = Df T) passes the scale of the
unrestricted map (the classification passes σ₁ of the unit actuator rows and
σ₁(H^½ Df), both times diag(s)), so that a map that is small on the whole
subspace is seen as small. A matrix whose scale is below ``atol``
has rank 0.

At a fold of M (a turning point such as the slider-crank's sin θ = l/R) a
singular value grows like the square root of the distance to the
singularity, so a configuration given to rounding error (1e-16) shows
σ ≈ 1e-8: the default cut ``rtol = 1e-6`` sits above that and well below the
singular values of any configuration a user would call regular. Relative cuts
do not change when a matrix is multiplied by a common factor; mixed units
(angles and lengths in one matrix) are made commensurate upstream (loop
rows divided by a characteristic length, end-effector Jacobians weighted by
H^½). That length is taken from the joints' points alone
(:attr:`mechanisms.Mechanism.characteristic_length`): DΦ, its cut and
its margin describe M, so they do not depend on where the end-effector
point is.

The decision carries its *margin*: the last singular value kept and the
first one dropped, so a user sees how close a call was.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["DEFAULT_RTOL", "DEFAULT_ATOL", "RankDecision", "numerical_rank", "rank_of_values", "check_rtol"]

#: default relative cut, ``σ > rtol · scale``
DEFAULT_RTOL = 1e-6
#: default absolute floor: a matrix with ``σ₁ ≤ atol`` has rank 0
DEFAULT_ATOL = 1e-12


@dataclass(frozen=True, eq=False)
class RankDecision:
    """The outcome of a rank decision.

    Attributes
    ----------
    rank : int
    singular_values : ndarray, shape=[min(rows, columns)]
        In descending order.
    tolerance : float
        The cut actually used.
    """

    rank: int
    singular_values: np.ndarray
    tolerance: float

    @property
    def margin(self):
        """``(σ_rank, σ_rank+1)``: the smallest value kept and the largest dropped.

        Either entry is ``None`` where it does not exist.
        """
        values = self.singular_values
        kept = float(values[self.rank - 1]) if self.rank > 0 else None
        dropped = float(values[self.rank]) if self.rank < len(values) else None
        return kept, dropped

    def to_dict(self):
        kept, dropped = self.margin
        return {
            "rank": int(self.rank),
            "tolerance": float(self.tolerance),
            "singular_values": [float(value) for value in self.singular_values],
            "margin": {"smallest_kept": kept, "largest_dropped": dropped},
        }


def numerical_rank(matrix, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, scale=None):
    """Rank of a matrix by a relative singular-value cut.

    Parameters
    ----------
    matrix : array_like, shape=[rows, columns]
    rtol : float
        Relative cut: σᵢ counts when ``σᵢ > rtol · scale``.
    atol : float
        Absolute floor of the cut.
    scale : float, optional
        Reference magnitude; default σ₁ of `matrix` itself.

    Returns
    -------
    decision : RankDecision

    Examples
    --------
    >>> decision = numerical_rank([[1.0, 0.0], [0.0, 1e-12]])
    >>> decision.rank, decision.margin
    (1, (1.0, 1e-12))
    """
    matrix = np.asarray(matrix, dtype=float)
    if matrix.ndim != 2:
        raise ValueError(f"Expected a matrix of shape (rows, columns), got shape {matrix.shape}")
    if not np.all(np.isfinite(matrix)):
        raise ValueError("Expected a matrix of finite numbers (NaN or infinity has no rank)")
    if matrix.size == 0:  # no singular values: the cut that would apply (max(rtol·scale, atol), as for others)
        return rank_of_values(np.zeros(0), rtol=rtol, atol=atol, scale=scale)
    return rank_of_values(np.linalg.svd(matrix, compute_uv=False), rtol=rtol, atol=atol, scale=scale)


def check_rtol(rtol):
    """ValueError unless `rtol` is a relative cut: a number in (0, 1) (NaN, 0 or 1 and above make every rank
    decision meaningless: with NaN every rank was 0 and a singular configuration came out regular)."""
    if isinstance(rtol, bool) or not (isinstance(rtol, (int, float, np.floating, np.integer)) and 0 < rtol < 1):
        raise ValueError(f"Expected rtol to be a relative cut in (0, 1), got {rtol!r}")


def rank_of_values(singular_values, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, scale=None):
    """The decision of :func:`numerical_rank` from singular values already computed.

    For a matrix known by pieces, e.g. a block-diagonal DΦ (after permuting
    rows and columns) whose singular values are the union of its blocks':
    the cut is the same as for the whole matrix (relative to its σ₁ unless
    `scale` is given).

    Parameters
    ----------
    singular_values : array_like, shape=[count]
        In any order; sorted here into descending order.
    rtol, atol, scale : float
        As in :func:`numerical_rank`.

    Returns
    -------
    decision : RankDecision

    Examples
    --------
    >>> rank_of_values([1e-12, 1.0, 0.5]).rank
    2
    """
    check_rtol(rtol)
    values = np.sort(np.asarray(singular_values, dtype=float).ravel())[::-1]
    reference = (values[0] if len(values) else 0.0) if scale is None else float(scale)
    tolerance = max(rtol * reference, atol)
    rank = int(np.count_nonzero(values > tolerance))
    return RankDecision(rank, values, float(tolerance))
