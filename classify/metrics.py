"""Metrics on K, M and N, and the manipulability proper values.

Park & Kim (1999), Section 2:

* E on K, the actuator metric: ``ds² = Σ εᵢ dxᵢ²`` with εᵢ the weight of an
  actuated coordinate and 0 for a passive one (eq. 5), possibly semidefinite.
* G = Tᵀ E T on M for a basis T of T_pM (eqs. 6-7), ``G = AᵀA`` with the
  *actuator Jacobian* ``A = E^{1/2} T`` restricted to the actuated rows,
  whose singular values are the square roots of G's eigenvalues; A serves
  the proper values. Rank decisions are taken on the unit actuator rows
  (:func:`unit_rows` of ``E^{1/2} Dπ``) times T: the same kernel on T_pM,
  independent of the weights and of the unit of length.
* H on N: Euclidean on ℝ²/ℝ³, bi-invariant (identity on body angular
  velocity) on SO(2)/SO(3), and on SE(2)/SE(3) the left-invariant metric
  ``L²|ω|² + |v|²`` on body twists (ω, v) with a length scale L.
* The proper values of the pull-back f*h: the roots of
  ``det(λ G − Jᵀ H J) = 0`` (Park & Kim, Section 2), with J = Df T; the
  condition number λ₁/λₙ (eq. 3) and the volume (λ₁⋯λₙ)^½ (eq. 4).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from mechanisms import actuator_jacobian, end_effector_dimension, kinematics_of

#: how far from the characteristic length an end-effector length scale L may be (beyond, L² makes the metric's
#: rotation and translation parts 1e12 apart and the proper values say nothing; 1e300 overflowed)
LENGTH_SCALE_RATIO = 1e6

__all__ = [
    "actuator_metric", "weighted_actuator_jacobian", "end_effector_metric",
    "metric_root", "pullback_metric", "Manipulability", "manipulability",
    "unit_rows", "largest_singular_value", "coordinate_rows", "coordinate_singular_values", "proper_values",
    "singular_values", "jacobi_singular_values",
    "moving_directions",
]


def actuator_metric(mechanism):
    """E: the k×k actuator metric on K (Park & Kim, eq. 5), shape=[k, k]."""
    selection = actuator_jacobian(mechanism)
    weights = np.asarray(mechanism.actuator_weights, dtype=float)
    return selection.T @ np.diag(weights) @ selection


def weighted_actuator_jacobian(mechanism):
    """``E^{1/2}`` on the actuated rows: ``diag(√w) Dπ``, shape=[a, k]."""
    weights = np.sqrt(np.asarray(mechanism.actuator_weights, dtype=float))
    return weights[:, None] * actuator_jacobian(mechanism)


def unit_rows(matrix, scales):
    """The rows of a map on joint rates, each divided by its dimensionless norm ``|row·diag(s)|``.

    Rank decisions on G = Tᵀ E T use ``unit_rows(E^½ Dπ, s)`` instead of
    ``E^½ Dπ``: with positive weights both have the same kernel on any
    subspace, but the unit rows depend neither on the weights nor on the
    unit of length of a prismatic actuator, so neither can change a verdict
    (a weight of 1e-300 or a mechanism drawn in micrometres decides as one in
    metres with weight 1).

    Parameters
    ----------
    matrix : ndarray, shape=[a, k]
    scales : ndarray, shape=[k]
        The tangent scales s (:attr:`manifold.AmbientSpace.tangent_scales`).

    Returns
    -------
    ndarray, shape=[a, k]
        Zero rows stay zero.
    """
    matrix = np.asarray(matrix, dtype=float)
    norms = np.linalg.norm(matrix * scales, axis=-1, keepdims=True)
    return np.divide(matrix, norms, out=np.zeros_like(matrix), where=norms > 0)


def largest_singular_value(matrix):
    """σ₁ of a matrix (0 for an empty one): the reference scale of a restricted map's rank."""
    return float(np.linalg.norm(matrix, 2)) if np.size(matrix) else 0.0


def coordinate_rows(matrix):
    """Where every row of a matrix has exactly one nonzero entry (an actuated joint's rate, as the actuators of a
    joint-graph mechanism), that entry's column and value; else None.

    Parameters
    ----------
    matrix : ndarray, shape=[a, k]

    Returns
    -------
    tuple or None
        ``(columns [a], factors [a])``: row i is ``factors[i]`` times the unit row at ``columns[i]``.
    """
    matrix = np.asarray(matrix, dtype=float)
    nonzero = matrix != 0.0
    if matrix.ndim != 2 or not np.all(np.count_nonzero(nonzero, axis=1) == 1):
        return None
    columns = np.argmax(nonzero, axis=1)
    return columns, matrix[np.arange(len(matrix)), columns]


def coordinate_singular_values(columns, factors):
    """Singular values of the matrix M whose row i is ``factors[i]`` times the unit row at ``columns[i]``
    (:func:`coordinate_rows`), descending, one per distinct column: the norms of M's nonzero columns.

    MᵀM is diagonal, ``(MᵀM)ⱼⱼ = Σ_{i: columns[i] = j} factors[i]²`` (rows at distinct columns are
    orthogonal), so σⱼ = ‖M e_j‖. Each column's norm is taken over its largest factor, which neither
    overflows nor underflows.

    Parameters
    ----------
    columns : ndarray of int, shape=[a]
    factors : ndarray, shape=[a]

    Returns
    -------
    ndarray, shape=[distinct columns]

    Examples
    --------
    >>> import numpy as np
    >>> from classify.metrics import coordinate_singular_values
    >>> coordinate_singular_values(np.array([2, 0, 2]), np.array([3.0, -1.0, 4.0])).tolist()
    [5.0, 1.0]
    """
    distinct, which = np.unique(columns, return_inverse=True)
    magnitudes = np.abs(np.asarray(factors, dtype=float))
    largest = np.zeros(len(distinct))
    np.maximum.at(largest, which, magnitudes)
    size = np.where(largest > 0, largest, 1.0)
    values = size * np.sqrt(np.bincount(which, weights=(magnitudes / size[which]) ** 2, minlength=len(distinct)))
    return -np.sort(-values)


def end_effector_metric(mechanism, length_scale=None):
    """H on the end-effector space, in the chart of :func:`mechanisms.end_effector_jacobian`.

    Parameters
    ----------
    mechanism : Mechanism
    length_scale : float, optional
        L of the left-invariant metric on SE(2)/SE(3) and of the metric
        ``|dx|² + L²|du|²`` on ℝ³ × S² (a ``tool`` output); default the
        mechanism's characteristic length. Unused for other outputs.

    Returns
    -------
    H : ndarray, shape=[n, n]
        Pose: ``diag(L² I, I)`` (rotation rows first); tool:
        ``diag(I₃, L² I₂)`` (point rows first, then the direction in an
        orthonormal basis of u^⊥, :func:`mechanisms.kinematics.tool_basis`).
    """
    compiled = kinematics_of(mechanism)
    n = end_effector_dimension(mechanism)
    metric = np.eye(n)
    if compiled.output in ("pose", "tool"):
        scale = compiled.length if length_scale is None else float(length_scale)
        if not np.isfinite(scale) or scale <= 0:
            raise ValueError(f"Expected a positive finite length scale, got {length_scale!r}")
        if not compiled.length / LENGTH_SCALE_RATIO <= scale <= compiled.length * LENGTH_SCALE_RATIO:
            raise ValueError(f"Expected a length scale within a factor {LENGTH_SCALE_RATIO:g} of the mechanism's "
                             f"characteristic length {compiled.length:.3g} (L² weighs the rotations), got {scale:g}")
        if compiled.output == "tool":
            metric[3:, 3:] *= scale ** 2
        else:
            rotation_rows = 1 if compiled.space == "planar" else 3
            metric[:rotation_rows, :rotation_rows] *= scale ** 2
    return metric


def metric_root(metric):
    """H^½, the symmetric square root of a metric: rank decisions on H^½ J are taken in H's units."""
    values, vectors = np.linalg.eigh(metric)
    return vectors @ np.diag(np.sqrt(np.clip(values, 0.0, None))) @ vectors.T


def pullback_metric(matrix, basis):
    """``Bᵀ M B``: a metric pulled back to the span of a basis, shape=[m, m]."""
    return basis.T @ matrix @ basis


@dataclass(frozen=True, eq=False)
class Manipulability:
    """Proper values of f*h with respect to G.

    Attributes
    ----------
    eigenvalues : ndarray
        λ₁ ≥ … ≥ λₙ (the min(n, m) largest roots of det(λG − JᵀHJ) = 0).
    condition_number : float or None
        λ₁/λₙ, None when λₙ = 0 (end-effector singularity).
    volume : float
        (λ₁⋯λₙ)^½.
    """

    eigenvalues: np.ndarray
    condition_number: Optional[float]
    volume: float

    def to_dict(self):
        return {
            "eigenvalues": [float(value) for value in self.eigenvalues],
            "condition_number": None if self.condition_number is None else float(self.condition_number),
            "volume": float(self.volume),
        }


def moving_directions(stacked_rows, keep):
    """Coordinates of a complement of the idle freedoms in a tangent basis, shape=[..., m, keep].

    The idle freedoms are the kernel (dimension m − keep) of the stacked
    actuator and end-effector rows on T_pM (:func:`classify.survey.stacked`);
    the first `keep` right singular vectors of those rows span their
    orthogonal complement. G and JᵀHJ both vanish on the idle freedoms, so
    their pencil on T_pM is that of the quotient by them, and the proper
    values ``det(λG − JᵀHJ) = 0`` on any complement are those of the motions
    that move something (Park & Kim 1999, Section 2, where G is definite).

    Parameters
    ----------
    stacked_rows : ndarray, shape=[..., a + n, m]
    keep : int
        m − (the number of idle freedoms).

    Returns
    -------
    ndarray, shape=[..., m, keep]
    """
    right_transposed = np.linalg.svd(np.asarray(stacked_rows, dtype=float), full_matrices=True)[2]
    return np.swapaxes(right_transposed[..., :keep, :], -1, -2)


def proper_values(actuator_block, end_effector_block, metric, count):
    """The manipulability proper values of stacks of configurations.

    The roots of ``det(λG − JᵀHJ) = 0`` with G = AᵀA (Park & Kim 1999,
    Section 2), computed without forming G: with A = QR (R upper
    triangular, invertible where G is definite), they are the eigenvalues
    of ``R⁻ᵀ JᵀHJ R⁻¹ = XᵀX`` for ``X = H^½ J R⁻¹``, i.e. the squared
    singular values of X. A small λ keeps its relative accuracy (no
    squared condition number of G).

    Parameters
    ----------
    actuator_block : ndarray, shape=[..., a, m]
        A = E^½ T with a ≥ m and full column rank.
    end_effector_block : ndarray, shape=[..., n, m]
        J = Df T.
    metric : ndarray, shape=[n, n]
        H.
    count : int
        How many to keep, at most min(n, m).

    Returns
    -------
    ndarray, shape=[..., count]
        λ₁ ≥ λ₂ ≥ … ≥ λ_count.
    """
    actuator_block = np.asarray(actuator_block, dtype=float)
    # a square A needs no QR: H^½ J A⁻¹ = X Qᵀ has the singular values of X
    triangular = (actuator_block if actuator_block.shape[-2] == actuator_block.shape[-1]
                  else np.linalg.qr(actuator_block, mode="r"))
    weighted = metric_root(metric) @ np.asarray(end_effector_block, dtype=float)
    transformed = np.linalg.solve(np.swapaxes(triangular, -1, -2), np.swapaxes(weighted, -1, -2))  # Xᵀ
    values = singular_values(transformed.reshape((-1,) + transformed.shape[-2:]))
    return values.reshape(transformed.shape[:-2] + values.shape[-1:])[..., :count] ** 2


def singular_values(matrices):
    """Singular values of a stack of matrices, descending, shape=[b, min(rows, columns)].

    Empty matrices have none; a single row or column has its norm; 2×2
    matrices use the closed form of :func:`_singular_values_2x2`; matrices
    with 3 or 4 rows (or columns, transposed) and at most
    :data:`JACOBI_COLUMNS` columns (rows), in stacks of at least
    :data:`JACOBI_STACK`, one-sided Jacobi
    (:func:`jacobi_singular_values`, LAPACK where it does not converge);
    others LAPACK's (``numpy.linalg.svd``).
    """
    rows, columns = matrices.shape[-2:]
    if rows == 0 or columns == 0:
        return np.zeros(matrices.shape[:-2] + (0,))
    if rows == 1 or columns == 1:
        return np.linalg.norm(matrices.reshape(matrices.shape[:-2] + (-1,)), axis=-1)[..., None]
    if rows == columns == 2:
        return _singular_values_2x2(matrices)
    if (3 <= min(rows, columns) <= JACOBI_ROWS and max(rows, columns) <= JACOBI_COLUMNS
            and matrices.size >= JACOBI_STACK * rows * columns):
        wide = matrices if rows <= columns else np.swapaxes(matrices, -1, -2)
        flat = wide.reshape((-1,) + wide.shape[-2:])
        values, converged = jacobi_singular_values(flat)
        unconverged = np.flatnonzero(~converged)
        if len(unconverged):
            values[unconverged] = np.linalg.svd(flat[unconverged], compute_uv=False)
        return values.reshape(matrices.shape[:-2] + values.shape[-1:])
    return np.linalg.svd(matrices, compute_uv=False)


#: the most rows (of the wide orientation) and columns for which :func:`singular_values` uses Jacobi:
#: beyond, LAPACK's call per matrix is cheaper than the array operations of the sweeps
JACOBI_ROWS = 4
JACOBI_COLUMNS = 12
#: the fewest matrices in a stack for which :func:`singular_values` uses Jacobi (its cost is mostly per
#: array operation, LAPACK's per matrix)
JACOBI_STACK = 64


def _singular_values_2x2(matrices):
    """Singular values of 2×2 matrices ``[[a, b], [c, d]]`` in closed form, shape=[b, 2].

    ``σ₁ = (√((a+d)² + (c−b)²) + √((a−d)² + (c+b)²)) / 2`` (a sum of
    non-negative terms, no cancellation) and ``σ₂ = |ad − bc| / σ₁``, whose
    absolute error, of the order of the rounding unit times σ₁, is that of
    a backward-stable SVD: the same decisions and margins as LAPACK's,
    without a call per matrix.
    """
    size = np.max(np.abs(matrices), axis=(-2, -1))
    size = np.where(size > 0, size, 1.0)  # each matrix scaled to entries ≤ 1: ad − bc cannot underflow
    scaled = matrices / size[..., None, None]
    a, b = scaled[..., 0, 0], scaled[..., 0, 1]
    c, d = scaled[..., 1, 0], scaled[..., 1, 1]
    largest = 0.5 * (np.hypot(a + d, c - b) + np.hypot(a - d, c + b))
    determinant = np.abs(a * d - b * c)
    smallest = np.divide(determinant, largest, out=np.zeros_like(largest), where=largest > 0)
    return size[..., None] * np.stack([largest, np.minimum(smallest, largest)], axis=-1)


def jacobi_singular_values(matrices, sweeps=8):
    """Singular values of a stack of wide matrices by one-sided (Hestenes) Jacobi on their rows.

    Plane rotations on pairs of rows ``x, y`` (left multiplications, which
    keep the singular values) make every pair orthogonal: with ``α = |x|²``,
    ``β = |y|²``, ``γ = x·y``, ``ζ = (β − α)/(2γ)``, ``t = sign(ζ)/(|ζ| + √(1 + ζ²))``
    the rotation ``(c, s) = (1, t)/√(1 + t²)`` zeroes ``γ``; the singular values
    are then the row norms. Each sweep rotates every pair once, all matrices
    of the stack at once (array operations on the rows, no call per matrix).
    Converged rows give the singular values to high relative accuracy
    (Demmel & Veselić 1992): a few rounding units of each σ, as accurate as
    LAPACK's for the σ's that decide ranks here. For a handful of rows this
    is several times faster than ``numpy.linalg.svd`` of the stack.

    Parameters
    ----------
    matrices : ndarray, shape=[b, r, c]
        Any shape; wide (r ≤ c) is the cheap case.
    sweeps : int
        Most sweeps over the pairs (quadratic convergence: 4 to 6 suffice to rounding).

    Returns
    -------
    values : ndarray, shape=[b, r]
        Descending (r of them: pad with the zeros of a tall matrix yourself).
    converged : ndarray of bool, shape=[b]
        Where every pair ended orthogonal to ``|γ| ≤ 4 ε √(αβ)``; elsewhere use LAPACK.
    """
    count, size = matrices.shape[:2]
    largest = np.max(np.abs(matrices), axis=(-2, -1)) if matrices.size else np.zeros(count)
    largest = np.where(largest > 0, largest, 1.0)  # each matrix scaled to entries ≤ 1: no under- or overflow
    scaled = matrices / largest[:, None, None]
    rows = [np.ascontiguousarray(scaled[:, index, :].T) for index in range(size)]  # [c, b]: the stack last
    pairs = [(first, second) for first in range(size) for second in range(first + 1, size)]
    norms = [np.einsum("ib,ib->b", row, row) for row in rows]
    limit = 4.0 * np.finfo(float).eps
    converged = np.zeros(count, dtype=bool)
    for _ in range(sweeps):
        worst = np.zeros(count)
        for first, second in pairs:
            x, y = rows[first], rows[second]
            alpha, beta = norms[first], norms[second]
            gamma = np.einsum("ib,ib->b", x, y)
            scale = np.sqrt(alpha * beta)
            np.maximum(worst, np.divide(np.abs(gamma), scale, out=np.zeros(count), where=scale > 0), out=worst)
            zeta = np.divide(beta - alpha, 2.0 * gamma, out=np.zeros(count), where=gamma != 0)
            tangent = np.where(gamma != 0, np.copysign(1.0, zeta) / (np.abs(zeta) + np.hypot(1.0, zeta)), 0.0)
            cosine = 1.0 / np.sqrt(1.0 + tangent * tangent)
            sine = cosine * tangent
            rows[first] = cosine * x - sine * y
            rows[second] = sine * x + cosine * y
            norms[first] = np.einsum("ib,ib->b", rows[first], rows[first])
            norms[second] = np.einsum("ib,ib->b", rows[second], rows[second])
        converged = worst <= limit
        if converged.all():
            break
    values = np.sqrt(np.stack(norms, axis=1))
    return largest[:, None] * -np.sort(-values, axis=1), converged


def manipulability(actuator_block, end_effector_block, metric, count, rank=None, rtol=1e-6):
    """Manipulability proper values from the actuator and end-effector Jacobians on T_pM.

    Parameters
    ----------
    actuator_block : ndarray, shape=[a, m]
        ``E^{1/2} T``; G = AᵀA must be positive definite.
    end_effector_block : ndarray, shape=[n, m]
        J = Df T.
    metric : ndarray, shape=[n, n]
        H.
    count : int
        How many proper values to keep: :func:`classify.classify` keeps as many as J has rank on M (the
        end-effector's expected rank, at most min(n, m); at least one).
    rank : int, optional
        The numerical rank of J (from the end-effector rank decision); when
        below `count`, λₙ is zero and the condition number is None.
    rtol : float
        Without `rank`, λₙ counts as zero when ``λₙ ≤ rtol · λ₁``.

    Returns
    -------
    Manipulability
    """
    values = proper_values(actuator_block, end_effector_block, metric, count)
    largest = values[0] if len(values) else 0.0
    smallest = values[-1] if len(values) else 0.0
    vanishing = (rank < count) if rank is not None else smallest <= rtol * largest
    condition = None if vanishing or smallest <= 0.0 else float(largest / smallest)
    return Manipulability(values, condition, float(np.sqrt(np.prod(values))))
