"""Local minima of an even function on the unit sphere: the root searches of the second- and higher-order tests.

Both tests look for the directions v of K = ker G (unit vectors, up to sign)
where a function of v vanishes: the second-order forms Q_e(v)
(:func:`classify.second_order.common_roots`), the higher-order obstructions
(:mod:`classify.higher_order`). The search is the same: in dimension 2 a scan
of the half circle (the function is even, so v and −v are one direction) with
every local minimum of the scan refined by bounded minimisation of the angle;
in higher dimensions the lowest of many starts, each refined by a local
method; then the minima, lowest first, without repeats up to sign.
"""

from __future__ import annotations

import numpy as np

__all__ = ["sphere_minima", "distinct_directions"]

#: two unit vectors are one direction when |cos| between them is at least 1 − PARALLEL
PARALLEL = 1e-6


def sphere_minima(function, dimension, starts=None, limit=None, scan=180, closed=False, xatol=1e-10, refine=None):
    """Local minima of an even function on the unit sphere of ℝ^dimension, in the order they were refined.

    Dimension 2: `scan` angles of the half circle [0, π) (and π itself when
    `closed`: a minimum at the ends is then refined from both), the local
    minima of the scan (cyclically: angle π is angle 0) refined by bounded
    minimisation of the angle within one scan step, to `xatol`. Higher: the
    `limit` `starts` of lowest value, each refined by `refine` (default
    Nelder–Mead of ``function(y / |y|)`` to `xatol`). A minimum can be missed
    in dimension ≥ 3.

    Parameters
    ----------
    function : callable
        ``function(vectors) -> values``, vectors of shape=[n, dimension], values of shape=[n].
    dimension : int
        At least 2.
    starts : ndarray, shape=[n, dimension], optional
        The starting vectors in dimension ≥ 3 (required there).
    limit : int, optional
        How many scan minima or starts are refined, lowest first; default
        every scan minimum, in scan order (and every start).
    scan : int
        Angles of the half circle scanned in dimension 2.
    closed : bool
        Whether the scan also takes the angle π.
    xatol : float
        Tolerance of the refinement, in the angle or the vector.
    refine : callable, optional
        ``refine(start) -> (value, vector)`` in dimension ≥ 3.

    Returns
    -------
    list of tuple
        ``(value, vector, start)``: the refined minimum (`vector` unit for
        the default refinements) and the scan point or start it came from.
        Not deduplicated (see :func:`distinct_directions`).
    """
    import scipy.optimize  # here, not at start-up: only actuator singularities need it

    if dimension == 2:
        angles = np.linspace(0.0, np.pi, scan + 1)
        angles = angles if closed else angles[:-1]
        circle = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
        values = function(circle)
        step = angles[1] - angles[0]
        count = len(values)
        previous = values[(np.arange(count) - 1) % scan]
        following = values[np.r_[np.arange(1, count), count % scan]]
        lower = np.flatnonzero((values <= previous) & (values <= following))
        chosen = lower if limit is None else lower[np.argsort(values[lower])][:limit]
        found = []
        for index in chosen:
            result = scipy.optimize.minimize_scalar(
                lambda angle: function(np.array([[np.cos(angle), np.sin(angle)]]))[0],
                bounds=(angles[index] - step, angles[index] + step), method="bounded", options={"xatol": xatol})
            found.append((float(result.fun), np.array([np.cos(result.x), np.sin(result.x)]), circle[index]))
        return found

    if refine is None:
        def refine(start):
            result = scipy.optimize.minimize(lambda y: function((y / np.linalg.norm(y))[None])[0], start,
                                             method="Nelder-Mead", options={"xatol": xatol, "fatol": 1e-14})
            return float(result.fun), result.x / np.linalg.norm(result.x)

    values = function(starts)
    return [(*refine(starts[index]), starts[index]) for index in np.argsort(values, kind="stable")[:limit]]


def distinct_directions(vectors, values=None):
    """Indices of unit vectors that are distinct up to sign, lowest value first.

    A vector is kept unless it is parallel or antiparallel (``|cos|`` ≥ 1 −
    :data:`PARALLEL`) to one kept before it, in the order of `values`
    (stable) or, without values, as given.

    Parameters
    ----------
    vectors : ndarray, shape=[n, d]
    values : ndarray, shape=[n], optional

    Returns
    -------
    list of int
    """
    order = range(len(vectors)) if values is None else np.argsort(values, kind="stable")
    kept = []
    for index in order:
        if all(abs(vectors[index] @ vectors[other]) < 1 - PARALLEL for other in kept):
            kept.append(int(index))
    return kept
