"""Sampling an implicit manifold: local rank, local dimension, global samples.

The rank r of DΦ *on M near p* is estimated by projecting a few random
points of a small ball around p back onto M and taking the largest rank of
DΦ found there (at a singular point of M, nearby points are regular). The
local dimension is then ``m = k − r`` (docs/design.rst, "Dimension").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ProjectionError
from . import implicit as implicit_module
from .implicit import handled_by_blocks, jacobian_rank, project, project_each, project_many, settle_blocks
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, numerical_rank

__all__ = ["LocalRank", "local_rank", "sample_manifold", "largest_rank", "TangentExtent", "tangent_extent",
           "tangent_extents", "EXTENT_STEP", "EXTENT_CUT"]

#: a random point is projected onto ``manifold.closing`` until its residual is below this (then onto Φ, to
#: Φ's own tolerance): close enough that Gauss-Newton on Φ converges to the same point of M
CLOSING_TOLERANCE = 1e-6
#: iterations allowed on the closing map, whose projection is damped (Levenberg-Marquardt: from far away
#: Gauss-Newton's steps wander; the map jumps across half-turns and has local minima): of 48 random starts of
#: an RSUR loop 36 reached it within 30 iterations, 46 within 60, all 48 within 100
CLOSING_ITERATIONS = 100
#: on a closing map handled block by block (:func:`~manifold.settle_blocks`): the cap of each block's part of a
#: Gauss-Newton step, the iterations a block is given to settle after each draw, the iterations allowed in all,
#: and how many random points are drawn at once for the blocks drawn again. Of 180 blocks of random starts of
#: RSUR loops, with steps capped at 1 (2, 3), 13% (52%, 51%) settled within 12 iterations, 34% (65%, 66%)
#: within 20: the expected iterations per settled block, patience / share settled, are least about (2, 12)
CLOSING_BLOCK_STEP, CLOSING_PATIENCE, CLOSING_BLOCK_ITERATIONS, CLOSING_DRAWS = 2.0, 12, 300, 8


@dataclass(frozen=True, eq=False)
class LocalRank:
    """Rank of DΦ on M near a point.

    Attributes
    ----------
    rank : int
        The largest rank of DΦ over the neighbours (and the point itself).
    dimension : int
        ``k − rank``, the local dimension of M.
    neighbours : ndarray, shape=[count, point_size]
        The points of M used.
    """

    rank: int
    dimension: int
    neighbours: np.ndarray


def local_rank(manifold, point, rng, count=6, radius=1e-3, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL):
    """Rank of DΦ on M in a small neighbourhood of `point`.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
        A point of M.
    rng : numpy.random.Generator
    count : int
        Number of neighbours sought (at most 4·count attempts: fewer may be found).
    radius : float
        Size of the random steps, relative to each coordinate's scale.

    Returns
    -------
    LocalRank
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    rank = jacobian_rank(manifold, point, rtol=rtol, atol=atol).rank
    neighbours = []
    attempts = 0
    while len(neighbours) < count and attempts < 4 * count:
        attempts += 1
        direction = rng.standard_normal(ambient.dim)
        direction /= np.linalg.norm(direction)
        guess = ambient.retract(point, radius * scales * direction)
        try:
            neighbour = project(manifold, guess, max_step=10 * radius)
        except ProjectionError:
            continue
        if np.linalg.norm(ambient.inverse_retract(point, neighbour) / scales) > 20 * radius:
            continue
        neighbours.append(neighbour)
        rank = max(rank, jacobian_rank(manifold, neighbour, rtol=rtol, atol=atol).rank)
    return LocalRank(rank, ambient.dim - rank, np.array(neighbours).reshape(-1, ambient.point_size))


#: dimensionless step h along each direction of ker DΦ(p) in :func:`tangent_extent`
EXTENT_STEP = 1e-3
#: a direction counts as one M extends along when its secant keeps more than this of its length: on M the
#: secant of a step h differs from the direction by O(κh) (κ the curvature), towards a point where M does not
#: extend it shrinks to O(h)
EXTENT_CUT = 0.5


@dataclass(frozen=True, eq=False)
class TangentExtent:
    """How many directions of ker DΦ(p) M extends along (:func:`tangent_extent`).

    Attributes
    ----------
    extent : int
        The number of singular values of the secant matrix above :data:`EXTENT_CUT`.
    singular_values : ndarray, shape=[m]
        Those of the secant matrix (1 along a direction M extends along, ≈ 0 along a flex).
    still : ndarray, shape=[k, m - extent]
        Joint-rate directions (columns of ``basis`` combined) along which M does not extend: infinitesimal
        motions (flexes) that no curve of M follows.
    moving : ndarray, shape=[k, extent]
        The other directions of ``basis`` (orthonormal to `still` in the same product): those M extends along.
    """

    extent: int
    singular_values: np.ndarray
    still: np.ndarray
    moving: np.ndarray


def tangent_extent(manifold, point, basis, step=EXTENT_STEP):
    """Along how many directions of ``ker DΦ(p)`` (the columns of `basis`) M extends from `point`.

    For each column t of `basis` (orthonormal for ⟨·,·⟩_s), the point ``p ⊕ h t`` is projected back onto M
    (:func:`manifold.project_many`) and the dimensionless secant ``(q ⊖ p) / (h s)`` kept. Where M is a
    manifold with tangent space ker DΦ(p), every secant is its direction up to O(κh) and the secant matrix has
    singular values ≈ 1. Where DΦ(p) has a kernel M does not follow — an infinitesimal flex of a structure
    that cannot move (a triangle with its sides flat, a four-bar fully stretched: M is a point there, yet DΦ
    loses rank; its rank on M near p is that rank, so k − rank overstates the dimension) — the projection
    returns towards p and the secant shrinks to O(h). The extent is the number of singular values above
    :data:`EXTENT_CUT`. The constraint map must take stacks of points; :func:`tangent_extents` does a stack
    of points at once, with the same arithmetic point by point.

    Resolution: M is seen at the scale h. A C-space that extends less than about h from p (a spatial 4R
    within ~5e-8 of a design that cannot move, whose C-space is a loop smaller than 1e-3) reads as a
    structure that only flexes. h cannot be made much smaller: along a flex the projection's residual
    tolerance leaves the point uncertain by about its square root (1e-6), which a secant over h must not reach.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
    basis : ndarray, shape=[k, m]
        A basis of ker DΦ(p) (:func:`manifold.tangent_basis`).
    step : float

    Returns
    -------
    TangentExtent
    """
    values, right_transposed = _secant_decompositions(manifold, np.asarray(point, dtype=float)[None],
                                                      np.asarray(basis, dtype=float)[None], step)
    extent = int(np.count_nonzero(values[0] > EXTENT_CUT))
    combined = np.asarray(basis, dtype=float) @ right_transposed[0].T
    return TangentExtent(extent, values[0], combined[:, extent:], combined[:, :extent])


def tangent_extents(manifold, points, bases, step=EXTENT_STEP):
    """:func:`tangent_extent` of a stack of points, shape=[n]: the extents alone.

    Parameters
    ----------
    manifold : ImplicitManifold
    points : ndarray, shape=[n, point_size]
    bases : ndarray, shape=[n, k, m]
    step : float

    Returns
    -------
    ndarray of int, shape=[n]
    """
    values, _ = _secant_decompositions(manifold, np.asarray(points, dtype=float), np.asarray(bases, dtype=float),
                                       step)
    return np.count_nonzero(values > EXTENT_CUT, axis=-1)


def _secant_decompositions(manifold, points, bases, step):
    """Singular values [n, m] and right singular vectors [n, m, m] of the secant matrices of
    :func:`tangent_extent`.

    The moved points are projected by :func:`~manifold.project_many` in chunks whose dense Jacobians hold
    about :data:`~manifold.implicit.CHUNK_ENTRIES` floats, or as :func:`~manifold.project` projects each
    (:func:`~manifold.project_each`, block by block: no dense Jacobian is formed) on a manifold handled block
    by block. A projection that stops short of
    its tolerance (at the rounding floor of a map with large entries) still gives its point: only a point
    that is not finite counts as a secant of zero.
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    count, k, width = bases.shape
    if not width:
        return np.zeros((count, 0)), np.zeros((count, 0, 0))
    starts = np.repeat(points, width, axis=0)                                       # [n·m, point_size]
    directions = np.swapaxes(bases, -1, -2).reshape(count * width, k)               # [n·m, k]
    predicted = ambient.retract(starts, step * directions)
    if handled_by_blocks(manifold):  # as project with steps capped at 2·step, NaN where it raises
        moved, reached = project_each(manifold, predicted, max_step=2 * step)
        moved[~reached] = np.nan
    else:
        rows = max(1, np.shape(manifold.constraint(points[:1]))[-1])
        chunk = max(1, implicit_module.CHUNK_ENTRIES // (rows * k))
        moved = np.concatenate([project_many(manifold, predicted[first:first + chunk])[0]
                                for first in range(0, len(predicted), chunk)])
    secants = ambient.inverse_retract(starts, moved) / scales / step                # [n·m, k]
    secants[~np.all(np.isfinite(secants), axis=-1)] = 0.0
    secants = np.swapaxes(secants.reshape(count, width, k), -1, -2)                 # [n, k, m]
    _, values, right_transposed = np.linalg.svd(secants, full_matrices=True)
    return values, right_transposed


def sample_manifold(manifold, rng, starts, random_count=24, walk_count=24, step=0.3):
    """Points of M spread over its assembly branches.

    Two sources: Gauss-Newton from random points of K (angles and rotations
    uniform, lengths normal about the start; reaching
    other assembly branches), and a random walk on M from each start
    (exploring the start's branch). A random point is projected onto
    ``manifold.closing`` first where there is one (a map without Φ's
    spurious zeros, which would otherwise catch most of them; a damped
    projection, see :func:`~manifold.project`), then onto Φ: all of them at
    once (:func:`~manifold.project_each`: the same iterations as
    :func:`~manifold.project` point by point, where Φ and DΦ take stacks of
    points as their contract says; a map written for one point is
    projected one point at a time). On a closing
    map handled block by block (M the product of its blocks' zero sets, see
    :mod:`manifold.implicit`, the note on sparsity) all the random points
    are settled at once, block by block, a block that does not settle drawn
    again from `rng` (:func:`~manifold.settle_blocks`): projected whole, a
    random point of a product of many loops nearly always has one loop at a
    critical point, and fails.

    Parameters
    ----------
    manifold : ImplicitManifold
    rng : numpy.random.Generator
    starts : array_like, shape=[n, point_size]
        Points of M to walk from (e.g. the home configuration).
    random_count : int
        Number of random starts in K.
    walk_count : int
        Number of random-walk steps per start.
    step : float
        Walk step, relative to the coordinate scales.

    Returns
    -------
    samples : ndarray, shape=[count, point_size]
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    samples = [start for start in starts]
    closing = manifold.closing
    guesses = ambient.random_point(rng, center=starts[0], size=random_count)
    settled = np.ones(len(guesses), dtype=bool)
    if closing is not None and _settles_blocks(closing):
        guesses, settled = _settled(closing, guesses, rng, starts[0])
    guesses = guesses[settled]
    if closing is not None:
        guesses, closed = project_each(closing, guesses, tolerance=CLOSING_TOLERANCE, max_step=1.0,
                                       max_iterations=CLOSING_ITERATIONS, damped=True)
        guesses = guesses[closed]
    projected, reached = project_each(manifold, guesses, max_step=1.0)
    samples.extend(projected[reached])
    for start in starts:
        current = start
        for _ in range(walk_count):
            direction = rng.standard_normal(ambient.dim)
            direction /= np.linalg.norm(direction)
            try:
                candidate = project(manifold, ambient.retract(current, step * scales * direction),
                                    max_step=step)
            except ProjectionError:
                continue
            samples.append(candidate)
            current = candidate
    return np.array(samples)


def _settles_blocks(closing):
    """Whether :func:`sample_manifold` settles random starts on the closing map block by block: handled block by
    block, and no block left to LSQR (:data:`~manifold.implicit.SPARSE_BLOCK_COLUMNS`)."""
    return handled_by_blocks(closing) and all(group.columns.shape[1] <= implicit_module.SPARSE_BLOCK_COLUMNS
                                              for group in closing.pattern.blocks)


def _settled(closing, guesses, rng, center):
    """Random starts `guesses` [n, point_size] settled on a closing map handled block by block
    (:func:`~manifold.settle_blocks`), and which settled: ``(points [n, point_size], settled [n])``.

    M is the product of the blocks' zero sets and the free columns (see
    :mod:`manifold.implicit`, the note on sparsity), so a block that does not
    settle takes its columns from a new random point (`rng`, reals about
    `center`, :data:`CLOSING_DRAWS` points drawn at a time) and the other
    columns stay: a product of many loops then closes as its loops do one by
    one, where projected all at once nearly every random start has a loop
    stuck at a critical point of its ‖Φ_b‖² that is no zero, and fails.
    """
    ambient = closing.ambient
    drawn = []  # random points not used yet

    def redraw(points, columns):
        if len(drawn) < len(points):
            drawn.extend(ambient.random_point(rng, center=center, size=max(CLOSING_DRAWS, len(points))))
        fresh = np.array([drawn.pop() for _ in points])
        return ambient.retract(points, np.where(columns, ambient.inverse_retract(points, fresh), 0.0))

    settled, unsettled = settle_blocks(closing, guesses, redraw, tolerance=CLOSING_TOLERANCE,
                                       max_iterations=CLOSING_BLOCK_ITERATIONS, max_step=CLOSING_BLOCK_STEP,
                                       patience=CLOSING_PATIENCE)
    return settled, ~unsettled.any(axis=-1)


def largest_rank(matrix_field, points, rtol=DEFAULT_RTOL, atol=DEFAULT_ATOL, scale=None):
    """The largest numerical rank a matrix field reaches over sample points.

    Parameters
    ----------
    matrix_field : callable
        ``matrix_field(point) -> array, shape=[rows, columns]``.
    points : iterable
        The arguments of `matrix_field`, usually points of shape [point_size].
    scale : float, optional
        Reference scale of every decision (see :func:`numerical_rank`).

    Returns
    -------
    rank : int
    """
    return max((numerical_rank(matrix_field(point), rtol=rtol, atol=atol, scale=scale).rank for point in points),
               default=0)
