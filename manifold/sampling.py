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
from .implicit import jacobian_rank, project
from .rank import DEFAULT_ATOL, DEFAULT_RTOL, numerical_rank

__all__ = ["LocalRank", "local_rank", "sample_manifold", "largest_rank"]

#: a random point is projected onto ``manifold.closing`` until its residual is below this (then onto Φ, to
#: Φ's own tolerance): close enough that Gauss-Newton on Φ converges to the same point of M
CLOSING_TOLERANCE = 1e-6
#: iterations allowed on the closing map, whose projection is damped (Levenberg-Marquardt: from far away
#: Gauss-Newton's steps wander; the map jumps across half-turns and has local minima): of 48 random starts of
#: an RSUR loop 36 reached it within 30 iterations, 46 within 60, all 48 within 100
CLOSING_ITERATIONS = 100


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


def sample_manifold(manifold, rng, starts, random_count=24, walk_count=24, step=0.3):
    """Points of M spread over its assembly branches.

    Two sources: Gauss-Newton from random points of K (angles and rotations
    uniform, lengths normal about the start; reaching
    other assembly branches), and a random walk on M from each start
    (exploring the start's branch). A random point is projected onto
    ``manifold.closing`` first where there is one (a map without Φ's
    spurious zeros, which would otherwise catch most of them; a damped
    projection, see :func:`~manifold.project`), then onto Φ.

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
    for guess in ambient.random_point(rng, center=starts[0], size=random_count):
        try:
            if manifold.closing is not None:
                guess = project(manifold.closing, guess, tolerance=CLOSING_TOLERANCE, max_step=1.0,
                                max_iterations=CLOSING_ITERATIONS, damped=True)
            samples.append(project(manifold, guess, max_step=1.0))
        except ProjectionError:
            continue
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
