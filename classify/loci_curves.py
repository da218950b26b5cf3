"""The curves of the loci on M, {Φ = 0, s = 0} (3 dof: and a section), followed by a predictor–corrector.

A curve is an implicit manifold: M's constraints Φ with one more row per
function on K (a sign function s, a section coordinate h), whose gradients
are central differences (step 1e-6, dimensionless). A point is corrected
onto it by Gauss–Newton (:func:`manifold.project`, to :data:`TOLERANCE`);
the curve is followed from it along the null vector of its Jacobian, both
ways, until it comes back to its start, a corrector fails four times halved,
or :data:`STEP_LIMIT` steps (see :mod:`classify.loci`).

References
----------
Park & Kim 1999, Section 3 (the loci the curves trace).
"""

from __future__ import annotations

import numpy as np

__all__ = ["TOLERANCE", "STEP_LIMIT"]

#: ‖(Φ, s)‖ of a corrected locus point
TOLERANCE = 1e-11
#: most predictor–corrector steps along one curve, each way
STEP_LIMIT = 1500
#: finite-difference step of ∇s (dimensionless)
_DIFFERENCE = 1e-6


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


#: a curve point where σ_min of its scaled Jacobian (one row short of square) is at most this relative to σ₁ is
#: where branches cross (the rank cut of :data:`manifold.DEFAULT_RTOL`)
CROSSING_RTOL = 1e-6


def _is_crossing(curve, point):
    """Whether the curve's Jacobian has a null space of more than one line at `point` (two branches cross):
    the direction a trace would leave it along is then arbitrary (it changed with the base frame)."""
    jacobian = np.asarray(curve.constraint_jacobian(point), dtype=float) * curve.ambient.tangent_scales
    if not 0 < jacobian.shape[0] < jacobian.shape[1]:
        return False
    values = np.linalg.svd(jacobian, compute_uv=False)
    return bool(values[-1] <= CROSSING_RTOL * values[0])


def _trace_from_seeds(curve, seeds, step):
    """The curves through the seeds (each seed corrected onto the curve first; seeds on a traced curve skipped).

    Seeds where two branches of the curve cross are taken last: a trace from one leaves along an arbitrary
    branch, so the pieces would depend on the frame where another seed traces the same curves."""
    from manifold import project_each

    ambient = curve.ambient
    projected, reached = project_each(curve, seeds, tolerance=TOLERANCE, max_step=4 * step)  # as _correct, at once
    corrected = list(projected[reached])
    crossing = [_is_crossing(curve, on) for on in corrected]
    traced = []
    for on in [on for on, at in zip(corrected, crossing) if not at] + [on for on, at in zip(corrected, crossing) if at]:
        if any(_distances(ambient, on[None], points)[0] < 2 * step for points, _ in traced):
            continue
        traced.append(_trace(curve, on, step))
    return traced


def _residuals(curve, points):
    return np.linalg.norm(curve.constraint(points), axis=-1)
