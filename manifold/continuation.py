"""Continuation of a curve on an implicit manifold, for self-motion certificates.

From a point p̄ and a direction d, a predictor-corrector walk follows
the solution set of Φ = 0: predict ``q ⊕ h·d``, correct by Gauss-Newton, take
the secant as the next direction. A curve that reaches distance ≥ `length`
from p̄ with every corrector converged is a certificate that p̄ is not
isolated in that direction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ProjectionError
from .implicit import project

__all__ = ["CurveCertificate", "continue_curve"]


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
            corrected = project(manifold, guess, tolerance=tolerance, max_step=step * scales.max())
        except ProjectionError:
            break
        secant = ambient.inverse_retract(current, corrected) / scales
        advance = np.linalg.norm(secant)
        if advance < 0.25 * step or advance > 2.0 * step:
            break
        new_distance = float(np.linalg.norm(ambient.inverse_retract(start, corrected) / scales))
        if new_distance <= distance:
            break
        points.append(corrected)
        largest = max(largest, float(np.linalg.norm(manifold.constraint(corrected))))
        direction = secant / advance
        current = corrected
        distance = new_distance
        if distance >= length:
            break
    return CurveCertificate(distance >= length, distance, np.array(points), largest, initial)
