"""Continuation of a curve on an implicit manifold, for self-motion certificates.

From a point p̄ and a direction d, a predictor-corrector walk follows
the solution set of Φ = 0: predict ``q ⊕ h·d``, correct by Gauss-Newton, take
the secant as the next direction. A step is kept only where the midpoint of
its secant is within :data:`MIDPOINT_FRACTION` of its length from M (on a
curve of curvature κ it is κh²/8 away; a corrector that jumped to another
branch of M, a line passing near an isolated point, leaves it about half
as far as the jump). A curve that reaches distance ≥ `length` from p̄ with every
corrector converged and every midpoint near M is a certificate that p̄ is
not isolated in that direction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ProjectionError
from .implicit import project

__all__ = ["CurveCertificate", "continue_curve", "MIDPOINT_FRACTION"]

#: largest distance from M (dimensionless) of a step's secant midpoint, as a fraction of the step's length:
#: 1/10 allows curvature up to 0.8/h (a circle of radius 1.25 h), and refuses a jump to another branch
#: farther than about h/5 (the midpoint of a secant to a branch at distance d is about d/2 from M)
MIDPOINT_FRACTION = 0.1


@dataclass(frozen=True, eq=False)
class CurveCertificate:
    """A piece of curve on M through a start point.

    Attributes
    ----------
    reached : bool
        Whether the curve reached the requested distance.
    distance : float
        Largest scaled distance from the start reached.
    points : ndarray, shape=[steps + 1, point_size]
        The corrected points, the start first.
    largest_residual : float
        Largest ‖Φ‖ over the points.
    direction : ndarray, shape=[k]
        The initial direction, unit length.
    """

    reached: bool
    distance: float
    points: np.ndarray
    largest_residual: float
    direction: np.ndarray


def continue_curve(manifold, point, direction, length=0.1, step=0.01, tolerance=1e-10, max_steps=None):
    """Follow M from `point` along `direction` up to distance `length`.

    Parameters
    ----------
    manifold : ImplicitManifold
    point : array_like, shape=[point_size]
        A point of M.
    direction : array_like, shape=[k]
        Initial tangent direction (normalised here).
    length : float
        Distance to reach, in units of the coordinate scales.
    step : float
        Predictor step, same units.
    tolerance : float
        Residual required of every corrected point.
    max_steps : int, optional
        Default ``4 · length / step``.

    Returns
    -------
    CurveCertificate
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    start = np.asarray(point, dtype=float)
    direction = np.asarray(direction, dtype=float) / scales
    direction = direction / np.linalg.norm(direction)
    initial = direction.copy()
    max_steps = int(np.ceil(4 * length / step)) if max_steps is None else max_steps
    points = [start]
    current = start
    distance = 0.0
    largest = float(np.linalg.norm(manifold.constraint(start)))
    for _ in range(max_steps):
        guess = ambient.retract(current, step * scales * direction)
        try:
            corrected = project(manifold, guess, tolerance=tolerance, max_step=step)
        except ProjectionError:
            break
        secant = ambient.inverse_retract(current, corrected) / scales
        advance = np.linalg.norm(secant)
        if advance < 0.25 * step or advance > 2.0 * step:
            break
        new_distance = float(np.linalg.norm(ambient.inverse_retract(start, corrected) / scales))
        if new_distance <= distance or not _joined(manifold, current, secant, advance, tolerance, step):
            break
        points.append(corrected)
        largest = max(largest, float(np.linalg.norm(manifold.constraint(corrected))))
        direction = secant / advance
        current = corrected
        distance = new_distance
        if distance >= length:
            break
    return CurveCertificate(distance >= length, distance, np.array(points), largest, initial)


def _joined(manifold, current, secant, advance, tolerance, step):
    """Whether the midpoint ``current ⊕ ½ secant`` (dimensionless secant) projects onto M within
    :data:`MIDPOINT_FRACTION` · `advance` of itself: a curve of M joins the two points."""
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    middle = ambient.retract(current, 0.5 * secant * scales)
    try:
        on = project(manifold, middle, tolerance=tolerance, max_step=step)
    except ProjectionError:
        return False
    return float(np.linalg.norm(ambient.inverse_retract(middle, on) / scales)) <= MIDPOINT_FRACTION * advance
