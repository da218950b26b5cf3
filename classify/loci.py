"""Singularity loci of 1- and 2-dof mechanisms, traced as curves on M and confirmed by :func:`classify.classify`.

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
so.

**2 dof.** A grid over two coordinates is assembled by continuation from a
starting configuration (:func:`classify.cli.map_command.assemble_grid`: the
starting configuration's branch). Seeds are the grid edges along which a sign
function changes sign, and the edges from a reached point to an unreached one
(the reach of a branch ends at a fold, often an actuator singularity). Each
seed is corrected onto the curve ``{Φ = 0, s = 0}`` by Gauss–Newton
(:func:`manifold.project`, ‖(Φ, s)‖ ≤ :data:`TOLERANCE`), the gradient of s by
central differences (step 1e-6, dimensionless). From the first seed not yet
on a traced curve, the curve is followed by a predictor (along the null
vector of ``[DΦ; ∇s]``) and corrector (the same projection) both ways until
it comes back to its start (a closed curve), a corrector fails four times
halved, or :data:`STEP_LIMIT` steps. Seeds within two steps of a traced
curve are covered by it.

**1 dof.** M itself is the curve ``{Φ = 0}``, followed the same way from
points of M sampled over its branches (:func:`manifold.sample_manifold`) and
the starting configuration: each traced curve is one branch. The loci are
points: where s_a or s_e changes sign between consecutive points of a branch,
corrected onto ``{Φ = 0, s = 0}`` (a square system). A C-space singularity
(a branch point, where two branches cross) is a zero of both, found the same
way.

**Confirmation.** Every point traced for a kind is classified
(:func:`classify.classify_many`, one batch); the points the classification
does not find singular of that kind are dropped (their count is in the
coverage), and split the piece there. Points classified C-space singular
are reported as branch points.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["default_columns", "TOLERANCE", "STEP_LIMIT", "LocusPiece", "Loci", "sign_functions", "trace_loci", "TRACEABLE_KINDS",
           "locus_coordinates"]

#: ‖(Φ, s)‖ of a corrected locus point
TOLERANCE = 1e-11
#: most predictor–corrector steps along one curve, each way
STEP_LIMIT = 1500
#: the kinds a sign function exists for (C-space points are found as zeros of both)
TRACEABLE_KINDS = ("actuator", "end_effector")
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
        ‖(Φ, s)‖ at each point.
    """

    kind: str
    points: np.ndarray
    closed: bool
    residuals: np.ndarray


@dataclass(frozen=True, eq=False)
class Loci:
    """The loci of a mechanism and how much of M they cover.

    Attributes
    ----------
    pieces : tuple of LocusPiece
    branches : tuple of LocusPiece
        1 dof: the traced curves of M (kind ``"branch"``); 2 dof: empty.
    samples : ndarray, shape=[n, point_size]
        The points of M the search started from (the assembled grid, or the sampled points).
    sample_signs : ndarray, shape=[n, 2]
        The signs of s_a and s_e at the samples (0 where not defined): the assembly and working modes.
    coverage : dict
        ``dof``, ``grid`` (names and counts, 2 dof), ``reached`` grid points, ``seeds``, ``pieces``,
        ``closed`` per piece, ``unconfirmed`` (points dropped per kind), ``not_traced`` (kinds and why),
        ``tolerance``, ``step``.
    """

    pieces: tuple
    branches: tuple
    samples: np.ndarray
    sample_signs: np.ndarray
    coverage: dict = field(default_factory=dict)


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
        functions["actuator"] = lambda points: np.linalg.det(np.concatenate(
            [constraint_rows(points), np.broadcast_to(actuators, np.shape(points)[:-1] + actuators.shape)], axis=-2))
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
            return np.linalg.det(np.concatenate([constraint_rows(points), jacobian / np.maximum(size, 1e-300)],
                                                axis=-2))
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


def _curve_manifold(model, function):
    """The implicit manifold {Φ = 0, s = 0} (or M itself when `function` is None)."""
    from manifold import ImplicitManifold

    manifold = model.manifold
    if function is None:
        return manifold

    def constraint(points):
        points = np.asarray(points, dtype=float)
        return np.concatenate([manifold.constraint(points), function(points)[..., None]], axis=-1)

    def jacobian(points):
        points = np.asarray(points, dtype=float)
        flat = points.reshape(-1, points.shape[-1])
        rows = np.concatenate([np.asarray(manifold.constraint_jacobian(flat), dtype=float).reshape(
            len(flat), -1, manifold.ambient.dim), _gradient(manifold.ambient, function, flat)[:, None, :]], axis=1)
        return rows.reshape(points.shape[:-1] + rows.shape[-2:])

    return ImplicitManifold(ambient=manifold.ambient, constraint=constraint, constraint_jacobian=jacobian,
                            is_solution=manifold.is_solution)


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
            corrected = _correct(curve, guess, max_step=size * scales.max())
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
        on = _correct(curve, seed, max_step=4 * step * ambient.tangent_scales.max())
        if on is None:
            continue
        if any(_distances(ambient, on[None], points)[0] < 2 * step for points, _ in traced):
            continue
        traced.append(_trace(curve, on, step))
    return traced


# ------------------------------------------------------------------------------------------------ seeds

def _grid_seeds(points, reached, shape, values):
    """The seed points of a 2-D grid: per kind, the endpoint of smaller |s| of each sign-changing edge, and the
    reached end of each edge to an unreached point (for every kind)."""
    from .cli.map_command import grid_neighbours

    neighbours = grid_neighbours(shape)
    seeds = {kind: [] for kind in values}
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


def _sign_changes(curve_points, function):
    """Points of a traced curve just before a sign change of s, shape=[n, point_size]."""
    values = function(curve_points)
    change = np.flatnonzero(values[:-1] * values[1:] < 0)
    return curve_points[change]


# ------------------------------------------------------------------------------------------------ confirmation

def _confirmed(model, survey, kind, points, residuals, closed):
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
            pieces.append(LocusPiece(kind, points[run], bool(closed and good.all()), residuals[run]))
    return pieces, int((~good).sum()), cspace


def _residuals(curve, points):
    return np.linalg.norm(curve.constraint(points), axis=-1)


# ------------------------------------------------------------------------------------------------ entry point

def trace_loci(mechanism, start, columns=None, ranges=None, counts=(24, 24), kinds=("actuator", "end_effector"),
               rng=None, survey=None, sample_count=24):
    """Trace the singularity loci of a 1- or 2-dof mechanism (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        A configuration of M (its branch is the grid's).
    columns : sequence of int, optional
        2 dof: the two tangent coordinates of the grid (default the actuated ones, else the first two).
        1 dof: ignored.
    ranges : sequence of (float, float), optional
        2 dof: the grid's range per coordinate, displacements from home (default (−π, π) for angles, ±2
        characteristic lengths for lengths, around the start's values).
    counts : (int, int)
        Grid points per axis.
    kinds : sequence of str
        Among ``actuator``, ``end_effector`` and ``cspace`` (C-space points are the zeros of both sign
        functions that classify finds C-space singular).
    rng : numpy.random.Generator, optional
        For the sampling of M (1 dof); default seeded 0.
    survey : Survey, optional
        The model's survey (default computed once per model).
    sample_count : int
        1 dof: random points projected onto M, and random-walk steps, to find its branches.

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
    start = np.asarray(start, dtype=float)
    dof = int(ambient.dim - survey.constraint_rank)
    if dof not in (1, 2):
        raise ValueError(f"loci are traced for 1- and 2-dof mechanisms; this one has {dof} dof")
    functions, refused = sign_functions(model, _regular_reference(model, survey, start, rng))
    traced_kinds = [kind for kind in TRACEABLE_KINDS if kind in functions
                    and (kind in kinds or "cspace" in kinds)]
    not_traced = {kind: refused[kind] for kind in kinds if kind in refused}
    coverage = {"dof": dof, "tolerance": TOLERANCE, "not_traced": not_traced}
    pieces, branches, unconfirmed, branch_points = [], [], {}, []

    if dof == 2:
        columns, ranges, counts = _grid_arguments(mechanism, start, columns, ranges, counts)
        samples, reached = _assembled_grid(mechanism, start, columns, ranges, counts)
        spacing = min((high - low) / max(count - 1, 1) / ambient.tangent_scales[column]
                      for column, (low, high), count in zip(columns, ranges, counts))
        step = spacing / 2
        values = {kind: functions[kind](samples[reached]) if reached.any() else np.zeros(0) for kind in traced_kinds}
        full_values = {kind: np.zeros(len(samples)) for kind in traced_kinds}
        for kind in traced_kinds:
            full_values[kind][reached] = values[kind]
        seeds = _grid_seeds(np.nan_to_num(samples), reached, tuple(counts), full_values)
        coverage.update({"grid": {mechanism.coordinate_names[column]: [low, high, count] for column, (low, high), count
                                  in zip(columns, ranges, counts)},
                         "reached": int(reached.sum()), "grid_points": int(len(samples)),
                         "seeds": {kind: int(len(seeds[kind])) for kind in traced_kinds}, "step": step})
        samples = samples[reached]
        for kind in traced_kinds:
            curve = _curve_manifold(model, functions[kind])
            for points, closed in _trace_from_seeds(curve, seeds[kind], step):
                found, dropped, cspace = _confirmed(model, survey, kind, points, _residuals(curve, points), closed)
                unconfirmed[kind] = unconfirmed.get(kind, 0) + dropped
                branch_points += list(cspace)
                if kind in kinds:
                    pieces += found
    else:
        samples = sample_manifold(manifold, rng, start[None], random_count=sample_count, walk_count=sample_count)
        step = 0.05
        coverage.update({"samples": int(len(samples)), "step": step})
        traced = _trace_from_seeds(manifold, samples, step)
        for index, (points, closed) in enumerate(traced):
            branches.append(LocusPiece("branch", points, closed, _residuals(manifold, points)))
        for kind in traced_kinds:
            curve = _curve_manifold(model, functions[kind])
            candidates = [candidate for points, _ in traced for candidate in _sign_changes(points, functions[kind])]
            found_points = []
            for candidate in candidates:
                on = _correct(curve, candidate, max_step=4 * step * ambient.tangent_scales.max())
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
        coverage["branches_closed"] = [branch.closed for branch in branches]
    if "cspace" in kinds:
        unique = []
        for candidate in branch_points:
            if not unique or _distances(ambient, candidate[None], np.array(unique))[0] > 10 * step:
                unique.append(candidate)
        pieces += [LocusPiece("cspace", candidate[None], False, _residuals(manifold, candidate[None]))
                   for candidate in unique]
    signs = np.zeros((len(samples), 2))
    for column, kind in enumerate(TRACEABLE_KINDS):
        if kind in functions and len(samples):
            signs[:, column] = np.sign(functions[kind](samples))
    coverage.update({"pieces": {kind: sum(piece.kind == kind for piece in pieces) for kind in kinds},
                     "closed": [piece.closed for piece in pieces], "unconfirmed": unconfirmed})
    return Loci(tuple(pieces), tuple(branches), samples, signs, coverage)


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


def _grid_arguments(mechanism, start, columns, ranges, counts):
    """Default grid columns (the actuated coordinates, else the first two) and ranges (a turn around the start
    for angles, ±2 characteristic lengths for lengths)."""
    from .cli._configurations import displacements_of

    if columns is None:
        actuated = list(mechanism.actuated_coordinates)
        columns = actuated if len(actuated) == 2 else [0, 1]
    columns = [int(column) for column in columns]
    if len(columns) != 2:
        raise ValueError(f"a 2-dof locus grid has two coordinates, got {len(columns)}")
    if ranges is None:
        values = displacements_of(mechanism, start[None])[0]
        from mechanisms.kinematics import kinematics_of

        scales = kinematics_of(mechanism).ambient.tangent_scales
        ranges = [((values[column] - np.pi, values[column] + np.pi) if scales[column] == 1.0 and
                   _is_angle(mechanism, column) else (values[column] - 2 * scales[column],
                                                      values[column] + 2 * scales[column])) for column in columns]
    counts = [int(count) for count in counts]
    if len(counts) != 2 or min(counts) < 2:
        raise ValueError(f"a 2-dof locus grid needs two counts ≥ 2, got {counts}")
    return columns, [tuple(map(float, pair)) for pair in ranges], counts


def _is_angle(mechanism, column):
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    for factor, part in zip(ambient.factors, ambient.tangent_slices):
        if part.start <= column < part.stop:
            return factor != "R"
    return False


def _assembled_grid(mechanism, start, columns, ranges, counts):
    """The grid assembled by continuation from `start` (:func:`classify.cli.map_command.assemble_grid`)."""
    from .cli._configurations import displacements_of, points_of
    from .cli._grid import Grid
    from .cli.map_command import assemble_grid, held_columns

    grid = Grid(tuple(mechanism.coordinate_names[column] for column in columns), tuple(columns),
                tuple(low for low, _ in ranges), tuple(high for _, high in ranges), tuple(counts))
    base = displacements_of(mechanism, start[None])[0]
    requested = np.array(np.broadcast_to(base, (grid.size, base.size)))
    requested[:, list(grid.columns)] = grid.values().reshape(grid.size, len(grid.columns))
    targets = points_of(mechanism, requested)
    points, reached = assemble_grid(mechanism, start, targets, grid.shape, held_columns(mechanism, grid))
    return points, np.asarray(reached, dtype=bool)


# ------------------------------------------------------------------------------------------------ coordinates

def default_columns(mechanism, dof):
    """The tangent coordinates a locus is traced over and shown in, when the user names none.

    2 dof: the two actuated coordinates, else the first two. 1 dof: the first
    actuated coordinate (else the first) and the next one.

    Parameters
    ----------
    mechanism : Mechanism
    dof : int
        1 or 2.

    Returns
    -------
    list of int
    """
    actuated = list(mechanism.actuated_coordinates)
    if dof == 2:
        return actuated if len(actuated) == 2 else [0, 1]
    first = actuated[0] if actuated else 0
    return [first, (first + 1) % mechanism.ambient_dimension]


def locus_coordinates(mechanism, points, coordinates):
    """The coordinates a locus is shown in.

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[n, point_size]
    coordinates : sequence of int or "end-effector"
        Tangent coordinate columns (joint displacements from home, angles
        wrapped to [−π, π)), or the end-effector point (position and pose
        outputs: its position).

    Returns
    -------
    values : ndarray, shape=[n, d]
    names : tuple of str
    """
    from mechanisms.kinematics import end_effector

    from .cli._configurations import displacements_of

    points = np.atleast_2d(points)
    if isinstance(coordinates, str):
        value = end_effector(mechanism, points)
        if value.ndim == 3:  # a frame: its origin
            value = value[..., :-1, -1]
        names = ("x", "y", "z")[: value.shape[-1]]
        return np.asarray(value, dtype=float), names
    columns = list(coordinates)
    values = displacements_of(mechanism, points)[:, columns]
    for index, column in enumerate(columns):
        if _is_angle(mechanism, column):
            values[:, index] = (values[:, index] + np.pi) % (2 * np.pi) - np.pi
    return values, tuple(mechanism.coordinate_names[column] for column in columns)
