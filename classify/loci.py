"""Singularity loci of 1-, 2- and 3-dof mechanisms, traced as curves on M (3 dof: in sections) and confirmed by
:func:`classify.classify`.

**Sign functions** (:mod:`classify.loci_signs`). Where the kept
constraint rows and the m rows of a kind's map make a square matrix, its
determinant s is a smooth function on K whose zeros on M are that kind's
singularities (Park & Kim 1999, Section 3; Chablat, Wenger & Angeles 1998
eqs. 3b–3c: det A and det B). A kind without a square matrix is not traced,
and the coverage says so.

**2 dof.** A grid over two coordinates is assembled by continuation from a
starting configuration (:func:`classify.grid_continuation.assemble_grid`: the
starting configuration's branch). Seeds are the grid edges along which a sign
function changes sign, and the edges from a reached point to an unreached one
(the reach of a branch ends at a fold, often an actuator singularity), and
the reached points where a sign function vanishes (its magnitude,
:func:`~classify.loci_signs.sign_magnitudes`, at most :data:`~classify.loci_signs.ZERO_TOLERANCE`). From a start
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
(:func:`manifold.project`, ‖(Φ, s)‖ ≤ :data:`~classify.loci_curves.TOLERANCE`), the gradient of s by
central differences (step 1e-6, dimensionless). From the first seed not yet
on a traced curve, the curve is followed by a predictor (along the null
vector of ``[DΦ; ∇s]``) and corrector (the same projection) both ways until
it comes back to its start (a closed curve), a corrector fails four times
halved, or :data:`~classify.loci_curves.STEP_LIMIT` steps. Seeds within two steps of a traced
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
magnitude, :func:`~classify.loci_signs.sign_magnitudes`, at most :data:`~classify.loci_signs.ZERO_TOLERANCE`: a start
at a singularity is found), corrected onto ``{Φ = 0, s = 0}`` (a square
system). Where a sign function vanishes at every point of a traced branch
(its largest magnitude along it at most :data:`~classify.loci_signs.ZERO_TOLERANCE`, reported
in the coverage's ``whole_branch`` with the tolerance), the whole branch is
that kind's locus: one piece, ``whole_branch`` set, confirmed by the
classification at its points (Park & Kim 1999 Fig. 3a: the slider-crank
with crank = coupler, whose slider stays at the crank's pivot on one
branch; Gosselin & Angeles 1990 eq. 17). A C-space singularity
(a branch point, where two branches cross) is a zero of both, found the same
way.

**C-space singularities, searched for** (:mod:`classify.loci_search`):
from the points where σ_r, the r-th singular value of DΦ·diag(s), is
locally smallest, 1- and 2-dof loci with the kind ``cspace`` search for the
C-space singularities whether or not a traced curve passes through them;
with redundant actuation the actuator singularities are searched for the
same way. The coverage's ``cspace_search`` (``actuator_search``) counts the
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

from .loci_coordinates import _is_angle, default_columns, locus_coordinates
from .loci_curves import (
    STEP_LIMIT, TOLERANCE, _correct, _curve_manifold, _distances, _residuals, _trace_from_seeds)
from .loci_grids import SECTION_COUNT, _assembled_grid, _grid_arguments, _section_function
from .loci_search import (
    CSPACE_ITERATIONS, CSPACE_TOLERANCE, _search_zeros, _zero_manifold, cspace_function, redundant_actuator_function,
    search_cspace)
from .loci_seeds import _branch_minima, _grid_minima, _grid_seeds, _sign_changes
from .loci_signs import TRACEABLE_KINDS, ZERO_TOLERANCE, sign_functions, sign_magnitudes

__all__ = ["default_columns", "TOLERANCE", "STEP_LIMIT", "SECTION_COUNT", "LocusPiece", "Loci",
           "sign_functions", "trace_loci", "TRACEABLE_KINDS", "locus_coordinates", "cspace_function", "search_cspace",
           "CSPACE_TOLERANCE", "CSPACE_ITERATIONS", "redundant_actuator_function", "sign_magnitudes", "ZERO_TOLERANCE"]


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
        kind's sign function vanishes identically: its magnitude (:func:`~classify.loci_signs.sign_magnitudes`)
        is at most :data:`~classify.loci_signs.ZERO_TOLERANCE` at every point (e.g. the slider-crank with
        crank = coupler, whose slider stays at the crank's pivot on one branch: Park & Kim 1999 Fig. 3a;
        Gosselin & Angeles 1990 eq. 17).
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
        ``tolerance``, ``step``; 2 and 3 dof: ``start`` (``singular``, ``cspace``, ``moved``, ``margin``,
        ``tolerance``, ``tied``: :meth:`classify.grid_continuation.StartingPoint.to_dict`); 2 dof with
        ``assembly_branches`` > 1: ``assembly_branches`` (``found``, ``reached`` per branch, ``solutions`` the
        probes found, ``asked``); 1 dof:
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
        (default :func:`~classify.loci_coordinates.default_columns`). 1 dof: ignored.
    ranges : sequence of (float, float) or None, optional
        2 and 3 dof: the range per coordinate, displacements from home; a None entry (or a missing third) is
        defaulted around the start's values: (−π, π) for angles, ±½ characteristic length for slides
        (:data:`~classify.loci_grids.SLIDE_RANGE`); a section's default has the start's value among its n evenly
        spaced values (:func:`~classify.loci_grids._default_sections`): for an angle a turn without its end (4
        sections: −π, −π/2, 0, π/2 from the start), for a slide within ±½ characteristic length (4 sections: −½,
        −¼, 0, ¼ of it).
    counts : (int, int) or (int, int, int)
        Grid points per axis (≥ 2); 3 dof: then the number of sections (default
        :data:`~classify.loci_grids.SECTION_COUNT`).
    kinds : sequence of str
        Among ``actuator``, ``end_effector`` and ``cspace`` (C-space points: the points of the traced curves
        that classify finds C-space singular, and, for 1 and 2 dof, those
        :func:`~classify.loci_search.search_cspace` finds).
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
                                                        assembly_branches, rng, survey.constraint_rank)
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
