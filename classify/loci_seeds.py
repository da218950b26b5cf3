"""Where the loci are traced and searched from: seeds over a grid or along a branch of M, and local minima.

The seeds of a 2-dof grid are the reached points where a sign function
vanishes, the edges along which it changes sign and the edges from a
reached point to an unreached one; along a traced branch of M (1 dof), the
points before a sign change or where it vanishes; the seeds of a search
(:mod:`classify.loci_search`) are the local minima of a singular value over
a grid or along the branches (see :mod:`classify.loci`).

References
----------
Park & Kim 1999, Section 3 (the loci the seeds start).
"""

from __future__ import annotations

import numpy as np

from .loci_signs import ZERO_TOLERANCE


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
