"""Continuation over a grid of joint coordinates: every grid point assembled on the starting configuration's branch.

A :class:`Grid` is a rectangular grid over some tangent coordinates (joint
displacements from the home, :mod:`classify.displacements`); the other
coordinates keep the starting configuration's values. The grid
coordinates are held at exactly the grid values, and so are the actuated
coordinates off the grid when the grid is over actuated coordinates only
(:func:`held_columns`); an S joint with a grid coordinate is held whole.
The other coordinates close the loops (where the held ones leave them free
to move, the corrections of least length pick the configuration nearest the
previous one), by continuation over the grid (:func:`assemble_grid`): the
grid point nearest the starting configuration is reached from it, and every
other point from an already reached neighbouring grid point (one step along
one axis), so the grid follows the starting configuration's assembly branch
(working mode).

One continuation step, from a configuration q on M to the held values h'
(the predictor–corrector :func:`mechanisms.assemble` uses from the home):
the held coordinates move from their values at q to h' in sub-steps of at
most 0.2 (dimensionless), each predicted to first order,
``q ⊕ −s·(DΦ_q s)⁺ DΦ_h Δh``, and corrected by Gauss–Newton in the free
coordinates to ‖Φ‖ ≤ 1e-10 with no half-turn loop; a sub-step whose
corrector does not converge, or moves the free coordinates more than 0.25
(dimensionless: a jump to another branch), is halved, and the step fails
below 1/64 of the way (or 1e-5). A grid point none of whose reached
neighbours leads to it is *unreachable* (outside the inputs' reach on this
branch, or beyond a fold). A part of the grid with no reached neighbour at
all is started like the first point: from the starting configuration,
nearest point first. The held values of a reached point are the grid values
bit for bit. All the grid points of one continuation front are computed at
once (array work): a grid of n₁ × … × n_d points takes about n₁ + … + n_d
fronts. An axis whose two ends are the same configurations (a held angle
over a whole turn, both ends given) is closed on itself, both ways: its two
ends are neighbours of each other (a reached end is continued to the other
first, a step of zero, so the two are one configuration and get one
verdict) and of the points next to the other end, so continuation walks
across the ends and the map does not depend on which end is called which.

**A singular start.** Where the starting configuration is singular for the
held coordinates — DΦ restricted to the free ones, ``DΦ_free·s``, has a
lower rank than DΦ·s, as at an actuator singularity when the grid is over
the actuated coordinates (Chablat, Wenger & Angeles 1998 eq. 9: the
five-bar's distal links aligned) — the first continuation step has no
unique predictor and can reach nothing. When no grid point left is reached
from the start, the remaining ones (those tried from the start and missed
included: the map must not depend on which points the grid's resolution
let the start try) are started (nearest first, as above) from a regular
neighbour on M instead (:func:`regular_start`): a step of
0.05, 0.1 or 0.2 (dimensionless, :data:`NEIGHBOUR_STEPS`) from the start
along each coordinate axis projected onto T_pM (both ways; no arbitrary
basis of T_pM chooses them: :func:`neighbour_directions`), corrected onto M, the first
size at which one is regular, and of those the best conditioned (of equally
well conditioned ones, by a convention of the coordinates, the others
reported: :func:`regular_start`). A small
step along M stays on the start's connected part of M; where the start is
a fold between two assembly modes, the neighbour is in one of them.

**A start at a C-space singularity**, where DΦ·s itself has a lower rank
than on M (branches of M may cross: Park & Kim 1999 Fig. 1, the five-bar's
joints collinear), when the caller gives that rank (``constraint_rank``,
the survey's: ``closedchain map`` and the loci do): the whole grid is
started from the start's regular neighbour, none of it from the start,
whose own continuation could take another branch through it than the
neighbour's.

**Other assembly branches** (:func:`assemble_branches`). The grid follows
one branch. The loops are solved at a few grid points (probes) from random
values of the free coordinates (Gauss–Newton in the free coordinates, as
the corrector above, to ‖Φ‖ ≤ 1e-10); a solution farther than
:data:`BRANCH_SEPARATION` (dimensionless) from every branch's configuration
at its grid point starts a new branch, assembled over the grid from it like
the first; the points of a new branch that coincide with an earlier
branch's are left to the earlier one.

Used by ``closedchain map`` (:mod:`classify.cli.map_command`) and the loci
(:mod:`classify.loci`).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field as dataclass_field

import numpy as np

__all__ = ["Grid", "grid_targets", "held_columns", "held_entries", "assemble_grid", "grid_neighbours",
           "regular_start", "neighbour_directions", "held_margins", "StartingPoint", "REGULAR_RTOL", "NEIGHBOUR_STEPS",
           "TIE_RTOL", "SAME_POINT", "assemble_branches", "BRANCH_SEPARATION"]

#: ‖Φ‖ of an assembled grid point (the default of :func:`mechanisms.assemble`)
_TOLERANCE = 1e-10
#: largest dimensionless corrector move a continuation sub-step accepts (as :mod:`mechanisms.assembly`)
_JUMP = 0.25
#: largest dimensionless move of the held coordinates in one sub-step
_SUBSTEP = 0.2
#: continuation gives up when a sub-step falls below this fraction of the way to the target, or below 1e-5
#: (dimensionless): a grid map needs the points on the branch, not where exactly it ends between two of them
_SMALLEST_FRACTION = 1 / 64
_SMALLEST_STEP = 1e-5
#: Gauss–Newton iterations of one corrector
_CORRECTOR_ITERATIONS = 8
#: sub-steps one continuation may take
_STEP_LIMIT = 2000
#: grid points tried at once when a part of the grid is started from the configuration: first, and at most
_SEED_CHUNK = 16
_SEED_CHUNK_LIMIT = 4096


#: relative singular-value cut of ``DΦ_free·s`` against σ₁(DΦ·s) below which a start is singular for the held
#: coordinates (as :data:`manifold.rank.DEFAULT_RTOL` for the classification)
REGULAR_RTOL = 1e-6
#: dimensionless distance above which two configurations at one grid point are on different assembly branches
BRANCH_SEPARATION = 1e-3
#: dimensionless step sizes from a singular start to its regular neighbour, tried in order
NEIGHBOUR_STEPS = (0.05, 0.1, 0.2)
#: coordinate axes whose neighbours :func:`regular_start` corrects together (both signs: twice as many points)
NEIGHBOUR_CHUNK = 256
#: relative difference of margins within which :func:`regular_start`'s neighbours are equally well conditioned:
#: mirror-image neighbours' margins differ by the rounding of their separate corrections (1e-14), which must not
#: choose between them
TIE_RTOL = 1e-6
#: dimensionless distance within which :func:`regular_start`'s corrected neighbours are one configuration (the
#: corrector's tolerance, far below :data:`BRANCH_SEPARATION`)
SAME_POINT = 1e-8


@dataclass(frozen=True)
class StartingPoint:
    """Where a grid's continuation starts (:func:`regular_start`).

    Attributes
    ----------
    point : ndarray, shape=[point_size]
        The configuration the continuation starts from.
    singular : bool
        Whether the given start was singular: for the held coordinates, or at a C-space singularity (`cspace`).
    moved : float
        Dimensionless distance from the given start to `point` (0 when the continuation started at the given
        start).
    margin : float
        At `point`: ``σ_r(DΦ_free·s) / σ₁(DΦ·s)`` (:func:`held_margins`), against :data:`REGULAR_RTOL`.
    alternatives : ndarray, shape=[t, point_size]
        The other neighbours as well conditioned as `point` (within :data:`TIE_RTOL`), distinct from it and from
        each other: a start symmetric between its neighbours (the slider-crank at a dead centre between its two
        mirror-image assembly modes) has no neighbour better than the others, and which of them is `point`
        follows the coordinates' orientation (:func:`regular_start`). No rows (t = 0) when the neighbour is
        unique or the start is not left.
    cspace : bool
        Whether the given start is a C-space singularity: DΦ·s of a lower rank there than the `constraint_rank`
        given (:func:`held_margins`).
    """

    point: np.ndarray
    singular: bool
    moved: float
    margin: float
    alternatives: np.ndarray = dataclass_field(default_factory=lambda: np.zeros((0, 0)))
    cspace: bool = False

    @property
    def tied(self):
        """How many distinct neighbours were equally well conditioned: 1 + len(alternatives) (1 at a regular
        start)."""
        return 1 + len(self.alternatives)

    def to_dict(self):
        """``{"singular", "cspace", "moved", "margin", "tolerance", "tied"}`` for a coverage or a JSON
        document."""
        return {"singular": self.singular, "cspace": self.cspace, "moved": self.moved, "margin": self.margin,
                "tolerance": REGULAR_RTOL, "tied": self.tied}


@dataclass(frozen=True)
class Grid:
    """A rectangular grid of coordinate values (``closedchain map --grid NAME=a:b:n ...``).

    Attributes
    ----------
    names : tuple of str
        The coordinate names, one per grid axis.
    columns : tuple of int
        Their columns in a displacement matrix (indices into ``mechanism.coordinate_names``).
    starts, stops : tuple of float
    counts : tuple of int

    Raises
    ------
    ValueError
        If the fields are not one per axis, the columns not distinct
        non-negative integers, a start or stop not a finite number, or a
        count not a positive integer (so nothing is dropped or rounded).
    """

    names: tuple
    columns: tuple
    starts: tuple
    stops: tuple
    counts: tuple

    def __post_init__(self):
        fields = {"names": self.names, "columns": self.columns, "starts": self.starts, "stops": self.stops,
                  "counts": self.counts}
        if len({len(value) for value in fields.values()}) != 1:
            raise ValueError("Grid: names, columns, starts, stops and counts must have one entry per axis, got "
                             + ", ".join(f"{len(value)} {field}" for field, value in fields.items()))

        def whole(value):
            return isinstance(value, numbers.Integral) and not isinstance(value, bool)

        if not all(whole(column) and column >= 0 for column in self.columns) or len(set(self.columns)) != len(
                self.columns):
            raise ValueError(f"Grid: columns must be distinct non-negative integers, got {self.columns!r}")
        for field in ("starts", "stops"):
            if not all(isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)
                       for value in fields[field]):
                raise ValueError(f"Grid: {field} must be finite numbers, got {fields[field]!r}")
        if not all(whole(count) and count >= 1 for count in self.counts):
            raise ValueError(f"Grid: counts must be positive integers, got {self.counts!r}")

    @property
    def shape(self):
        return tuple(self.counts)

    @property
    def size(self):
        return math.prod(self.counts)

    def axes(self):
        """The values along each axis, a list of arrays of shape=[n_i]."""
        return [np.linspace(start, stop, count) for start, stop, count in zip(self.starts, self.stops, self.counts)]

    def values(self):
        """The coordinates of every grid point, shape ``[*shape, d]`` (C order: the last axis varies fastest)."""
        return np.stack(np.meshgrid(*self.axes(), indexing="ij"), axis=-1)

    def to_dict(self):
        """``{name: [a, b, n]}``."""
        return {name: [start, stop, count]
                for name, start, stop, count in zip(self.names, self.starts, self.stops, self.counts)}


def grid_targets(mechanism, grid, start):
    """The grid's points: the starting configuration's displacements with the grid coordinates set.

    Parameters
    ----------
    mechanism : Mechanism
    grid : Grid
    start : ndarray, shape=[point_size]
        A configuration (its displacements give the coordinates off the grid).

    Returns
    -------
    targets : ndarray, shape=[n, point_size]
        In C order (:meth:`Grid.values`).
    """
    from .displacements import displacements_of, points_of

    base = displacements_of(mechanism, np.asarray(start, dtype=float)[None])[0]
    requested = np.array(np.broadcast_to(base, (grid.size, base.size)))
    requested[:, list(grid.columns)] = grid.values().reshape(grid.size, len(grid.columns))
    return points_of(mechanism, requested)


# ------------------------------------------------------------------------------------------------ held coordinates

def held_columns(mechanism, grid, actuated=True):
    """The tangent coordinates held at each grid point (sorted column indices).

    The grid's coordinates (an S joint's three when one of them is on the
    grid), and, with `actuated`, the actuated coordinates off the grid when
    every grid coordinate is actuated (``closedchain map``: the inputs not
    named stay where they are; the loci hold the grid's coordinates only, so
    that a redundantly actuated mechanism's grid is not over-constrained).
    """
    from .displacements import coordinate_columns

    held = set(grid.columns)
    for name, columns in coordinate_columns(mechanism).items():
        if mechanism.joint(name).type == "S" and held & set(columns):
            held |= set(columns)
    inputs = set(mechanism.actuated_coordinates)
    if actuated and set(grid.columns) <= inputs:
        held |= inputs
    return tuple(sorted(held))


def held_entries(ambient, held):
    """The point entries of the factors whose tangent coordinates are held, shape=[h]."""
    held = set(held)
    entries = []
    for point_part, tangent_part in zip(ambient.point_slices, ambient.tangent_slices):
        if held & set(range(ambient.dim)[tangent_part]):
            entries += list(range(ambient.point_size)[point_part])
    return np.array(entries, dtype=int)


# ------------------------------------------------------------------------------------------------ continuation

def _correct(mechanism, points, free, iterations=_CORRECTOR_ITERATIONS, closing=False):
    """Gauss–Newton corrector in the free coordinates from a stack of configurations (held ones fixed bit for bit).

    ``q ← q ⊕ −s·(DΦ_q(q)·s)⁺ Φ(q)``, the step of least dimensionless length,
    until ‖Φ‖ ≤ 1e-3 × the assembly tolerance, `iterations` steps, or a step
    that does not decrease ‖Φ‖ (then the iteration stops there): the
    corrector of a continuation step, whose predictor is close, so neither
    damped nor line-searched (a step that does not converge is halved by the
    caller instead).

    Parameters
    ----------
    mechanism : Mechanism
    points : ndarray, shape=[m, point_size]
    free : ndarray of int, shape=[f]
        The free tangent coordinates.
    closing : bool
        Iterate on the closing map (:func:`mechanisms.kinematics.closing_space`: no half-turn zeros) instead
        of Φ, for starts far from M; its residual is returned.

    Returns
    -------
    points : ndarray, shape=[m, point_size]
    residuals : ndarray, shape=[m]
        ‖Φ‖ at each (NaN where the iteration diverged).
    """
    from manifold import minimum_norm_steps
    from mechanisms.kinematics import configuration_space

    space = configuration_space(mechanism)
    space = space.closing if closing else space
    value_of, ambient = space.constraint, space.ambient
    scales = ambient.tangent_scales[free]
    points = np.array(points, dtype=float)
    values = value_of(points)
    norms = np.linalg.norm(values, axis=-1)
    if not len(free):
        return points, norms
    active = np.isfinite(norms)
    for _ in range(iterations):
        rows = np.flatnonzero(active & (norms > 1e-3 * _TOLERANCE))
        if not rows.size:
            break
        tangent = np.zeros((rows.size, ambient.dim))
        tangent[:, free] = -scales * minimum_norm_steps(space, points[rows], values[rows], columns=free, rcond=1e-12)
        points[rows] = ambient.retract(points[rows], tangent)
        values[rows] = value_of(points[rows])
        previous, norms[rows] = norms[rows], np.linalg.norm(values[rows], axis=-1)
        active[rows] = norms[rows] < previous  # not converging (above the tolerance): the caller halves the step
    return points, norms


def _continue(mechanism, sources, targets, held, entries):
    """Continuation from configurations on M to the held values of target points, all at once.

    Parameters
    ----------
    mechanism : Mechanism
    sources : ndarray, shape=[m, point_size]
        Configurations on M.
    targets : ndarray, shape=[m, point_size]
        Points whose held entries are the values to reach.
    held : ndarray of int
        The held tangent coordinates.
    entries : ndarray of int
        The point entries of the held factors (:func:`held_entries`).

    Returns
    -------
    reached : ndarray, shape=[m, point_size]
        The configurations (held entries those of `targets`; NaN rows where not reached).
    ok : ndarray of bool, shape=[m]
    """
    from manifold import minimum_norm_steps
    from mechanisms.kinematics import closes, configuration_space

    space = configuration_space(mechanism)
    ambient, pattern = space.ambient, space.pattern
    scales = ambient.tangent_scales
    free = np.setdiff1d(np.arange(ambient.dim), held)
    held_pattern, held_entries = pattern.restricted(held)  # DΦ's held columns: the motion of the held values
    count = len(sources)
    delta = np.zeros((count, ambient.dim))
    delta[:, held] = ambient.inverse_retract(sources, targets)[:, held]
    size = np.linalg.norm(delta / scales, axis=-1)
    largest = np.minimum(1.0, _SUBSTEP / np.maximum(size, 1e-300))
    step, done = largest.copy(), np.zeros(count)
    current = np.array(sources, dtype=float)
    status = np.zeros(count, dtype=np.int8)  # 0 walking, 1 reached, -1 failed
    for _ in range(_STEP_LIMIT):
        rows = np.flatnonzero(status == 0)
        if not rows.size:
            break
        goal = np.minimum(1.0, done[rows] + step[rows])
        base = ambient.retract(sources[rows], goal[:, None] * delta[rows])
        final = goal == 1.0
        base[final] = targets[rows[final]]  # the grid values bit for bit
        start = current[rows].copy()
        start[:, entries] = base[:, entries]
        tangent = np.zeros((rows.size, ambient.dim))
        if free.size:  # no dense c × k Jacobian of the stack: the held columns, then the free ones block by block
            held_jacobian = held_pattern.dense(space.constraint_jacobian_entries(current[rows])[..., held_entries])
            motion = np.einsum("mch,mh->mc", held_jacobian, (goal - done[rows])[:, None] * delta[rows][:, held])
            tangent[:, free] = -scales[free] * minimum_norm_steps(space, current[rows], motion, columns=free,
                                                                  rcond=1e-12)
        predicted = ambient.retract(start, tangent)
        corrected, residuals = _correct(mechanism, predicted, free)
        move = np.linalg.norm(ambient.inverse_retract(predicted, corrected)[:, free] / scales[free], axis=-1)
        good = ((residuals <= _TOLERANCE) & np.asarray(closes(mechanism, corrected, _TOLERANCE), dtype=bool)
                & (move <= _JUMP))
        accepted, refused = rows[good], rows[~good]
        current[accepted], done[accepted] = corrected[good], goal[good]
        step[accepted] = np.minimum(2.0 * step[accepted], largest[accepted])
        status[accepted[goal[good] == 1.0]] = 1
        step[refused] /= 2.0
        status[refused[(step[refused] < _SMALLEST_FRACTION) | (step[refused] * size[refused] < _SMALLEST_STEP)]] = -1
    ok = status == 1
    current[~ok] = np.nan
    return current, ok


def held_margins(mechanism, points, held, constraint_rank=None):
    """``σ_r(DΦ_free·s) / σ₁(DΦ·s)`` at each point, r the numerical rank of DΦ·s there, shape=[n].

    Above :data:`REGULAR_RTOL`, the `held` tangent coordinates are independent coordinates of M there: the loops
    can be solved for the others (the implicit-function theorem). With `constraint_rank`, the rank of DΦ·s on M
    (the survey's), r is at least it: at a C-space singularity (DΦ·s of a lower rank: M is no manifold there,
    its branches may cross) no choice of held coordinates is regular — removing columns raises no singular
    value, so the margin is at most ``σ_r(DΦ·s) / σ₁(DΦ·s)``, below the cut of DΦ's own rank decision
    (:func:`manifold.rank_of_values`' default relative tolerance, :data:`REGULAR_RTOL` too)."""
    return _margins_and_ranks(mechanism, points, held, constraint_rank)[0]


def _margins_and_ranks(mechanism, points, held, constraint_rank=None):
    """:func:`held_margins` and the numerical rank of DΦ·s at each point, shape=[n] each."""
    from manifold import rank_of_values, scaled_singular_values
    from mechanisms.kinematics import configuration_space

    space = configuration_space(mechanism)
    free = np.setdiff1d(np.arange(space.ambient.dim), np.asarray(held, dtype=int))
    points = np.atleast_2d(points)
    full = scaled_singular_values(space, points)  # block by block for a large mechanism
    ranks = np.array([rank_of_values(values).rank for values in full], dtype=int)
    if not free.size:
        return np.ones(len(full)), ranks
    restricted = scaled_singular_values(space, points, columns=free)
    margins = np.zeros(len(full))
    for index, values in enumerate(full):
        rank = max(int(ranks[index]), constraint_rank or 0)
        if rank == 0:
            margins[index] = 1.0
        elif rank <= restricted.shape[1]:
            margins[index] = restricted[index, rank - 1] / max(values[0], 1e-300)
    return margins, ranks


def neighbour_directions(basis, axes=None):
    """The directions of T_pM toward :func:`regular_start`'s neighbours: each coordinate axis projected onto
    T_pM, normalised, shape=[d, k] (the axes that M moves along, in the order of the coordinates), and those
    axes, shape=[d].

    The projection ``U Uᵀ eⱼ`` does not depend on which orthonormal basis U
    of T_pM (dimensionless, shape=[k, m]) is given — an SVD's or the blocks'
    of DΦ, whose vectors are arbitrary within a repeated singular value and
    in sign — so neither do the neighbours, nor which grid points the map
    reaches from them; an axis sign or a joint zero changes a direction's
    sign at most (both are tried). Axes that M does not move along (a
    projection shorter than 1e-9) are left out. `axes` (default all) are the
    axes to project, so that a large mechanism's are taken a chunk at a time.
    """
    axes = np.arange(basis.shape[0]) if axes is None else np.asarray(axes, dtype=np.intp)
    projections = basis[axes] @ basis.T                             # [a, k]: row j is (U Uᵀ eⱼ)ᵀ
    lengths = np.linalg.norm(projections, axis=1)
    moving = lengths > 1e-9
    return projections[moving] / lengths[moving, None], axes[moving]


def regular_start(mechanism, start, held, constraint_rank=None):
    """The start itself when it is regular for the held coordinates, else a regular neighbour on M (module notes).

    Of the neighbours at the first step size at which one is regular, the best conditioned (largest margin)
    is taken. Those within :data:`TIE_RTOL` of the best are equally good (a start symmetric between them, as a
    dead centre between two mirror-image assembly modes, or neighbours whose margins differ by rounding): of
    them one is taken by a convention of the coordinates — the + directions before the −, then the first
    axis (an axis sign or the joints' order picks another) — and the others, one per distinct configuration,
    are returned too (``alternatives``) and counted in the map's ``start.tied``. No choice among them can be
    independent of every coordinate change: flipping every axis of a planar mechanism describes the same
    mechanism turned over, and turns each mirror-image neighbour into the other.

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        A configuration on M.
    held : sequence of int
        The held tangent coordinates (:func:`held_columns`).
    constraint_rank : int, optional
        The rank of DΦ·s on M (the survey's): a start where DΦ·s has a lower rank (a C-space singularity) is
        singular too (:func:`held_margins`).

    Returns
    -------
    StartingPoint
        The given start when no neighbour within :data:`NEIGHBOUR_STEPS` is regular (the continuation tries it
        as it is).
    """
    here = _given_start(mechanism, start, held, constraint_rank)
    return _neighbour_of(mechanism, here, held, constraint_rank) if here.singular else here


def _given_start(mechanism, start, held, constraint_rank=None):
    """The given start as a :class:`StartingPoint` (``moved`` 0): its margin (:func:`held_margins`), whether it
    is singular and a C-space singularity."""
    start = np.asarray(start, dtype=float)
    margins, ranks = _margins_and_ranks(mechanism, start, held, constraint_rank)
    return StartingPoint(start, bool(margins[0] <= REGULAR_RTOL), 0.0, float(margins[0]),
                         cspace=bool(constraint_rank is not None and ranks[0] < constraint_rank))


def _neighbour_of(mechanism, here, held, constraint_rank):
    """:func:`regular_start` of a singular start `here` (:func:`_given_start`): its regular neighbour, or
    `here` where none is found."""
    from manifold import tangent_basis
    from mechanisms.kinematics import closes, configuration_space

    space = configuration_space(mechanism)
    ambient = space.ambient
    start = here.point
    scales = ambient.tangent_scales
    basis = tangent_basis(space, start)[0] / scales[:, None]  # dimensionless, orthonormal
    for size in NEIGHBOUR_STEPS:
        found = _Neighbours(ambient)
        for first in range(0, ambient.dim, NEIGHBOUR_CHUNK):  # a chunk of axes at a time: bounded memory
            tangent, axes = neighbour_directions(basis, np.arange(first, min(first + NEIGHBOUR_CHUNK, ambient.dim)))
            directions = np.concatenate([tangent, -tangent]) * scales
            keys = [(0, int(axis)) for axis in axes] + [(1, int(axis)) for axis in axes]
            guesses = ambient.retract(np.broadcast_to(start, (len(directions), start.size)), size * directions)
            corrected, residuals = _correct(mechanism, guesses, np.arange(ambient.dim), 4 * _CORRECTOR_ITERATIONS)
            moved = np.linalg.norm(ambient.inverse_retract(start, corrected) / scales, axis=-1)
            margins = held_margins(mechanism, corrected, held, constraint_rank)
            good = ((residuals <= _TOLERANCE) & np.asarray(closes(mechanism, corrected, _TOLERANCE), dtype=bool)
                    & (moved <= 2 * size) & (margins > REGULAR_RTOL))
            for index in np.flatnonzero(good):
                found.add(float(margins[index]), keys[index], corrected[index], float(moved[index]))
        if found.tied:
            return found.choice(here.cspace)
    return here


class _Neighbours:
    """The regular neighbours of a singular start within :data:`TIE_RTOL` of the best margin so far, the
    corrections of one configuration (closer than :data:`SAME_POINT`, dimensionless: the axes whose projections
    onto T_pM are one direction) kept once, with their largest margin and smallest key ``(sign, axis)``. What
    is kept does not depend on the order the axes come in: a neighbour pruned below the band of the best so
    far is below the final best's; :meth:`choice` then groups the distinct configurations."""

    def __init__(self, ambient):
        self.ambient, self.best, self.tied = ambient, -math.inf, []

    def _distance(self, first, second):
        return np.linalg.norm(self.ambient.inverse_retract(first, second) / self.ambient.tangent_scales)

    def add(self, margin, key, point, moved):
        if margin < self.best * (1.0 - TIE_RTOL):
            return
        self.best, point = max(self.best, margin), np.array(point)  # a copy: not a view keeping the chunk alive
        self.tied = [entry for entry in self.tied if entry[0] >= self.best * (1.0 - TIE_RTOL)]
        for position, (other_margin, other_key, other_point, other_moved) in enumerate(self.tied):
            if self._distance(other_point, point) <= SAME_POINT:
                self.tied[position] = ((max(margin, other_margin),) + min((key, point, moved),
                                                                          (other_key, other_point, other_moved),
                                                                          key=lambda entry: entry[0]))
                return
        self.tied.append((margin, key, point, moved))

    def choice(self, cspace):
        """The tied neighbour of the smallest key, and the others, one per distinct configuration (farther than
        :data:`BRANCH_SEPARATION` from the earlier ones in key order), as its alternatives."""
        representatives = []
        for margin, key, point, moved in sorted(self.tied, key=lambda entry: entry[1]):
            if all(self._distance(other[2], point) > BRANCH_SEPARATION for other in representatives):
                representatives.append((margin, key, point, moved))
        margin, _, point, moved = representatives[0]
        others = np.array([entry[2] for entry in representatives[1:]]).reshape(len(representatives) - 1, point.size)
        return StartingPoint(point, True, moved, margin, others, cspace)


def grid_neighbours(shape):
    """The neighbours of every grid point, shape=[n, 2d]: column 2a the point one step back along axis a,
    2a + 1 one step forward (flat C-order indices, -1 off the grid)."""
    flat = np.arange(int(np.prod(shape, dtype=np.int64))).reshape(shape)
    result = np.full((flat.size, 2 * len(shape)), -1, dtype=np.int64)
    for axis in range(len(shape)):
        for column, (target, origin) in enumerate(((slice(1, None), slice(None, -1)),
                                                   (slice(None, -1), slice(1, None)))):
            neighbour = np.full(shape, -1, dtype=np.int64)
            into, out_of = [slice(None)] * len(shape), [slice(None)] * len(shape)
            into[axis], out_of[axis] = target, origin
            neighbour[tuple(into)] = flat[tuple(out_of)]
            result[:, 2 * axis + column] = neighbour.reshape(-1)
    return result


def _periodic_axes(ambient, targets, shape, held):
    """The grid axes whose two ends are the same configurations (a held angle over a whole turn, both ends
    given): their ends are one point of M twice, not the two edges of the grid."""
    grid = targets.reshape(tuple(shape) + targets.shape[-1:])
    scales = ambient.tangent_scales[held]
    axes = []
    for axis, size in enumerate(shape):
        if size < 3:
            continue
        first, last, second = (np.take(grid, index, axis=axis) for index in (0, size - 1, 1))
        apart = ambient.inverse_retract(first, last)[..., held] / scales
        step = ambient.inverse_retract(first, second)[..., held] / scales
        if np.max(np.abs(apart)) <= 1e-9 < np.max(np.abs(step)):
            axes.append(axis)
    return axes


def _wrapped(neighbours, axes, shape):
    """`neighbours` (:func:`grid_neighbours`) with each periodic axis closed on itself, both ways.

    The two ends of a periodic axis are one configuration: each is a neighbour of the other, and of the points
    next to the other end (one step back from the first point is the point before the last, one step on from the
    last is the point after the first, and the other way round). The grid's result then does not depend on which
    end a user called which (the hybrid's 3-D grid over a whole turn of A reached 844 or 980 points by the sign of
    A's axis), and continuation walks across the ends (the links were one-sided: a front never crossed them).

    Returns
    -------
    ndarray, shape=[n, 2d + 2p]
        p the number of periodic axes. First, per periodic axis, the other end (-1 off the ends): continuation
        takes the first reached neighbour of a point in column order, and from the other end it is a step of
        zero. Then the 2d columns of `neighbours` (column 2a of the first point of a periodic axis a the point
        before its last, column 2a + 1 of its last the point after its first). Last, per periodic axis, the
        other end again for the point after the first (the last) and the point before the last (the first).
    """
    if not axes:
        return neighbours
    flat = np.arange(len(neighbours)).reshape(shape)
    neighbours = neighbours.copy()
    ends = np.full((len(neighbours), len(axes)), -1, dtype=neighbours.dtype)
    across = np.full((len(neighbours), len(axes)), -1, dtype=neighbours.dtype)
    for column, axis in enumerate(axes):
        size = shape[axis]
        first, last = np.take(flat, 0, axis=axis).ravel(), np.take(flat, size - 1, axis=axis).ravel()
        after_first, before_last = np.take(flat, 1, axis=axis).ravel(), np.take(flat, size - 2, axis=axis).ravel()
        neighbours[first, 2 * axis] = before_last
        neighbours[last, 2 * axis + 1] = after_first
        ends[first, column], ends[last, column] = last, first
        across[after_first, column] = last
        across[before_last, column] = first  # of three points, the middle one: both ends are its neighbours already
    return np.concatenate([ends, neighbours, across], axis=1)


def assemble_grid(mechanism, start, targets, shape, held, bar=None, with_start=False, constraint_rank=None):
    """Every grid point assembled by continuation over the grid from a configuration (see the module notes).

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
        The starting configuration, on M.
    targets : ndarray, shape=[n, point_size]
        The grid points in C order: the held entries are the values to hold.
    shape : tuple of int
        The grid's shape (n = its product).
    held : sequence of int
        The held tangent coordinates (:func:`held_columns`).
    bar : progress bar, optional
        Updated by the number of points reached.
    with_start : bool
        Also return where the continuation started.
    constraint_rank : int, optional
        The rank of DΦ·s on M (the survey's): a start at a C-space singularity is singular then, and the whole
        grid is continued from a regular neighbour (:func:`regular_start`), none of it from the start (where
        branches of M cross, the start's own continuation may take another branch than the neighbour's); by
        default only a start singular for the held coordinates is.

    Returns
    -------
    points : ndarray, shape=[n, point_size]
        NaN rows where unreachable.
    reached : ndarray of bool, shape=[n]
    starting : StartingPoint
        With `with_start`: the given start (``moved`` 0; ``singular`` and ``margin`` there), or the regular
        neighbour the grid's unreached points were started from.
    """
    from mechanisms.kinematics import kinematics_of

    ambient = kinematics_of(mechanism).ambient
    held = np.asarray(held, dtype=int)
    entries = held_entries(ambient, held)
    targets = np.asarray(targets, dtype=float)
    given = np.asarray(start, dtype=float)
    here = None      # the given start as a StartingPoint, once needed
    starting = None  # where the continuation started, once known
    left = False     # whether the given start has been left for its regular neighbour (or none was found)
    count = len(targets)
    periodic = _periodic_axes(ambient, targets, shape, held)
    neighbours = _wrapped(grid_neighbours(shape), periodic, shape)
    ends = neighbours[:, :len(periodic)]  # the other end of each closed axis (-1 off its ends)
    points = np.full(targets.shape, np.nan)
    reached = np.zeros(count, dtype=bool)
    tried = np.zeros(neighbours.shape, dtype=bool)
    started = np.zeros(count, dtype=bool)
    distance = _held_distances(ambient, start, targets, held)
    candidates = np.zeros(0, dtype=np.int64)
    if constraint_rank is not None:
        here = _given_start(mechanism, given, held, constraint_rank)
        if here.cspace:  # a C-space singularity: none of the grid from it
            starting, left = _neighbour_of(mechanism, here, held, constraint_rank), True
            start = starting.point
            distance = _held_distances(ambient, start, targets, held)
    while True:
        if candidates.size:  # a continuation front: each from one reached neighbour not tried yet
            around = neighbours[candidates]
            usable = (around >= 0) & reached[np.maximum(around, 0)] & ~tried[candidates]
            keep = usable.any(axis=1)
            candidates, around, usable = candidates[keep], around[keep], usable[keep]
        if candidates.size:
            # an end of a closed axis whose other end (of lower index) is in this front waits for it, then follows
            # it by a step of zero: the two ends are one configuration
            partners = ends[candidates]
            waiting = ((partners >= 0) & (partners < candidates[:, None])
                       & np.isin(partners, candidates)).any(axis=1)
            waiters, candidates, around, usable = (candidates[waiting], candidates[~waiting], around[~waiting],
                                                   usable[~waiting])
            direction = np.argmax(usable, axis=1)
            origins = around[np.arange(candidates.size), direction]
            tried[candidates, direction] = True
            found, ok = _continue(mechanism, points[origins], targets[candidates], held, entries)
            won = candidates[ok]
            points[won], reached[won] = found[ok], True
            if bar is not None:
                bar.update(int(won.size))
            following = neighbours[won].reshape(-1)
            following = following[following >= 0]
            candidates = np.unique(np.concatenate([candidates[~ok], waiters, following[~reached[following]]]))
            continue
        seed = _seed(mechanism, start, targets, held, entries, distance,
                     np.flatnonzero(~reached & ~started & ~tried.any(axis=1)), started)
        if seed is None and not left and not reached.all():  # points left that the start reaches not
            here = here or _given_start(mechanism, given, held, constraint_rank)
            starting, left = (_neighbour_of(mechanism, here, held, constraint_rank) if here.singular else here), True
            if starting.moved:  # a singular start: the rest of the grid from its regular neighbour
                start = starting.point
                distance = _held_distances(ambient, start, targets, held)
                started = reached.copy()
                tried[~reached] = False  # a try from the singular start is no try from its neighbour
                continue
        if seed is None:
            break
        index, point = seed
        points[index], reached[index] = point, True
        if bar is not None:
            bar.update(1)
        candidates = neighbours[index][neighbours[index] >= 0]
        candidates = candidates[~reached[candidates]]
    if with_start:
        return points, reached, starting or here or _given_start(mechanism, given, held, constraint_rank)
    return points, reached


def _held_distances(ambient, start, targets, held):
    """Dimensionless distance of each grid point's held coordinates from the start's, shape=[n]."""
    return np.linalg.norm(ambient.inverse_retract(start, targets)[:, held] / ambient.tangent_scales[held], axis=-1)


def _seed(mechanism, start, targets, held, entries, distance, fresh, started):
    """The grid point nearest the starting configuration (among `fresh`) that continuation from it reaches;
    (index, configuration) or None. The points are tried nearest first, in chunks that double in size (the first
    is usually the one), and marked in `started`."""
    order = fresh[np.argsort(distance[fresh], kind="stable")]
    begin, size = 0, _SEED_CHUNK
    while begin < order.size:
        chunk = order[begin:begin + size]
        started[chunk] = True
        found, ok = _continue(mechanism, np.broadcast_to(start, targets[chunk].shape), targets[chunk], held,
                              entries)
        if ok.any():
            first = int(np.argmax(ok))
            return int(chunk[first]), found[first]
        begin, size = begin + size, min(2 * size, _SEED_CHUNK_LIMIT)
    return None


def assemble_branches(mechanism, start, targets, shape, held, count, rng, probes=8, tries=16, constraint_rank=None):
    """The grid assembled on the start's branch and on up to ``count − 1`` other assembly branches (module notes).

    Parameters
    ----------
    mechanism : Mechanism
    start : ndarray, shape=[point_size]
    targets : ndarray, shape=[n, point_size]
    shape : tuple of int
    held : sequence of int
    count : int
        The most branches (≥ 1; 1: :func:`assemble_grid` alone).
    rng : numpy.random.Generator
        For the probes and the random free coordinates.
    probes : int
        Grid points where the loops are solved from random values.
    tries : int
        Random values per probe.
    constraint_rank : int, optional
        The rank of DΦ·s on M, for the first branch's start (:func:`assemble_grid`).

    Returns
    -------
    points : ndarray, shape=[b, n, point_size]
        Per branch, NaN rows where not reached (or reached by an earlier branch).
    reached : ndarray of bool, shape=[b, n]
    starting : StartingPoint
        Where the first branch's continuation started (:func:`assemble_grid`).
    solutions : int
        Distinct solutions the probes found (before they were assembled into branches).
    """
    from mechanisms.kinematics import closes, kinematics_of

    ambient = kinematics_of(mechanism).ambient
    scales = ambient.tangent_scales
    targets = np.asarray(targets, dtype=float)
    held = np.asarray(held, dtype=int)
    first, reached, starting = assemble_grid(mechanism, start, targets, shape, held, with_start=True,
                                             constraint_rank=constraint_rank)
    points, masks = [first], [reached]
    if count <= 1:
        return np.array(points), np.array(masks), starting, 0
    free = np.setdiff1d(np.arange(ambient.dim), held)
    entries = held_entries(ambient, held)
    chosen = np.sort(rng.choice(len(targets), size=min(probes, len(targets)), replace=False))
    which = np.repeat(chosen, tries)
    tangent = np.zeros((which.size, ambient.dim))
    tangent[:, free] = rng.uniform(-np.pi, np.pi, (which.size, free.size)) * scales[free]
    guesses = ambient.retract(targets[which], tangent)
    guesses[:, entries] = targets[which][:, entries]
    # onto the closing map first: from far starts, Gauss-Newton on Φ ends at half-turns for most loops
    guesses = _correct(mechanism, guesses, free, 8 * _CORRECTOR_ITERATIONS, closing=True)[0]
    solved, residuals = _correct(mechanism, guesses, free, 8 * _CORRECTOR_ITERATIONS)
    good = (residuals <= _TOLERANCE) & np.asarray(closes(mechanism, solved, _TOLERANCE), dtype=bool)
    solved, which = solved[good], which[good]

    def known(point, index):
        others = [branch[index] for branch, mask in zip(points, masks) if mask[index]]
        return bool(others) and np.min(np.linalg.norm(
            ambient.inverse_retract(np.array(others), point) / scales, axis=-1)) <= BRANCH_SEPARATION

    distinct = []
    for point, index in zip(solved, which):
        if not any(index == other and np.linalg.norm(ambient.inverse_retract(found, point) / scales)
                   <= BRANCH_SEPARATION for found, other in distinct) and not known(point, index):
            distinct.append((point, index))
    for point, index in distinct:
        if len(points) >= count:
            break
        if known(point, index):
            continue
        branch, mask = assemble_grid(mechanism, point, targets, shape, held)
        for index_reached in np.flatnonzero(mask):  # left to an earlier branch where they coincide
            if known(branch[index_reached], index_reached):
                mask[index_reached] = False
        branch[~mask] = np.nan
        if mask.any():
            points.append(branch)
            masks.append(mask)
    return np.array(points), np.array(masks), starting, len(distinct)
