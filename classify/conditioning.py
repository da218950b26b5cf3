"""Condition numbers of the direct and inverse kinematics matrices, batched over stacks of configurations.

With the velocity relation ``A t = B θ̇`` of Chablat, Caro, Wenger & Angeles
2002 (eq. 3) and Chablat, Wenger & Angeles 1998 (eq. 3a) — A the
direct-kinematics matrix, B the inverse-kinematics matrix, t the output twist,
θ̇ the actuated joint rates — this module computes, for stacks of matrices:

* ``"A"``: κ(Ā), Ā = A with its orientation columns divided by the
  characteristic length L (Chablat et al. 2002 eq. 7);
* ``"B"``: κ(B);
* ``"A-1B"``: κ(J̄), J̄ = Ā⁻¹B, the normalised Jacobian (t̄ = J̄ θ̇, t̄ the
  twist with its angular rates multiplied by L);
* ``"B-1A"``: κ(K̄), K̄ = B⁻¹Ā (eq. 9's K̄). κ(K̄) = κ(J̄) always, since
  K̄ = J̄⁻¹; both are reported because the papers tabulate K̄;
* ``"lambda"``: Park & Kim's condition number λ₁/λₙ (Park & Kim 1999 eq. 3),
  the ratio of the extreme roots of ``det(λG − JᵀHJ) = 0``. With unit actuator
  weights and H = diag(L², …, 1, …) it equals κ(J̄)²: λ's are squared singular
  values. For a mechanism without a paper relation G is taken on the actuated
  rates in units of length (angular ones multiplied by L, as J̄'s,
  :func:`mechanism_jacobians`), so that λ₁/λₙ = κ(J̄)² does not change with the
  unit of length where revolute and prismatic joints are both actuated.

Definitions of κ (both papers call each "the condition number"):

* :func:`singular_value_ratio` — σ_l/σ_s (Chablat et al. 2002 eq. 5;
  Chablat, Wenger & Angeles 1998 eqs. 4 and 7);
* :func:`square_root_ratio` — √(β_max/β_min) with β the singular values (the
  papers' κ(B): Chablat et al. 2002 §3.6, Chablat, Wenger & Angeles 1998
  eq. 11), i.e. the square root of σ_l/σ_s. The published global index of B
  (Table 1 of the 2002 paper, 0.709) is reproduced by σ_l/σ_s, not by this
  one (0.83); see ``docs/conditioning.rst``.

Each value is returned with its inverse 1/κ = σ_s/σ_l, which is finite
everywhere (0 at a singularity, where κ = ∞); maps and averages use 1/κ.

Only κ(J̄) (and κ(K̄), λ) is independent of how the rows of F are written:
scaling or reordering the rows of ``[B A]`` changes κ(A) and κ(B) but not
A⁻¹B. κ(A) and κ(B) are therefore taken from a paper's own F where it gives
one (:mod:`classify.conditioning_matrices`); for a mechanism without one
(:func:`mechanism_condition_numbers`) they are those of the derived relation
(:func:`derived_relation_ratios`), whose rows ``[B A]`` are orthonormal in
coordinates that all have the unit of length: actuated angles multiplied by
L (:func:`actuator_lengths`), the output's rotations multiplied by L by the
end-effector metric, as the characteristic length homogenises Ā (2002
eq. 7). κ(A) and κ(B) then do not change with the unit of length (L scaled
with it); that normalisation is stated with the result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "MATRICES", "DEFINITIONS", "ConditionNumbers",
    "singular_value_ratio", "square_root_ratio", "inverse_condition", "normalise_orientation",
    "condition_numbers", "tangent_bases", "mechanism_jacobians", "mechanism_condition_numbers",
    "actuator_lengths", "derived_relation_ratios", "DERIVED_NORMALISATION",
]

#: the matrices whose condition numbers are reported, in order (JSON keys of ``closedchain conditioning``)
MATRICES = ("A", "B", "A-1B", "B-1A", "lambda")
#: the definitions of κ: name → what it is
DEFINITIONS = {
    "singular_value_ratio": "σ_l/σ_s (Chablat et al. 2002 eq. 5; Chablat, Wenger & Angeles 1998 eq. 4)",
    "square_root_ratio": "√(β_max/β_min) (Chablat, Wenger & Angeles 1998 eq. 11; Chablat et al. 2002 §3.6)",
}


def _singular_values(matrices):
    """Singular values of a stack, descending, shape=[..., n]; NaN for a matrix with a non-finite entry."""
    from .metrics import singular_values

    matrices = np.asarray(matrices, dtype=float)
    finite = np.all(np.isfinite(matrices), axis=(-2, -1))
    safe = np.where(finite[..., None, None], matrices, 0.0)
    flat = safe.reshape((-1,) + safe.shape[-2:])
    values = singular_values(flat).reshape(safe.shape[:-2] + (min(safe.shape[-2:]),))
    return np.where(finite[..., None], values, np.nan)


def _diagonal_singular_values(matrices):
    """|diagonal| sorted descending when every matrix of the stack is exactly diagonal (B of both papers),
    else None: the SVD of a diagonal matrix, without LAPACK."""
    n = matrices.shape[-1]
    if matrices.shape[-2] != n or n < 2:
        return None
    diagonal = np.diagonal(matrices, axis1=-2, axis2=-1)
    if np.any(matrices - diagonal[..., :, None] * np.eye(n)):
        return None
    return -np.sort(-np.abs(diagonal), axis=-1)


def inverse_condition(matrices, scale=None, rtol=1e-12):
    """1/κ = σ_s/σ_l of a stack of matrices, shape=[...]: in [0, 1], 0 where singular, NaN where not finite.

    Parameters
    ----------
    matrices : array_like, shape=[..., n, n]
    scale : float, optional
        The size of the matrices' entries away from singularities (the papers' L1 L2 for B): σ_l ≤
        ``rtol · scale`` (every entry rounding noise, e.g. all legs folded at once) gives 1/κ = 0, not a ratio
        of rounding errors.
    rtol : float

    Returns
    -------
    ndarray, shape=[...]
        A zero matrix has 1/κ = 0.
    """
    matrices = np.asarray(matrices, dtype=float)
    values = _diagonal_singular_values(matrices)
    if values is None:
        values = _singular_values(matrices)
    largest, smallest = values[..., 0], values[..., -1]
    if scale is not None:
        largest = np.where(largest <= rtol * scale, 0.0, largest)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(largest > 0, smallest / np.where(largest > 0, largest, 1.0),
                        np.where(np.isnan(largest), np.nan, 0.0))


def singular_value_ratio(matrices):
    """κ = σ_l/σ_s of a stack of matrices (Chablat et al. 2002 eq. 5), shape=[...]; ∞ where singular.

    Parameters
    ----------
    matrices : array_like, shape=[..., n, n]

    Returns
    -------
    ndarray, shape=[...]
    """
    inverse = inverse_condition(matrices)
    with np.errstate(divide="ignore"):
        return 1.0 / inverse


def square_root_ratio(matrices):
    """κ = √(β_max/β_min), β the singular values (Chablat, Wenger & Angeles 1998 eq. 11), shape=[...].

    The papers' definition for the diagonal B (β = ``|Bᵢᵢ|``); it is the square root
    of :func:`singular_value_ratio`.
    """
    return np.sqrt(singular_value_ratio(matrices))


def normalise_orientation(direct, length, orientation_columns):
    """Ā: the orientation columns of A divided by the characteristic length (Chablat et al. 2002 eq. 7).

    Parameters
    ----------
    direct : array_like, shape=[..., n, n]
        A, whose columns multiply the output twist t; the orientation columns
        multiply angular rates (units length², the others length).
    length : float or array_like, shape=[...]
        L > 0.
    orientation_columns : sequence of int
        The columns of A that multiply angular rates (the 3-PRR: ``(2,)``).

    Returns
    -------
    ndarray, shape=[..., n, n]
    """
    normalised = np.array(direct, dtype=float, copy=True)
    columns = list(orientation_columns)
    if columns:
        normalised[..., :, columns] = normalised[..., :, columns] / np.asarray(length, dtype=float)[..., None, None]
    return normalised


@dataclass(frozen=True, eq=False)
class ConditionNumbers:
    """Condition numbers of stacks of configurations, one array per matrix.

    Attributes
    ----------
    values : dict of str to ndarray, shape=[...]
        ``{"A", "B", "A-1B", "B-1A", "lambda"}`` → κ (∞ where singular, NaN where undefined). ``"lambda"``
        is Park & Kim's λ₁/λₙ.
    length : float
        The characteristic length L used (1 when no column is an orientation).
    definition : str
        The definition of κ used for ``"A"``, ``"B"``, ``"A-1B"``, ``"B-1A"`` (a key of :data:`DEFINITIONS`).
    normalisation : str
        Where A and B come from and how their rows are scaled.
    """

    values: dict
    length: float
    definition: str = "singular_value_ratio"
    normalisation: str = ""

    def inverse(self, matrix):
        """1/κ of one matrix, shape=[...], 0 where singular."""
        with np.errstate(divide="ignore"):
            return 1.0 / self.values[matrix]

    def at(self, index):
        """The values of one configuration, ``{matrix: float or None}`` (None where undefined or infinite)."""
        def number(value):
            value = float(np.asarray(value)[index])
            return value if np.isfinite(value) else None
        return {matrix: number(self.values[matrix]) for matrix in MATRICES}


def _measure(definition):
    if definition == "singular_value_ratio":
        return singular_value_ratio
    if definition == "square_root_ratio":
        return square_root_ratio
    raise ValueError(f"definition: expected one of {', '.join(DEFINITIONS)}, got {definition!r}")


def condition_numbers(direct, inverse, length=1.0, orientation_columns=(), definition="singular_value_ratio",
                      normalisation="", scales=None):
    """κ(Ā), κ(B), κ(Ā⁻¹B), κ(B⁻¹Ā) and λ₁/λₙ from stacks of A and B (``A t = B θ̇``).

    Parameters
    ----------
    direct, inverse : array_like, shape=[..., n, n]
        A and B.
    length : float
        The characteristic length L (Chablat et al. 2002 §3.4).
    orientation_columns : sequence of int
        Columns of A multiplying angular rates, divided by L (eq. 7).
    definition : {"singular_value_ratio", "square_root_ratio"}
        κ of each matrix (:data:`DEFINITIONS`).
    normalisation : str
        Recorded on the result.
    scales : tuple of float, optional
        Sizes of Ā's and B's entries away from singularities: a matrix whose singular values are all below
        1e-12 times its scale counts as singular (:func:`inverse_condition`).

    Returns
    -------
    ConditionNumbers
        ``"lambda"`` = κ(J̄)² with σ_l/σ_s (Park & Kim's λ's with unit actuator weights and
        H = diag(L², 1, …) on the normalised twist); ∞ where A or B is singular.

    Notes
    -----
    J̄ = Ā⁻¹B is formed by a linear solve where Ā is regular; where Ā or B is
    singular (1/κ = 0) κ(J̄) = κ(K̄) = ∞, as the papers' maps show.
    """
    _measure(definition)
    normalised = normalise_orientation(direct, length, orientation_columns)
    inverse = np.asarray(inverse, dtype=float)
    direct_scale, input_scale = (None, None) if scales is None else scales
    direct_inverse = inverse_condition(normalised, direct_scale)
    input_inverse = inverse_condition(inverse, input_scale)
    regular = (direct_inverse > 0) & (input_inverse > 0)
    n = normalised.shape[-1]
    identity = np.eye(n)
    safe_direct = np.where(regular[..., None, None], normalised, identity)
    safe_inverse = np.where(regular[..., None, None], inverse, identity)
    if _diagonal_singular_values(safe_inverse) is not None:   # K̄ = B⁻¹Ā by rows: κ(K̄) = κ(J̄)
        diagonal = np.diagonal(safe_inverse, axis1=-2, axis2=-1)
        jacobian = safe_direct / diagonal[..., :, None]
    else:
        jacobian = np.linalg.solve(safe_direct, safe_inverse)
    jacobian_ratio = np.where(regular, singular_value_ratio(jacobian), np.inf)
    jacobian_ratio = np.where(np.isnan(direct_inverse) | np.isnan(input_inverse), np.nan, jacobian_ratio)
    if definition == "singular_value_ratio":
        jacobian_value = jacobian_ratio
    else:
        jacobian_value = np.sqrt(jacobian_ratio)
    with np.errstate(divide="ignore"):
        direct_ratio, input_ratio = 1.0 / direct_inverse, 1.0 / input_inverse
    if definition == "square_root_ratio":
        direct_ratio, input_ratio = np.sqrt(direct_ratio), np.sqrt(input_ratio)
    values = {
        "A": direct_ratio, "B": input_ratio,
        "A-1B": jacobian_value, "B-1A": jacobian_value.copy(),
        "lambda": jacobian_ratio ** 2,
    }
    return ConditionNumbers(values, float(length), definition, normalisation)


# ------------------------------------------------------------------------------------------------ any mechanism

def mechanism_jacobians(mechanism, points, length=None):
    """The normalised Jacobian J̄ = H^½ Df T (Λ E^½ Dπ T)⁻¹ of a mechanism at stacks of configurations.

    Output twists per unit actuated rates, with the rotation rows of a pose
    output multiplied by L (H = the end-effector metric of
    :func:`classify.metrics.end_effector_metric`, diag(L², …) on rotations) and
    the actuated angles' rates multiplied by L too (Λ = :func:`actuator_lengths`:
    L on an angular actuated coordinate, 1 on a prismatic one), so that every
    input and output is a rate of length, as the derived relation's (2002
    eq. 7's homogenisation): the paper's J̄ = Ā⁻¹B up to an orthogonal change of
    the output frame (body twists) and its sign convention. Λ changes nothing
    where the actuators are all prismatic or all angular (a common factor), but
    where both kinds are actuated (the Eclipse) J̄ without it had columns of two
    units and κ(J̄) changed with the unit of length. It does not depend on the
    basis T of T_pM (T → T R cancels), on the chart, on joint zeros, axis signs or
    the unit of length (L scaled with it).

    Parameters
    ----------
    mechanism : Mechanism
        With n actuated coordinates, an n-dimensional end-effector and an n-dimensional C-space.
    points : array_like, shape=[b, point_size]
        Configurations on M.
    length : float, optional
        L (default: the mechanism's characteristic length, as Park & Kim's metric).

    Returns
    -------
    jacobians : ndarray, shape=[b, n, n]
        NaN where the actuators do not parametrise M: 1/κ ≤ 1e-12 of the unit actuator rows times T
        (:func:`classify.metrics.unit_rows` of E^½ Dπ, dimensionless: neither the weights nor the unit of length
        decide).
    actuator_blocks : ndarray, shape=[b, n, n]
        Λ E^½ Dπ T (rates of length).
    output_blocks : ndarray, shape=[b, n, n]
        H^½ Df T.

    Raises
    ------
    ValueError
        When the numbers of actuators, outputs and degrees of freedom differ.
    """
    from mechanisms import end_effector_jacobian
    from mechanisms.kinematics import kinematics_of

    from .metrics import metric_root, unit_rows
    from .model import model_of

    model = model_of(mechanism, length_scale=length)
    resolved = model.mechanism.characteristic_length if length is None else float(length)
    points = np.atleast_2d(np.asarray(points, dtype=float))
    actuator_count, output_count = model.actuators.shape[0], model.end_effector_dimension
    basis = tangent_bases(mechanism, points)
    freedom = basis.shape[-1]
    if not actuator_count == output_count == freedom:
        raise ValueError(f"{mechanism.name}: {actuator_count} actuated coordinates, {output_count} outputs and "
                         f"{freedom} degrees of freedom; condition numbers of A⁻¹B need n of each")
    input_lengths = actuator_lengths(mechanism, model.actuators, resolved)
    actuator_blocks = input_lengths[:, None] * (model.actuators @ basis)
    output_blocks = metric_root(model.end_effector_metric) @ end_effector_jacobian(mechanism, points) @ basis
    scales = kinematics_of(mechanism).ambient.tangent_scales
    regular = inverse_condition(unit_rows(model.actuators, scales) @ basis) > 1e-12
    safe = np.where(regular[:, None, None], actuator_blocks, np.eye(freedom))
    jacobians = np.swapaxes(np.linalg.solve(np.swapaxes(safe, -1, -2), np.swapaxes(output_blocks, -1, -2)),
                            -1, -2)
    return np.where(regular[:, None, None], jacobians, np.nan), actuator_blocks, output_blocks


def tangent_bases(mechanism, points):
    """Bases T of the tangent spaces of M at a stack of configurations, shape=[b, k, m]: joint-rate vectors
    ``s·u``, u orthonormal kernel vectors of DΦ·diag(s) (the dimensionless Jacobian), m = k − its largest
    numerical rank over the stack (rtol 1e-9 against σ₁). Any quantity used through them must not depend on
    which basis it is (T → T R)."""
    from mechanisms import closure_and_jacobian
    from mechanisms.kinematics import kinematics_of

    from .batch import kernel_bases

    points = np.atleast_2d(np.asarray(points, dtype=float))
    _, _, constraint = closure_and_jacobian(mechanism, points)
    scales = kinematics_of(mechanism).ambient.tangent_scales
    scaled = np.asarray(constraint, dtype=float) * scales
    return scales[:, None] * kernel_bases(scaled, _constraint_rank(scaled))


def _constraint_rank(scaled):
    """The largest numerical rank of DΦ·diag(s) over the stack (rtol 1e-9 against σ₁).

    DΦ·diag(s) is dimensionless (loop rows over the characteristic length, slide columns times it): its singular
    values, and so this rank, are the same in any unit of length."""
    from .metrics import singular_values

    if scaled.size == 0:  # no loop (a serial chain, a tree: DΦ has no rows), or no configuration
        return 0
    values = singular_values(scaled.reshape((-1,) + scaled.shape[-2:]))
    return int(np.max(np.count_nonzero(values > 1e-9 * values[:, :1], axis=1)))


def mechanism_condition_numbers(mechanism, points, length=None, rtol=1e-9):
    """Condition numbers of a mechanism with no paper relation: derived A and B, batched J̄ and λ.

    Parameters
    ----------
    mechanism : Mechanism
    points : array_like, shape=[b, point_size]
    length : float, optional
        L of the end-effector metric (default: the mechanism's characteristic length).
    rtol : float
        Relative cut of the derived relation's rank decision (:func:`derived_relation_ratios`).

    Returns
    -------
    ConditionNumbers
        ``"A-1B"``, ``"B-1A"`` from :func:`mechanism_jacobians` (batched); ``"lambda"`` from
        :func:`classify.metrics.proper_values` (Park & Kim, G on the actuated rates in units of length: Λ E^½ Dπ T,
        so λ₁/λₙ = κ(J̄)²); ``"A"`` and ``"B"`` of the derived relation
        (:func:`derived_relation_ratios`, batched): rows of ``[B A]`` orthonormal in coordinates of one unit,
        the length, so that κ(A), κ(B) do not change with the unit of length (another F gives other κ(A),
        κ(B)).
    """
    from .metrics import proper_values
    from .model import model_of

    model = model_of(mechanism, length_scale=length)
    resolved = model.mechanism.characteristic_length if length is None else float(length)
    points = np.atleast_2d(np.asarray(points, dtype=float))
    jacobians, actuator_blocks, output_blocks = mechanism_jacobians(mechanism, points, length)
    jacobian_ratio = singular_value_ratio(jacobians)
    count = actuator_blocks.shape[-1]
    regular = np.all(np.isfinite(jacobians), axis=(-2, -1))
    lambdas = np.full(len(points), np.inf)
    if np.any(regular):
        values = proper_values(actuator_blocks[regular], output_blocks[regular], np.eye(count), count)
        with np.errstate(divide="ignore"):
            lambdas[regular] = values[:, 0] / values[:, -1]
    direct, inverse = derived_relation_ratios(actuator_blocks, output_blocks, rtol)   # Λ E^½ Dπ T: lengths
    values = {"A": direct, "B": inverse, "A-1B": jacobian_ratio, "B-1A": jacobian_ratio.copy(), "lambda": lambdas}
    return ConditionNumbers(values, float(resolved), "singular_value_ratio", DERIVED_NORMALISATION)


#: how the derived relation's A and B are normalised (recorded on the results)
DERIVED_NORMALISATION = ("derived relation: rows of [B A] orthonormal in coordinates of one unit, the length "
                         "(L E^½ θ̇ for angular actuated rates, E^½ θ̇ for prismatic ones; H^½ ẋ with "
                         "H = diag(L², 1, …) on rotations); J̄ and λ on the same rates")


def actuator_lengths(mechanism, actuators, length):
    """Per actuated coordinate, the factor that turns its weighted rate into a rate of length, shape=[a].

    L for an actuated angle (a revolute joint, a rotation of a ball joint), 1 for a prismatic coordinate:
    with the rotations of the output multiplied by L too (the end-effector metric), every input and output
    of the derived relation is a rate of length, as Chablat, Caro, Wenger & Angeles 2002 eq. 7 makes Ā
    homogeneous by dividing by the characteristic length.

    Parameters
    ----------
    mechanism : Mechanism
    actuators : ndarray, shape=[a, k]
        E^½ Dπ (rows select the actuated joint coordinates).
    length : float
        L.

    Returns
    -------
    ndarray, shape=[a]
    """
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    angular = np.ones(ambient.dim, dtype=bool)
    for factor, part in zip(ambient.factors, ambient.tangent_slices):
        angular[part] = factor != "R"
    touches_angle = np.any((np.asarray(actuators) != 0) & angular, axis=1)
    return np.where(touches_angle, float(length), 1.0)


def derived_relation_ratios(input_blocks, output_blocks, rtol=1e-9):
    """κ(A) and κ(B) of the relation ``A ẋ = B θ̇`` whose rows ``[B A]`` are an orthonormal basis of the
    annihilator of V = {(P u, Q u)} (Gosselin & Angeles 1990 eq. 2, derived), batched.

    Parameters
    ----------
    input_blocks : ndarray, shape=[b, n, n]
        P: the actuated rates per tangent vector, in units of length (:func:`actuator_lengths`).
    output_blocks : ndarray, shape=[b, n, n]
        Q: the output rates per tangent vector, in units of length (H^½ Df T).
    rtol : float
        V has dimension n when σₙ > rtol·σ₁ of the stacked [P; Q] (2n × n). Both blocks in the one unit of
        length, the stacked matrix is multiplied by c when the unit changes by c: the decision does not
        depend on the unit. Where dim V < n (an idle freedom: a motion moving neither inputs nor outputs),
        the relation is undefined (NaN).

    Returns
    -------
    direct, inverse : ndarray, shape=[b]
        κ(A) and κ(B) (σ_l/σ_s; ∞ where singular).

    Notes
    -----
    Where P is regular, V is the graph of J = Q P⁻¹ and, with σ the singular values of J, κ(A) =
    √((1 + σ₁²)/(1 + σₙ²)) and κ(B) = (σ₁/√(1 + σ₁²)) / (σₙ/√(1 + σₙ²)): both functions of the
    dimensionless J only. Scaling P and Q by different factors (the former normalisation by ‖E^½ Dπ‖₂ and
    ‖H^½ Df‖₂, whose revolute and prismatic columns scale differently with the unit) would change them.
    """
    stacked = np.concatenate([input_blocks, output_blocks], axis=-2)
    count = input_blocks.shape[-1]
    finite = np.all(np.isfinite(stacked), axis=(-2, -1))
    safe = np.where(finite[:, None, None], stacked, np.vstack([np.eye(count), np.eye(count)]))
    left, values, _ = np.linalg.svd(safe, full_matrices=True)
    defined = finite & (values[:, -1] > rtol * values[:, 0])
    annihilator = np.swapaxes(left[..., count:], -1, -2)      # [b, n, 2n], orthonormal rows: [B A]
    direct = singular_value_ratio(annihilator[..., count:])
    inverse = singular_value_ratio(annihilator[..., :count])
    return np.where(defined, direct, np.nan), np.where(defined, inverse, np.nan)
