"""Singularity loci of 1-, 2- and 3-dof mechanisms, traced as curves on M (3 dof: in sections) and confirmed by
:func:`classify.classify`.

**Sign functions.** Where the constraint rows kept, Φ_r (r rows of DΦ
independent at the starting configuration, chosen once by a pivoted QR, so
that the choice is fixed over M), and the m rows of a kind's map make a
square matrix, its determinant is a smooth function on K whose zeros on M
are that kind's singularities (Park & Kim 1999, Section 3; Chablat, Wenger &
Angeles 1998 eqs. 3b–3c: det A and det B):

* actuator: ``s_a(p) = det [DΦ_r(p)·diag(s); U·diag(s)]``, U the unit
  actuator rows (Dπ over their own length): zero iff ker DΦ ∩ ker Dπ ≠ 0,
  i.e. rank G < m (or a C-space singularity);
* end-effector: ``s_e(p) = det [DΦ_r(p)·diag(s); D_m f(p)·diag(s) / ‖·‖]``:
  zero iff rank J < m (or a C-space singularity) when n = m. With more
  end-effector coordinates than degrees of freedom, D_m f keeps the m rows
  of Df best conditioned on T_pM at the starting configuration (pivoted QR):
  its zeros contain the end-effector singularities, and the others are
  dropped by the confirmation below.

The actuator function needs as many actuated coordinates as degrees of
freedom (r + a = k); otherwise the kind is not traced and the coverage says
so. With more (redundant actuation), the actuator singularities of a 1- or
2-dof mechanism are searched for as points instead
(:func:`redundant_actuator_function`, as the C-space singularities below).

**2 dof.** A grid over two coordinates is assembled by continuation from a
starting configuration (:func:`classify.grid_continuation.assemble_grid`: the
starting configuration's branch). Seeds are the grid edges along which a sign
function changes sign, and the edges from a reached point to an unreached one
(the reach of a branch ends at a fold, often an actuator singularity), and
the reached points where a sign function vanishes (its magnitude,
:func:`sign_magnitudes`, at most :data:`ZERO_TOLERANCE`). From a start
singular for the grid's coordinates (e.g. an actuator singularity of a grid
over the actuated coordinates) the continuation can reach nothing; the grid
points it leaves are then started from a regular neighbour on M
(:func:`classify.grid_continuation.regular_start`), said in the coverage's
``start``. With ``assembly_branches`` > 1 the grid is also assembled on
the other assembly branches the loops' solutions at a few grid points lead
to (:func:`classify.grid_continuation.assemble_branches`; each sample's
branch in :attr:`Loci.sample_branches`), and the seeds of every branch are
traced: e.g. the five-bar's two solutions for the same inputs, of opposite
signs of det A (Chablat, Wenger & Angeles 1998 eq. 9). Each
seed is corrected onto the curve ``{Φ = 0, s = 0}`` by Gauss–Newton
(:func:`manifold.project`, ‖(Φ, s)‖ ≤ :data:`TOLERANCE`), the gradient of s by
central differences (step 1e-6, dimensionless). From the first seed not yet
on a traced curve, the curve is followed by a predictor (along the null
vector of ``[DΦ; ∇s]``) and corrector (the same projection) both ways until
it comes back to its start (a closed curve), a corrector fails four times
halved, or :data:`STEP_LIMIT` steps. Seeds within two steps of a traced
curve are covered by it.

**3 dof.** The loci are surfaces of M, traced as curves in sections: at n
values c of a third coordinate x_c (the section coordinate; a displacement
from home, an angle's difference wrapped to [−π, π)), the curve
``{Φ = 0, s = 0, x_c = c}`` is traced exactly as a 2-dof curve (the same
seeds, corrector and predictor, with one more row, ``h(p) = x_c(p) − c``,
whose gradient is taken by the same central differences). The grids of all
the sections are one grid, the section coordinate its first axis, assembled
by one continuation from the starting configuration: every section is on
its branch. Each piece records its section value; the coverage gives, per
section, the grid points reached, the seeds and the pieces found.

**1 dof.** M itself is the curve ``{Φ = 0}``, followed the same way from
points of M sampled over its branches (:func:`manifold.sample_manifold`) and
the starting configuration: each traced curve is one branch. The loci are
points: where s_a or s_e changes sign between consecutive points of a branch
(a closed branch: its last and first points too) or vanishes at one (its
magnitude, :func:`sign_magnitudes`, at most :data:`ZERO_TOLERANCE`: a start
at a singularity is found), corrected onto ``{Φ = 0, s = 0}`` (a square
system). Where a sign function vanishes at every point of a traced branch
(its largest magnitude along it at most :data:`ZERO_TOLERANCE`, reported
in the coverage's ``whole_branch`` with the tolerance), the whole branch is
that kind's locus: one piece, ``whole_branch`` set, confirmed by the
classification at its points (Park & Kim 1999 Fig. 3a: the slider-crank
with crank = coupler, whose slider stays at the crank's pivot on one
branch; Gosselin & Angeles 1990 eq. 17). A C-space singularity
(a branch point, where two branches cross) is a zero of both, found the same
way.

**C-space singularities, searched for.** Besides the C-space points the
traced curves pass through, 1- and 2-dof loci with the kind ``cspace`` search
for them deliberately (:func:`search_cspace`): σ_r, the r-th singular value
of DΦ·diag(s) (r the constraint rank of M's regular points), vanishes on M
exactly at the C-space singularities (Park & Kim 1999, Section 3), so from
the points where σ_r is locally smallest — over the assembled grid (2 dof),
along the traced branches (1 dof) — Gauss–Newton on ``(Φ, σ_r)`` finds the
C-space singularities near them whether or not an actuator or end-effector
locus passes through them. The coverage's ``cspace_search`` counts the
seeds, the points found and those the classification confirms.

**Confirmation.** Every point traced for a kind is classified
(:func:`classify.classify_many`, one batch); the points the classification
does not find singular of that kind are dropped (their count is in the
coverage), and split the piece there. Points classified C-space singular
are reported as branch points.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["default_columns", "TOLERANCE", "STEP_LIMIT", "SECTION_COUNT", "LocusPiece", "Loci",
           "sign_functions", "trace_loci", "TRACEABLE_KINDS", "locus_coordinates", "cspace_function", "search_cspace",
           "CSPACE_TOLERANCE", "CSPACE_ITERATIONS", "redundant_actuator_function", "sign_magnitudes", "ZERO_TOLERANCE"]

#: ‖(Φ, s)‖ of a corrected locus point
TOLERANCE = 1e-11
#: most predictor–corrector steps along one curve, each way
STEP_LIMIT = 1500
#: the kinds a sign function exists for (C-space points are found as zeros of both)
TRACEABLE_KINDS = ("actuator", "end_effector")
#: ‖(Φ, σ_r)‖ of a C-space singularity found by :func:`search_cspace` (σ_r's gradient is a difference quotient
#: of DΦ, step 1e-6, whose error keeps σ_r from falling much below 1e-9), and the most Gauss–Newton steps to it
CSPACE_TOLERANCE = 1e-8
CSPACE_ITERATIONS = 200
#: a sign function vanishes at a configuration where its magnitude (:func:`sign_magnitudes`, Hadamard's ratio
#: ``|det A| / ∏ ‖A_i‖`` in [0, 1]) is at most this: a zero at a sample, or, at every point of a traced branch of
#: M, a branch singular everywhere (rounding leaves about 1e-16 there)
ZERO_TOLERANCE = 1e-9
#: sections of a 3-dof locus when the caller gives no count
SECTION_COUNT = 4
#: finite-difference step of ∇s (dimensionless)
_DIFFERENCE = 1e-6


@dataclass(frozen=True, eq=False)
class LocusPiece:
    """One piece of a locus.

    Attributes
    ----------
    kind : str
        ``"actuator"``, ``"end_effector"`` or ``"cspace"``.
    points : ndarray, shape=[n, point_size]
        Configurations in order along the curve (one for an isolated point).
    closed : bool
        Whether the curve comes back to its first point.
    residuals : ndarray, shape=[n]
        ‖(Φ, s)‖ at each point (3 dof: ‖(Φ, s, x_c − c)‖).
    section : float or None
        3 dof: the value c of the section coordinate x_c the piece lies in (a displacement from home);
        None for 1 and 2 dof.
    whole_branch : bool
        1 dof: the piece is a traced branch of M (or a part of it the classification confirms) along which the
        kind's sign function vanishes identically: its magnitude (:func:`sign_magnitudes`) is at most
        :data:`ZERO_TOLERANCE` at every point (e.g. the slider-crank with crank = coupler, whose slider stays at
        the crank's pivot on one branch: Park & Kim 1999 Fig. 3a; Gosselin & Angeles 1990 eq. 17).
    """

    kind: str
    points: np.ndarray
    closed: bool
    residuals: np.ndarray
    section: object = None
    whole_branch: bool = False


@dataclass(frozen=True, eq=False)
class Loci:
    """The loci of a mechanism and how much of M they cover.

    Attributes
    ----------
    pieces : tuple of LocusPiece
    branches : tuple of LocusPiece
        1 dof: the traced curves of M (kind ``"branch"``); 2 dof: empty.
    samples : ndarray, shape=[n, point_size]
        The points of M the search started from (the reached points of the assembled grid, every section's
        for 3 dof, or the sampled points).
    sample_signs : ndarray, shape=[n, 2]
        The signs of s_a and s_e at the samples (0 where not defined): the assembly and working modes.
    sample_branches : ndarray of int, shape=[n]
        2 dof: the assembly branch of the grid each sample is on (0 the start's; others with
        ``assembly_branches`` > 1 in :func:`trace_loci`); 1 and 3 dof: 0.
    coverage : dict
        ``dof``, ``grid`` (names and counts, 2 and 3 dof), ``reached`` grid points, ``seeds``, ``pieces``,
        ``closed`` per piece, ``unconfirmed`` (points dropped per kind), ``not_traced`` (kinds and why),
        ``tolerance``, ``step``; 2 and 3 dof: ``start`` (``singular``, ``moved``, ``margin``, ``tolerance``:
        :meth:`classify.grid_continuation.StartingPoint.to_dict`); 2 dof with ``assembly_branches`` > 1:
        ``assembly_branches`` (``found``, ``reached`` per branch, ``solutions`` the probes found, ``asked``); 1 dof:
        ``whole_branch`` (per branch singular everywhere: ``kind``, ``branch``, ``points``, ``largest``
        magnitude, ``tolerance``); 3 dof: ``section`` ({name: [a, b, n]}) and ``sections`` (per section its
        ``value``, grid points ``reached``, ``seeds`` and ``pieces`` per kind); 1 and 2 dof with ``cspace``:
        ``cspace_search`` (``seeds``, ``found``, ``confirmed``); redundant actuation: ``actuator_search`` (the same).
    """

    pieces: tuple
    branches: tuple
    samples: np.ndarray
    sample_signs: np.ndarray
    coverage: dict = field(default_factory=dict)
    sample_branches: np.ndarray = None


# ------------------------------------------------------------------------------------------------ sign functions

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
    :func:`trace_loci`).

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


def _gradient(ambient, function, points):
    """∇s in the tangent coordinates by central differences, shape=[n, k]."""
    points = np.atleast_2d(points)
    k, scales = ambient.dim, ambient.tangent_scales
    steps = np.eye(k) * (_DIFFERENCE * scales)
    forward = ambient.retract(points[:, None, :], steps[None])
    backward = ambient.retract(points[:, None, :], -steps[None])
    values = function(np.concatenate([forward, backward], axis=1).reshape(-1, points.shape[-1]))
    values = values.reshape(len(points), 2, k)
    return (values[:, 0] - values[:, 1]) / (2 * _DIFFERENCE * scales)


def _curve_manifold(model, function, section=None):
    """The implicit manifold {Φ = 0, s = 0} (or M itself when `function` is None); with a `section` function h
    (3 dof, :func:`_section_function`) the curve {Φ = 0, s = 0, h = 0}."""
    from manifold import ImplicitManifold

    manifold = model.manifold
    if function is None:
        return manifold
    functions = [function] if section is None else [function, section]

    def constraint(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        extra = np.stack([extra_function(flat) for extra_function in functions], axis=-1)
        return np.concatenate([manifold.constraint(points), extra.reshape(points.shape[:-1] + (len(functions),))],
                              axis=-1)

    def jacobian(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        gradients = [_gradient(manifold.ambient, extra_function, flat)[:, None, :] for extra_function in functions]
        rows = np.concatenate([np.asarray(manifold.constraint_jacobian(flat), dtype=float).reshape(
            len(flat), -1, manifold.ambient.dim)] + gradients, axis=1)
        return rows.reshape(points.shape[:-1] + rows.shape[-2:])

    return ImplicitManifold(ambient=manifold.ambient, constraint=constraint, constraint_jacobian=jacobian,
                            is_solution=manifold.is_solution)


def _section_function(mechanism, column, value):
    """h(p) = x_c(p) − c, the section coordinate's displacement from home minus the section's value (an angle's
    difference wrapped to [−π, π)), shape=[n]."""
    from .displacements import displacements_of

    angle = _is_angle(mechanism, column)

    def section(points):
        difference = displacements_of(mechanism, points)[:, column] - value
        return (difference + np.pi) % (2 * np.pi) - np.pi if angle else difference

    return section


def cspace_function(model, rank):
    """σ_r(p), the r-th largest singular value of DΦ(p)·diag(s), and its gradient on the ambient space.

    Zero on M iff rank DΦ < r, r the constraint rank of M's regular points: a
    C-space singularity (Park & Kim 1999, Section 3). Its gradient in the
    tangent coordinates is ``∂_j σ_r = u_rᵀ ∂_j(DΦ·diag(s)) v_r`` (u_r, v_r the
    singular vectors of σ_r; ∂_j DΦ by central differences, step 1e-6,
    dimensionless), the derivative of σ_r wherever it is a simple singular
    value, and a one-sided one at σ_r = 0.

    Parameters
    ----------
    model : Model
    rank : int
        r (the survey's constraint rank).

    Returns
    -------
    value : callable
        ``value(points [n, point_size]) -> [n]``.
    gradient : callable
        ``gradient(points [n, point_size]) -> [n, k]``.
    """
    manifold = model.manifold
    scales = manifold.ambient.tangent_scales

    def jacobian(points):
        return np.asarray(manifold.constraint_jacobian(points), dtype=float) * scales

    return _singular_value_function(manifold.ambient, jacobian, rank)


def redundant_actuator_function(model):
    """σ_k(p), the k-th (smallest) singular value of ``[DΦ(p)·diag(s); U·diag(s)]``, and its gradient.

    U the unit actuator rows (as :func:`sign_functions`). With more actuated
    coordinates than degrees of freedom (redundant actuation: r + a > k) the
    stacked matrix is not square, and the actuator singularities — ker DΦ ∩
    ker Dπ ≠ 0, a motion with every actuator still (Park & Kim 1999,
    Section 3) — are where its rank drops below k: the zeros of σ_k on M,
    which does not change sign there (so they are searched for, as the
    C-space singularities are, not traced by a sign change).

    Parameters
    ----------
    model : Model

    Returns
    -------
    value : callable
        ``value(points [n, point_size]) -> [n]``.
    gradient : callable
        ``gradient(points [n, point_size]) -> [n, k]`` (as :func:`cspace_function`).
    """
    from .survey import unit_actuator_rows

    manifold = model.manifold
    scales = manifold.ambient.tangent_scales
    actuators = unit_actuator_rows(model)[0] * scales

    def stacked(points):
        points = np.asarray(points, dtype=float)
        constraint_rows = np.asarray(manifold.constraint_jacobian(points), dtype=float) * scales
        return np.concatenate([constraint_rows, np.broadcast_to(actuators, points.shape[:-1] + actuators.shape)],
                              axis=-2)

    return _singular_value_function(manifold.ambient, stacked, manifold.ambient.dim)


def _singular_value_function(ambient, matrix, index):
    """The `index`-th largest singular value of ``matrix(points)`` [n, rows, k] and its gradient
    ``u_iᵀ ∂_j matrix v_i`` (∂_j by central differences, step 1e-6 dimensionless)."""
    scales = ambient.tangent_scales

    def value(points):
        return np.linalg.svd(matrix(np.atleast_2d(points)), compute_uv=False)[:, index - 1]

    def gradient(points):
        points = np.atleast_2d(points)
        left, _, right = np.linalg.svd(matrix(points))
        steps = np.eye(ambient.dim) * (_DIFFERENCE * scales)
        forward = matrix(ambient.retract(points[:, None, :], steps[None]))
        backward = matrix(ambient.retract(points[:, None, :], -steps[None]))
        derivative = (forward - backward) / (2 * _DIFFERENCE * scales)[None, :, None, None]
        return np.einsum("nc,njcd,nd->nj", left[:, :, index - 1], derivative, right[:, index - 1, :])

    return value, gradient


def _zero_manifold(model, value, gradient):
    """{Φ = 0, σ = 0} (σ a singular-value function: :func:`cspace_function`, :func:`redundant_actuator_function`)
    as an implicit manifold, for the Gauss–Newton corrector."""
    from manifold import ImplicitManifold

    manifold = model.manifold

    def constraint(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        rows = np.concatenate([np.asarray(manifold.constraint(flat), dtype=float), value(flat)[:, None]], axis=-1)
        return rows.reshape(points.shape[:-1] + rows.shape[-1:])

    def jacobian(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        rows = np.concatenate([np.asarray(manifold.constraint_jacobian(flat), dtype=float).reshape(
            len(flat), -1, manifold.ambient.dim), gradient(flat)[:, None, :]], axis=1)
        return rows.reshape(points.shape[:-1] + rows.shape[-2:])

    return ImplicitManifold(ambient=manifold.ambient, constraint=constraint, constraint_jacobian=jacobian,
                            is_solution=manifold.is_solution)


def search_cspace(model, survey, seeds, step):
    """C-space singularities searched for from seed configurations: each seed corrected onto {Φ = 0, σ_r = 0}.

    Gauss–Newton (:func:`manifold.project`, steps of at most 4 `step`) on
    ``(Φ, σ_r)`` (:func:`cspace_function`) from each seed, to ``‖(Φ, σ_r)‖ ≤``
    :data:`CSPACE_TOLERANCE` in at most :data:`CSPACE_ITERATIONS` steps
    (at a C-space singularity, where branches cross, the Jacobian of
    ``(Φ, σ_r)`` loses rank and Gauss–Newton converges only linearly, halving
    σ_r about every other step), then Φ to :data:`TOLERANCE` on M; a seed
    whose corrector fails, or that lands within `step` of a point already
    found, gives nothing. A search, not a trace:
    it finds the C-space singularities near the seeds whether or not an
    actuator or end-effector locus passes through them (the caller confirms
    them with the classification).

    Parameters
    ----------
    model : Model
    survey : Survey
    seeds : ndarray, shape=[n, point_size]
        Configurations on (or near) M: local minima of σ_r over a grid or along a branch.
    step : float
        Dimensionless: the corrector's step bound / 4, and the distance under which two points are one.

    Returns
    -------
    points : ndarray, shape=[m, point_size]
    residuals : ndarray, shape=[m]
        ``‖(Φ, σ_r)‖`` at each.
    """
    return _search_zeros(model, *cspace_function(model, survey.constraint_rank), seeds, step)


def _search_zeros(model, value, gradient, seeds, step):
    """The zeros on M of a singular-value function near the seeds (:func:`search_cspace`)."""
    from manifold import ProjectionError, project

    curve = _zero_manifold(model, value, gradient)
    ambient = curve.ambient
    found = []
    for seed in np.atleast_2d(seeds):
        try:
            on = project(curve, seed, tolerance=CSPACE_TOLERANCE, max_iterations=CSPACE_ITERATIONS,
                         max_step=4 * step)
            on = project(model.manifold, on, tolerance=TOLERANCE)  # Φ to the loci's tolerance (a move ≪ 1e-8)
        except ProjectionError:
            continue
        if (curve.is_solution is not None and not curve.is_solution(on)) or (found and _distances(ambient, on[None], np.array(found))[0] < step):
            continue
        found.append(on)
    points = np.array(found).reshape(-1, ambient.point_size)
    return points, _residuals(curve, points) if len(points) else np.zeros(0)


# ------------------------------------------------------------------------------------------------ curves

def _correct(curve, point, max_step=None):
    """The point of the curve nearest `point` by Gauss–Newton, or None."""
    from manifold import ProjectionError, project

    try:
        corrected = project(curve, point, tolerance=TOLERANCE, max_step=max_step)
    except ProjectionError:
        return None
    if curve.is_solution is not None and not curve.is_solution(corrected):
        return None
    return corrected


def _null_direction(curve, point, previous):
    """The unit (dimensionless) null vector of the curve's Jacobian, oriented along `previous`."""
    scales = curve.ambient.tangent_scales
    jacobian = np.asarray(curve.constraint_jacobian(point), dtype=float) * scales
    _, values, right = np.linalg.svd(jacobian, full_matrices=True)
    direction = right[-1]
    if previous is None:
        return direction
    dot = direction @ previous
    if abs(dot) < 0.7:  # near a crossing the null space is not one line: go straight on
        return previous
    return direction if dot > 0 else -direction


def _walk(curve, start, direction, step):
    """Follow a curve from `start` along `direction` (dimensionless); (points after start, closed)."""
    ambient = curve.ambient
    scales = ambient.tangent_scales
    points, current, size = [], start, step
    farthest = 0.0
    for _ in range(STEP_LIMIT):
        corrected = None
        while size >= step / 16:
            guess = ambient.retract(current, size * scales * direction)
            corrected = _correct(curve, guess, max_step=size)
            if corrected is not None:
                secant = ambient.inverse_retract(current, corrected) / scales
                advance = np.linalg.norm(secant)
                if 0.25 * size <= advance <= 2.0 * size and secant @ direction > 0.5 * advance:
                    break
            corrected, size = None, size / 2
        if corrected is None:
            return points, False
        points.append(corrected)
        direction = _null_direction(curve, corrected, secant / advance)
        current, size = corrected, min(step, 2 * size)
        distance = np.linalg.norm(ambient.inverse_retract(start, corrected) / scales)
        farthest = max(farthest, distance)
        if farthest > 3 * step and distance < 1.5 * step:
            return points, True
    return points, False


def _trace(curve, start, step):
    """The whole curve through a point of it, in order; (points [n, point_size], closed)."""
    direction = _null_direction(curve, start, None)
    forward, closed = _walk(curve, start, direction, step)
    if closed:
        return np.array([start] + forward), True
    backward, _ = _walk(curve, start, -direction, step)
    return np.array(backward[::-1] + [start] + forward), False


def _distances(ambient, points, others):
    """Dimensionless distance from each of `points` to the nearest of `others`, shape=[n]."""
    if not len(others) or not len(points):
        return np.full(len(points), np.inf)
    differences = ambient.inverse_retract(points[:, None, :], others[None, :, :]) / ambient.tangent_scales
    return np.linalg.norm(differences, axis=-1).min(axis=1)


def _trace_from_seeds(curve, seeds, step):
    """The curves through the seeds (each seed corrected onto the curve first; seeds on a traced curve skipped)."""
    ambient = curve.ambient
    traced = []
    for seed in seeds:
        on = _correct(curve, seed, max_step=4 * step)
        if on is None:
            continue
        if any(_distances(ambient, on[None], points)[0] < 2 * step for points, _ in traced):
            continue
        traced.append(_trace(curve, on, step))
    return traced


# ------------------------------------------------------------------------------------------------ seeds

def _grid_seeds(points, reached, shape, values, zeros=None):
    """The seed points of a 2-D grid: per kind, the reached points where s vanishes (`zeros`, kind → bool [n]),
    the endpoint of smaller |s| of each sign-changing edge, and the reached end of each edge to an unreached point
    (for every kind)."""
    from .grid_continuation import grid_neighbours

    neighbours = grid_neighbours(shape)
    seeds = {kind: list(points[reached & zeros[kind]]) if zeros else [] for kind in values}
    for index in np.flatnonzero(reached):
        for other in neighbours[index, 1::2]:  # one step forward along each axis
            if other < 0:
                continue
            if not reached[other]:
                for kind in values:
                    seeds[kind].append(points[index])
                continue
            for kind, value in values.items():
                if value[index] * value[other] < 0:
                    seeds[kind].append(points[index] if abs(value[index]) < abs(value[other]) else points[other])
        for other in neighbours[index, 0::2]:  # the unreached point one step back
            if other >= 0 and not reached[other]:
                for kind in values:
                    seeds[kind].append(points[index])
    return {kind: np.array(found).reshape(-1, points.shape[-1]) for kind, found in seeds.items()}


def _sign_changes(curve_points, function, magnitude, closed):
    """Points of a traced curve just before a sign change of s (a closed curve: also from its last point to its
    first), and those where s vanishes (its magnitude at most :data:`ZERO_TOLERANCE`, where the sign of s is
    rounding), shape=[n, point_size]."""
    values = function(curve_points)
    following = np.roll(values, -1)
    change = values * following < 0
    if not closed:
        change[-1] = False
    change |= magnitude(curve_points) <= ZERO_TOLERANCE
    return curve_points[change]


# ------------------------------------------------------------------------------------------------ confirmation

def _confirmed(model, survey, kind, points, residuals, closed, section=None, whole_branch=False):
    """Split a traced curve where `classify` does not confirm the kind; (pieces, dropped, cspace points)."""
    from .batch import classify_many
    from .report import KINDS

    result = classify_many(model, points, survey=survey)
    good = result.singular[:, KINDS.index(kind)]
    cspace = points[result.singular[:, KINDS.index("cspace")]]
    pieces = []
    runs = np.split(np.arange(len(points)), np.flatnonzero(np.diff(good.astype(int)) != 0) + 1)
    for run in runs:
        if len(run) and good[run[0]]:
            pieces.append(LocusPiece(kind, points[run], bool(closed and good.all()), residuals[run], section,
                                     whole_branch))
    return pieces, int((~good).sum()), cspace


def _residuals(curve, points):
    return np.linalg.norm(curve.constraint(points), axis=-1)


# ------------------------------------------------------------------------------------------------ entry point

def trace_loci(mechanism, start, columns=None, ranges=None, counts=(24, 24), kinds=("actuator", "end_effector"),
               rng=None, survey=None, sample_count=24, assembly_branches=1):
    """Trace the singularity loci of a 1-, 2- or 3-dof mechanism (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        A configuration of M (its branch is the grid's).
    columns : sequence of int, optional
        2 dof: the two tangent coordinates of the grid; 3 dof: the grid's two then the section coordinate
        (default :func:`default_columns`). 1 dof: ignored.
    ranges : sequence of (float, float) or None, optional
        2 and 3 dof: the range per coordinate, displacements from home; a None entry (or a missing third) is
        defaulted: (−π, π) for angles, ±2 characteristic lengths for lengths, around the start's values; a
        section angle's default is a turn without its end, so its n sections are evenly spaced around it.
    counts : (int, int) or (int, int, int)
        Grid points per axis (≥ 2); 3 dof: then the number of sections (default :data:`SECTION_COUNT`).
    kinds : sequence of str
        Among ``actuator``, ``end_effector`` and ``cspace`` (C-space points: the points of the traced curves
        that classify finds C-space singular, and, for 1 and 2 dof, those :func:`search_cspace` finds).
    rng : numpy.random.Generator, optional
        For the sampling of M (1 dof), the regular reference near a singular start and the probes of the
        assembly branches; default seeded 0.
    survey : Survey, optional
        The model's survey (default computed once per model).
    sample_count : int
        1 dof: random points projected onto M, and random-walk steps, to find its branches.
    assembly_branches : int
        2 dof: the most assembly branches the grid is assembled on
        (:func:`classify.grid_continuation.assemble_branches`: the start's, then those the loops' solutions from
        random values at a few grid points lead to, drawn from `rng`); the loci are traced from the seeds of all
        of them. Default 1: the start's branch only.

    Returns
    -------
    Loci
    """
    from manifold import sample_manifold

    from .model import model_of
    from .survey import survey_of

    model = model_of(mechanism)
    survey = survey_of(model) if survey is None else survey
    rng = np.random.default_rng(0) if rng is None else rng
    manifold = model.manifold
    ambient = manifold.ambient
    from mechanisms import CLOSURE_TOLERANCE, ConfigurationError
    from mechanisms.kinematics import closes

    from .report import KINDS

    start = np.asarray(start, dtype=float)
    if start.shape != (ambient.point_size,) or not bool(closes(mechanism, start, CLOSURE_TOLERANCE)):
        raise ConfigurationError(f"trace_loci: the start is not a configuration of M (shape {start.shape}; it must "
                                 f"close the loops, |Φ| ≤ {CLOSURE_TOLERANCE:g}): project it first")
    unknown = sorted(set(kinds) - set(KINDS)) if not isinstance(kinds, str) else [kinds]
    if unknown:
        raise ValueError(f"trace_loci: kinds must be a sequence of {', '.join(KINDS)}, got {unknown}")
    dof = int(ambient.dim - survey.constraint_rank)
    if dof not in (1, 2, 3):
        raise ValueError(f"loci are traced for 1-, 2- and 3-dof mechanisms; this one has {dof} dof")
    reference = _regular_reference(model, survey, start, rng)
    functions, refused = sign_functions(model, reference)
    magnitudes = sign_magnitudes(model, reference)
    redundant = len(model.actuators) > dof  # more actuated coordinates than degrees of freedom
    traced_kinds = [kind for kind in TRACEABLE_KINDS if kind in functions
                    and (kind in kinds or "cspace" in kinds)]
    not_traced = {kind: refused[kind] for kind in kinds if kind in refused}
    coverage = {"dof": dof, "tolerance": TOLERANCE, "not_traced": not_traced}
    pieces, branches, unconfirmed, branch_points = [], [], {}, []

    if dof in (2, 3):
        columns, ranges, counts = _grid_arguments(mechanism, start, columns, ranges, counts, dof)
        grids, masks, step = _trace_sections(mechanism, model, survey, start, columns, ranges, counts, functions,
                                             magnitudes, traced_kinds, kinds, coverage, pieces, unconfirmed,
                                             branch_points, assembly_branches if dof == 2 else 1, rng)
        samples = np.concatenate([grid[mask] for grid, mask in zip(grids, masks)])
        sample_branches = np.concatenate([np.full(int(mask.sum()), branch) for branch, mask in enumerate(masks)])

        def minima(function):
            return np.concatenate([_grid_minima(function, grid, mask, tuple(counts))
                                   for grid, mask in zip(grids, masks)])
    else:
        samples = sample_manifold(manifold, rng, start[None], random_count=sample_count, walk_count=sample_count)
        step = 0.05
        coverage.update({"samples": int(len(samples)), "step": step})
        traced = _trace_from_seeds(manifold, samples, step)
        for index, (points, closed) in enumerate(traced):
            branches.append(LocusPiece("branch", points, closed, _residuals(manifold, points)))
        whole_branches = []
        for kind in traced_kinds:
            curve = _curve_manifold(model, functions[kind])
            candidates = []
            for index, (points, closed) in enumerate(traced):
                magnitude = magnitudes[kind](points)
                if magnitude.max() > ZERO_TOLERANCE:
                    candidates += list(_sign_changes(points, functions[kind], magnitudes[kind], closed))
                    continue
                # s vanishes identically along this branch: the whole branch is the locus
                found, dropped, cspace = _confirmed(model, survey, kind, points, _residuals(curve, points), closed,
                                                    whole_branch=True)
                unconfirmed[kind] = unconfirmed.get(kind, 0) + dropped
                branch_points += list(cspace)
                whole_branches.append({"kind": kind, "branch": index, "points": int(len(points)),
                                       "largest": float(magnitude.max()), "tolerance": ZERO_TOLERANCE})
                if kind in kinds:
                    pieces += found
            found_points = []
            for candidate in candidates:
                on = _correct(curve, candidate, max_step=4 * step)
                if on is not None and not (found_points and _distances(ambient, on[None],
                                                                       np.array(found_points))[0] < 1e-6):
                    found_points.append(on)
            for on in found_points:
                found, dropped, cspace = _confirmed(model, survey, kind, on[None], _residuals(curve, on[None]), False)
                unconfirmed[kind] = unconfirmed.get(kind, 0) + dropped
                branch_points += list(cspace)
                if kind in kinds:
                    pieces += found
        coverage["branches"] = len(branches)
        coverage["whole_branch"] = [record for record in whole_branches if record["kind"] in kinds]
        coverage["branches_closed"] = [branch.closed for branch in branches]

        def minima(function):
            return _branch_minima(function, [branch.points for branch in branches], ambient.point_size)
    if dof in (1, 2) and "cspace" in kinds:
        function = cspace_function(model, survey.constraint_rank)
        branch_points[:0] = _searched(model, survey, "cspace", function, minima(function[0]), step, coverage)
    if dof in (1, 2) and "actuator" in kinds and "actuator" not in functions and redundant:
        function = redundant_actuator_function(model)
        found = _searched(model, survey, "actuator", function, minima(function[0]), step, coverage)
        pieces += [LocusPiece("actuator", point[None], False, _residuals(_zero_manifold(model, *function),
                                                                          point[None])) for point in found]
        not_traced["actuator"] += "; searched for as points (the zeros of the stacked matrix's k-th singular value)"
    if "cspace" in kinds:
        unique = []
        for candidate in branch_points:
            if not unique or _distances(ambient, candidate[None], np.array(unique))[0] > step:
                unique.append(candidate)
        pieces += [LocusPiece("cspace", candidate[None], False, _residuals(manifold, candidate[None]),
                              _section_of(mechanism, columns, coverage, candidate) if dof == 3 else None)
                   for candidate in unique]
    signs = np.zeros((len(samples), 2))
    for column, kind in enumerate(TRACEABLE_KINDS):
        if kind in functions and len(samples):
            signs[:, column] = np.sign(functions[kind](samples))
    coverage.update({"pieces": {kind: sum(piece.kind == kind for piece in pieces) for kind in kinds},
                     "closed": [piece.closed for piece in pieces], "unconfirmed": unconfirmed})
    if dof == 1:
        sample_branches = np.zeros(len(samples), dtype=int)
    return Loci(tuple(pieces), tuple(branches), samples, signs, coverage, sample_branches.astype(int))


def _trace_sections(mechanism, model, survey, start, columns, ranges, counts, functions, magnitudes, traced_kinds,
                    kinds, coverage, pieces, unconfirmed, branch_points, assembly_branches=1, rng=None):
    """2 and 3 dof: the grid assembled (on up to `assembly_branches` branches), its seeds, and the curves traced
    from them, section by section (one section, without a section constraint, for 2 dof); fills `coverage`,
    `pieces`, `unconfirmed`, `branch_points`; returns (grid points per branch [b, n, point_size], reached
    [b, n], step)."""
    ambient = model.manifold.ambient
    grids, masks, starting, solutions = _assembled_grid(mechanism, start, columns[2:] + columns[:2],
                                                        ranges[2:] + ranges[:2], counts[2:] + counts[:2],
                                                        assembly_branches, rng)
    coverage["start"] = starting.to_dict()
    if assembly_branches > 1:
        coverage["assembly_branches"] = {"found": int(len(grids)), "reached": [int(mask.sum()) for mask in masks],
                                         "solutions": int(solutions), "asked": int(assembly_branches)}
    spacing = min((high - low) / max(count - 1, 1) / ambient.tangent_scales[column]
                  for column, (low, high), count in zip(columns[:2], ranges[:2], counts[:2]))
    step = spacing / 2
    full_values = {kind: np.zeros(masks.shape) for kind in traced_kinds}
    zeros = {kind: np.zeros(masks.shape, dtype=bool) for kind in traced_kinds}
    for kind in traced_kinds:
        for branch, (samples, reached) in enumerate(zip(grids, masks)):
            if reached.any():
                full_values[kind][branch, reached] = functions[kind](samples[reached])
                zeros[kind][branch, reached] = magnitudes[kind](samples[reached]) <= ZERO_TOLERANCE
    reached, samples = masks.any(axis=0), grids[0]
    sections = [None] if len(columns) == 2 else np.linspace(ranges[2][0], ranges[2][1], counts[2]).tolist()
    size = counts[0] * counts[1]
    seed_counts = {kind: 0 for kind in traced_kinds}
    per_section = []
    for index, value in enumerate(sections):
        part = slice(index * size, (index + 1) * size)
        seeds = {kind: [] for kind in traced_kinds}
        for branch, (branch_samples, branch_reached) in enumerate(zip(grids, masks)):
            found = _grid_seeds(np.nan_to_num(branch_samples[part]), branch_reached[part], tuple(counts[:2]),
                                {kind: full_values[kind][branch, part] for kind in traced_kinds},
                                {kind: zeros[kind][branch, part] for kind in traced_kinds})
            for kind in traced_kinds:
                seeds[kind].append(found[kind])
        seeds = {kind: np.concatenate(found) for kind, found in seeds.items()}
        section = None if value is None else _section_function(mechanism, columns[2], value)
        found_here = {kind: 0 for kind in kinds}
        for kind in traced_kinds:
            seed_counts[kind] += len(seeds[kind])
            curve = _curve_manifold(model, functions[kind], section)
            for points, closed in _trace_from_seeds(curve, seeds[kind], step):
                found, dropped, cspace = _confirmed(model, survey, kind, points, _residuals(curve, points), closed,
                                                    value)
                unconfirmed[kind] = unconfirmed.get(kind, 0) + dropped
                branch_points += list(cspace)
                if kind in kinds:
                    pieces += found
                    found_here[kind] += len(found)
        if value is not None:
            per_section.append({"value": value, "reached": int(reached[part].sum()),
                                "seeds": {kind: int(len(seeds[kind])) for kind in traced_kinds},
                                "pieces": {kind: count for kind, count in found_here.items() if kind != "cspace"}})
    names = [mechanism.coordinate_names[column] for column in columns]
    coverage.update({"grid": {name: [low, high, count] for name, (low, high), count
                              in zip(names[:2], ranges[:2], counts[:2])},
                     "reached": int(masks[0].sum()), "grid_points": int(len(samples)),
                     "seeds": {kind: int(count) for kind, count in seed_counts.items()}, "step": step})
    if len(columns) == 3:
        coverage["section"] = {names[2]: [ranges[2][0], ranges[2][1], counts[2]]}
        coverage["sections"] = per_section
    return grids, masks, step


def _section_of(mechanism, columns, coverage, point):
    """The section value (of ``coverage["sections"]``) a 3-dof point lies in: the nearest to its section
    coordinate."""
    values = np.array([entry["value"] for entry in coverage["sections"]])
    offset = _section_function(mechanism, columns[2], 0.0)(point[None])[0] - values
    if _is_angle(mechanism, columns[2]):
        offset = (offset + np.pi) % (2 * np.pi) - np.pi
    return float(values[np.argmin(np.abs(offset))])


def _grid_minima(value, grid, reached, shape):
    """The reached grid points where `value` (a singular-value function) is no larger than at any reached
    neighbour, smallest first, shape=[n, point_size]."""
    from .grid_continuation import grid_neighbours

    values = np.full(len(grid), np.inf)
    if reached.any():
        values[reached] = value(grid[reached])
    neighbours = grid_neighbours(shape)
    around = np.where(neighbours >= 0, values[np.maximum(neighbours, 0)], np.inf)
    minima = np.flatnonzero(reached & (values <= around.min(axis=1)))
    return grid[minima[np.argsort(values[minima], kind="stable")]]


def _branch_minima(value, branches, point_size):
    """The points of traced branches of M where `value` is no larger than at the points before and after."""
    seeds = []
    for points in branches:
        values = value(points)
        before, after = np.roll(values, 1), np.roll(values, -1)
        before[0], after[-1] = np.inf, np.inf
        seeds += list(points[(values <= before) & (values <= after)])
    return np.array(seeds).reshape(-1, point_size)


def _searched(model, survey, kind, functions, seeds, step, coverage):
    """The zeros of a singular-value function found from `seeds` (:func:`search_cspace`) that the classification
    confirms of `kind` (a list of points); the counts go in ``coverage[kind + "_search"]``."""
    from .batch import classify_many
    from .report import KINDS

    points, _ = _search_zeros(model, *functions, seeds, step) if len(seeds) else (np.zeros((0, 0)), None)
    confirmed = []
    if len(points):
        confirmed = list(points[classify_many(model, points, survey=survey).singular[:, KINDS.index(kind)]])
    coverage[f"{kind}_search"] = {"seeds": int(len(seeds)), "found": int(len(points)), "confirmed": len(confirmed)}
    return confirmed


def _regular_reference(model, survey, start, rng):
    """`start` where DΦ has the survey's rank there, else the first such point of M sampled from it (the kept
    constraint rows are chosen at a regular point)."""
    from manifold import numerical_rank, sample_manifold, scaled_jacobian

    def regular(point):
        return numerical_rank(scaled_jacobian(model.manifold, point)).rank >= survey.constraint_rank

    if regular(start):
        return start
    for candidate in sample_manifold(model.manifold, rng, start[None], random_count=8, walk_count=8):
        if regular(candidate):
            return candidate
    raise ValueError("no configuration of M near the start where DΦ has its largest rank")


def _whole(value):
    """Whether `value` is an integer (not a bool, a float or text)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def _grid_arguments(mechanism, start, columns, ranges, counts, dof=2):
    """The grid's columns, ranges and counts with their defaults (see :func:`trace_loci`): 2 dof two axes; 3 dof
    three, the last the section coordinate."""
    from mechanisms.kinematics import kinematics_of

    from .displacements import displacements_of

    size = len(mechanism.coordinate_names)
    if columns is not None and not all(_whole(column) and 0 <= column < size for column in columns):
        raise ValueError(f"a locus grid's columns are coordinate numbers from 0 to {size - 1}, got {list(columns)}")
    columns = default_columns(mechanism, dof, start) if columns is None else [int(column) for column in columns]
    if len(columns) != dof:
        axes = "two grid axes and a section" if dof == 3 else "two grid axes"
        raise ValueError(f"a {dof}-dof locus grid has {dof} coordinates ({axes}), got {len(columns)}")
    if len(set(columns)) != len(columns):
        raise ValueError(f"a locus grid names a coordinate twice: {columns}")
    if isinstance(counts, (str, bytes)) or not all(_whole(count) for count in counts):
        raise ValueError(f"a locus grid's counts are whole numbers, got {counts!r}")
    counts = [int(count) for count in counts]
    if dof == 3 and len(counts) == 2:
        counts.append(SECTION_COUNT)
    if len(counts) != dof or min(counts[:2]) < 2 or min(counts) < 1:
        raise ValueError(f"a {dof}-dof locus grid needs {dof} counts (the grid's ≥ 2), got {counts}")
    if ranges is None:
        ranges = [None] * dof
    if len(ranges) > dof or not all(pair is None or (len(pair) == 2 and all(np.isfinite(value) for value in pair))
                                    for pair in ranges):
        raise ValueError(f"a {dof}-dof locus grid has at most {dof} ranges, each None or two finite numbers (low, "
                         f"high), got {ranges!r}")
    ranges = list(ranges) + [None] * (dof - len(ranges))
    values = displacements_of(mechanism, start[None])[0]
    scales = kinematics_of(mechanism).ambient.tangent_scales
    for axis, column in enumerate(columns):
        if ranges[axis] is not None:
            continue
        if _is_angle(mechanism, column):
            # a turn around the start; sections evenly around it without the turn's end (the start again)
            last = np.pi - (2 * np.pi / counts[axis] if axis == 2 else 0.0)
            ranges[axis] = (values[column] - np.pi, values[column] + last)
        else:
            ranges[axis] = (values[column] - 2 * scales[column], values[column] + 2 * scales[column])
    ranges = [tuple(map(float, pair)) for pair in ranges]
    if dof == 3 and counts[2] == 1 and ranges[2][0] != ranges[2][1]:
        raise ValueError(f"one section has one value: its range must be a single value, got {ranges[2]}")
    return columns, ranges, counts


def _is_angle(mechanism, column):
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    for factor, part in zip(ambient.factors, ambient.tangent_slices):
        if part.start <= column < part.stop:
            return factor != "R"
    return False


def _assembled_grid(mechanism, start, columns, ranges, counts, assembly_branches=1, rng=None):
    """The grid assembled by continuation from `start` (:func:`classify.grid_continuation.assemble_branches`; a
    singular start reaching nothing: from its regular neighbour); (points [b, n, point_size], reached [b, n],
    StartingPoint, distinct solutions the probes found)."""
    from .grid_continuation import Grid, assemble_branches, grid_targets, held_columns

    grid = Grid(tuple(mechanism.coordinate_names[column] for column in columns), tuple(columns),
                tuple(low for low, _ in ranges), tuple(high for _, high in ranges), tuple(counts))
    targets = grid_targets(mechanism, grid, start)
    rng = np.random.default_rng(0) if rng is None else rng
    points, reached, starting, solutions = assemble_branches(mechanism, start, targets, grid.shape,
                                                             held_columns(mechanism, grid, False),
                                                             assembly_branches, rng)
    return points, np.asarray(reached, dtype=bool), starting, solutions


# ------------------------------------------------------------------------------------------------ coordinates

def default_columns(mechanism, dof, point=None):
    """The tangent coordinates a locus is traced over and shown in, when the user names none.

    2 dof: the two actuated coordinates, else the first two. 1 dof: the first
    actuated coordinate (else the first) and the next one. 3 dof: the two
    grid axes then the section coordinate: with three actuated coordinates
    the last two and the first, else the second and third coordinates and
    the first.

    Given `point` (2 and 3 dof), the choice must also be independent
    coordinates of M there or at a neighbour on M
    (:func:`classify.grid_continuation.regular_start`; at an actuator
    singularity the actuated coordinates fail at the point only), as the grid
    continuation holds them (:func:`classify.grid_continuation.held_margins`
    above :data:`classify.grid_continuation.REGULAR_RTOL`). Where the rule's
    choice fails (an idle spin that no actuated coordinate moves, say), the
    independent actuated coordinates are kept, in order, and completed by
    the coordinates a column-pivoted QR of the other columns of DΦ·s leaves
    after the r it picks to solve the loops for (r the rank of DΦ·s).

    Parameters
    ----------
    mechanism : Mechanism
    dof : int
        1, 2 or 3.
    point : ndarray, shape=[point_size], optional
        A configuration of M.

    Returns
    -------
    list of int
    """
    actuated = list(mechanism.actuated_coordinates)
    if dof == 1:
        first = actuated[0] if actuated else 0
        return [first, (first + 1) % mechanism.ambient_dimension]
    if dof == 2:
        columns = actuated if len(actuated) == 2 else [0, 1]
    else:
        columns = actuated[1:] + actuated[:1] if len(actuated) == 3 else [1, 2, 0]
    if point is None:
        return columns
    import scipy.linalg

    from manifold import rank_of_values
    from mechanisms.kinematics import constraint_jacobian, kinematics_of

    from .grid_continuation import REGULAR_RTOL, held_margins, regular_start

    if regular_start(mechanism, point, columns).margin > REGULAR_RTOL:
        return columns
    chosen = []
    for column in actuated:
        if len(chosen) < dof and held_margins(mechanism, point, chosen + [column])[0] > REGULAR_RTOL:
            chosen.append(column)
    rest = [column for column in range(mechanism.ambient_dimension) if column not in chosen]
    scaled = constraint_jacobian(mechanism, point) * kinematics_of(mechanism).ambient.tangent_scales
    rank = rank_of_values(np.linalg.svd(scaled, compute_uv=False)).rank
    order = scipy.linalg.qr(scaled[:, rest], pivoting=True)[2]
    chosen += [rest[index] for index in order[rank:]][: dof - len(chosen)]
    if dof == 3 and len(actuated) >= 2 and chosen[0] in actuated and chosen[1] in actuated:
        return chosen  # the actuated coordinates as the grid's axes, the added one the section's
    return chosen[1:] + chosen[:1] if dof == 3 else chosen


def locus_coordinates(mechanism, points, coordinates):
    """The coordinates a locus is shown in.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]
    coordinates : sequence of int or "end-effector"
        Tangent coordinate columns (joint displacements from home, angles
        wrapped to [−π, π)), or the end-effector point (position, pose and
        tool outputs: its position).

    Returns
    -------
    values : ndarray, shape=[n, d]
    names : tuple of str
    """
    from mechanisms.kinematics import end_effector, kinematics_of

    from .displacements import displacements_of

    points = np.atleast_2d(points)
    if isinstance(coordinates, str):
        value = end_effector(mechanism, points)
        if value.ndim == 3:  # a frame: its origin
            value = value[..., :-1, -1]
        elif kinematics_of(mechanism).output == "tool":  # (point, axis): the point
            value = value[..., :3]
        names = ("x", "y", "z")[: value.shape[-1]]
        return np.asarray(value, dtype=float), names
    columns = list(coordinates)
    values = displacements_of(mechanism, points)[:, columns]
    for index, column in enumerate(columns):
        if _is_angle(mechanism, column):
            values[:, index] = (values[:, index] + np.pi) % (2 * np.pi) - np.pi
    return values, tuple(mechanism.coordinate_names[column] for column in columns)
