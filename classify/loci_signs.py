"""The sign functions of the loci: determinants whose zeros on M are a kind's singularities.

Where the constraint rows kept, Φ_r (r rows of DΦ independent at the
starting configuration, chosen once by a pivoted QR, so that the choice is
fixed over M), and the m rows of a kind's map make a square matrix, its
determinant is a smooth function on K whose zeros on M are that kind's
singularities (Park & Kim 1999, Section 3; Chablat, Wenger & Angeles 1998
eqs. 3b–3c: det A and det B):

* actuator: ``s_a(p) = det [DΦ_r(p)·diag(s); U·diag(s)]``, U the unit
  actuator rows (Dπ over their own length): zero iff ker DΦ ∩ ker Dπ ≠ 0,
  i.e. rank G < m (or a C-space singularity);
* end-effector: ``s_e(p) = det [DΦ_r(p)·diag(s); D_m f(p)·diag(s) / ‖·‖]``:
  zero iff rank J < m (or a C-space singularity) when n = m. With more
  end-effector coordinates than degrees of freedom, D_m f keeps the m rows
  of Df best conditioned on T_pM at the starting configuration (pivoted QR):
  its zeros contain the end-effector singularities, and the others are
  dropped by the confirmation of :func:`classify.loci.trace_loci`.

The actuator function needs as many actuated coordinates as degrees of
freedom (r + a = k); otherwise the kind is not traced and the coverage says
so. With more (redundant actuation), the actuator singularities of a 1- or
2-dof mechanism are searched for as points instead
(:func:`classify.loci_search.redundant_actuator_function`, as the C-space
singularities).

References
----------
Park & Kim 1999, Section 3; Chablat, Wenger & Angeles 1998, eqs. 3b–3c.
"""

from __future__ import annotations

import numpy as np

__all__ = ["TRACEABLE_KINDS", "ZERO_TOLERANCE", "sign_functions", "sign_magnitudes"]

#: the kinds a sign function exists for (C-space points are found as zeros of both)
TRACEABLE_KINDS = ("actuator", "end_effector")
#: a sign function vanishes at a configuration where its magnitude (:func:`sign_magnitudes`, Hadamard's ratio
#: ``|det A| / ∏ ‖A_i‖`` in [0, 1]) is at most this: a zero at a sample, or, at every point of a traced branch of
#: M, a branch singular everywhere (rounding leaves about 1e-16 there)
ZERO_TOLERANCE = 1e-9


def _kept_rows(model, point):
    """r rows of DΦ·diag(s) independent at `point` (pivoted QR of its transpose), as indices."""
    from scipy.linalg import qr

    from manifold import numerical_rank, scaled_jacobian

    jacobian = scaled_jacobian(model.manifold, point)
    rank = numerical_rank(jacobian).rank
    _, _, pivots = qr(jacobian.T, pivoting=True, mode="economic")
    return np.sort(pivots[:rank])


def sign_functions(model, point):
    """The sign functions of the traceable kinds (see the module notes), fixed at a starting configuration.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
        A regular configuration of M (fixes the kept constraint rows).

    Returns
    -------
    functions : dict of str to callable
        Kind → ``s(points [n, point_size]) -> values [n]``, for the kinds whose matrix is square.
    refused : dict of str to str
        Kind → why it has no sign function.
    """
    matrices, refused = _sign_matrices(model, point)
    return {kind: _determinant(matrix) for kind, matrix in matrices.items()}, refused


def sign_magnitudes(model, point):
    """The scale-aware magnitudes of the sign functions: ``|det A| / ∏ ‖A_i‖`` (Hadamard's ratio of the square
    matrix A of :func:`sign_functions`, rows A_i), in [0, 1] whatever the rows' lengths, 0 exactly where s is.

    A sign function is taken to vanish at a configuration where its magnitude
    is at most :data:`ZERO_TOLERANCE` (a zero at a sample of a branch or grid,
    and a branch of M along which it vanishes identically, see
    :func:`~classify.loci.trace_loci`).

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
        A regular configuration of M (fixes the kept constraint rows, as :func:`sign_functions`).

    Returns
    -------
    dict of str to callable
        Kind → ``magnitude(points [n, point_size]) -> values [n]``.
    """
    matrices, _ = _sign_matrices(model, point)
    return {kind: _hadamard_ratio(matrix) for kind, matrix in matrices.items()}


def _determinant(matrix):
    return lambda points: np.linalg.det(matrix(points))


def _hadamard_ratio(matrix):
    def magnitude(points):
        values = matrix(points)
        lengths = np.prod(np.linalg.norm(values, axis=-1), axis=-1)
        return np.abs(np.linalg.det(values)) / np.maximum(lengths, 1e-300)
    return magnitude


def _sign_matrices(model, point):
    """The square matrices of the sign functions (kind → ``matrix(points [n, point_size]) -> [n, k, k]``) and
    the kinds refused, with why."""
    from .survey import unit_actuator_rows

    manifold = model.manifold
    scales = manifold.ambient.tangent_scales
    rows = _kept_rows(model, point)
    k = manifold.ambient.dim
    functions, refused = {}, {}

    def constraint_rows(points):
        return np.asarray(manifold.constraint_jacobian(points), dtype=float)[..., rows, :] * scales

    actuators = unit_actuator_rows(model)[0] * scales
    if len(rows) + len(actuators) == k:
        functions["actuator"] = lambda points: np.concatenate(
            [constraint_rows(points), np.broadcast_to(actuators, np.shape(points)[:-1] + actuators.shape)], axis=-2)
    else:
        refused["actuator"] = (f"{len(actuators)} actuated coordinate(s) for {k - len(rows)} degree(s) of freedom: "
                               f"no square matrix")
    n = model.end_effector_dimension
    dof = k - len(rows)
    if n >= dof > 0:
        outputs = _kept_outputs(model, point, rows, dof)

        def end_effector(points):
            jacobian = np.asarray(model.end_effector_jacobian(points), dtype=float)[..., outputs, :] * scales
            size = np.linalg.norm(jacobian, axis=(-2, -1), keepdims=True)
            return np.concatenate([constraint_rows(points), jacobian / np.maximum(size, 1e-300)], axis=-2)
        functions["end_effector"] = end_effector
    elif n:
        refused["end_effector"] = f"{n} end-effector coordinate(s) for {dof} degree(s) of freedom"
    else:
        refused["end_effector"] = "no end-effector"
    return functions, refused


def _kept_outputs(model, point, rows, dof):
    """m rows of Df whose restriction to T_pM is best conditioned at `point` (pivoted QR), as indices: with more
    end-effector coordinates than degrees of freedom, their zeros contain the end-effector singularities."""
    from scipy.linalg import qr

    scales = model.manifold.ambient.tangent_scales
    jacobian = np.asarray(model.manifold.constraint_jacobian(point), dtype=float)[rows] * scales
    basis = np.linalg.svd(jacobian, full_matrices=True)[2][len(rows):].T
    restricted = (np.asarray(model.end_effector_jacobian(point), dtype=float) * scales) @ basis
    _, _, pivots = qr(restricted.T, pivoting=True, mode="economic")
    return np.sort(pivots[:dof])
