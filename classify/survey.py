"""Global survey of a mechanism's C-space: the largest ranks reached on M.

docs/design.rst, "The three kinds": the expected ranks are ``m − i`` for G,
with i the number of idle freedoms, and ``min(dim N, m, the largest rank J
reaches on M)`` for J. The largest ranks are estimated from points of M
spread over several assembly branches (:func:`manifold.sample_manifold`),
those of G, J and the stacked map at the samples where DΦ has its largest
rank only (at a C-space singularity ker DΦ is larger than the tangent spaces
of M); the estimate and the number of samples are reported.

Every rank is decided in dimensionless form: DΦ·diag(s), the unit actuator
rows (:func:`classify.metrics.unit_rows`) and H^½ Df over its own scale, on
tangent bases orthonormal for the dimensionless inner product.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manifold import DEFAULT_RTOL, numerical_rank, sample_manifold, tangent_basis

from .metrics import largest_singular_value, metric_root, unit_rows

__all__ = ["Survey", "survey", "decision_rows", "decision_blocks", "freedom_rows"]


@dataclass(frozen=True, eq=False)
class Survey:
    """Largest ranks reached over sampled points of M.

    Attributes
    ----------
    samples : int
        Number of points of M used.
    constraint_rank : int
        Largest rank of DΦ.
    actuator_rank : int
        Largest rank of G.
    end_effector_rank : int or None
        Largest rank of J (None without end-effector).
    joint_rank : int or None
        Largest rank of the stacked map (E^½Dπ T; H^½Df T), each block scaled
        by its own largest singular value (None without end-effector).
        ``m − joint_rank`` freedoms move neither an actuator nor the
        end-effector: the idle freedoms.
    """

    samples: int
    constraint_rank: int
    actuator_rank: int
    end_effector_rank: object
    joint_rank: object = None

    @property
    def freedom_rank(self):
        """The largest rank of the map whose kernel is the idle freedoms: the stacked map, or G without
        end-effector."""
        return self.actuator_rank if self.joint_rank is None else self.joint_rank

    @property
    def moving_idle_freedoms(self):
        """How many locked-actuator freedoms move the end-effector everywhere on M (0 without one).

        ``joint_rank − actuator_rank``. Such a freedom is not idle: with the
        actuators locked the end-effector is not fixed anywhere on M, the
        design is architecturally singular (e.g. a Gough–Stewart platform
        with similar hexagons, Gosselin & Angeles 1990 eq. 87, or a 5-SPU
        whose pose output sees the tool's spin).
        """
        return 0 if self.joint_rank is None else max(0, self.joint_rank - self.actuator_rank)

    def idle_freedoms(self, dof):
        """i = m − the largest rank of the stacked map (of G without end-effector), for m = `dof`."""
        return max(0, dof - self.freedom_rank)

    def to_dict(self):
        return {"samples": self.samples, "constraint_rank": self.constraint_rank,
                "actuator_rank": self.actuator_rank, "end_effector_rank": self.end_effector_rank,
                "joint_rank": self.joint_rank}


def decision_rows(model, point):
    """The dimensionless maps whose ranks are decided at a point, on joint rates, with their scales.

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]

    Returns
    -------
    actuator : ndarray, shape=[a, k]
        ``unit_rows(E^½ Dπ)`` (reference scale 1 per row).
    actuator_scale : float
        σ₁ of ``unit_rows(E^½ Dπ)·diag(s)``.
    end_effector : ndarray, shape=[n, k] or None
        ``H^½ Df``.
    end_effector_scale : float or None
        σ₁ of ``H^½ Df·diag(s)``.
    """
    scales = model.manifold.ambient.tangent_scales
    actuators = unit_rows(model.actuators, scales)
    actuator_scale = largest_singular_value(actuators * scales)
    if not model.end_effector_dimension:
        return actuators, actuator_scale, None, None
    jacobian = metric_root(model.end_effector_metric) @ model.end_effector_jacobian(point)
    return actuators, actuator_scale, jacobian, largest_singular_value(jacobian * scales)


def decision_blocks(model, point, basis):
    """:func:`decision_rows` restricted to a tangent basis (from :func:`manifold.tangent_basis`): the
    blocks ``[a, m]`` and ``[n, m]`` (None without end-effector) with the same scales."""
    actuator, actuator_scale, end_effector, end_effector_scale = decision_rows(model, point)
    return (actuator @ basis, actuator_scale, None if end_effector is None else end_effector @ basis,
            end_effector_scale)


def _stacked(actuator, actuator_scale, end_effector, end_effector_scale):
    """The actuator rows over their scale, with the end-effector rows over theirs below them (if any):
    the map whose kernel is the idle freedoms, decided with reference scale 1."""
    rows = [actuator / max(actuator_scale, 1e-300)]
    if end_effector is not None:
        rows.append(end_effector / max(end_effector_scale, 1e-300))
    return np.vstack(rows)


def freedom_rows(model, point):
    """The stacked dimensionless rows at `point` whose kernel on T_qM is the idle freedoms, shape=[a + n, k]
    (the actuator rows alone without end-effector)."""
    return _stacked(*decision_rows(model, point))


def survey(model, rng, starts=None, random_count=24, walk_count=24, rtol=DEFAULT_RTOL):
    """Sample M globally and record the largest ranks of DΦ, G and J.

    Parameters
    ----------
    model : Model
    rng : numpy.random.Generator
    starts : array_like, shape=[n, point_size], optional
        Points of M to walk from; default ``model.starts``.
    random_count, walk_count : int
        See :func:`manifold.sample_manifold`.

    Returns
    -------
    Survey
    """
    manifold = model.manifold
    starts = model.starts if starts is None else np.atleast_2d(starts)
    points = sample_manifold(manifold, rng, starts, random_count=random_count, walk_count=walk_count)
    bases = [tangent_basis(manifold, point, rtol=rtol) for point in points]
    constraint_rank = max(decision.rank for _, decision in bases)
    actuator_rank = 0
    end_effector_rank = joint_rank = None if not model.end_effector_dimension else 0
    for point, (basis, decision) in zip(points, bases):
        if decision.rank < constraint_rank:
            continue  # a C-space singularity: ker DΦ is larger than the tangent spaces of M
        blocks = decision_blocks(model, point, basis)
        actuator, actuator_scale, end_effector, end_effector_scale = blocks
        actuator_rank = max(actuator_rank, numerical_rank(actuator, rtol=rtol, scale=actuator_scale).rank)
        if end_effector is None:
            continue
        end_effector_rank = max(end_effector_rank,
                                numerical_rank(end_effector, rtol=rtol, scale=end_effector_scale).rank)
        joint_rank = max(joint_rank, numerical_rank(_stacked(*blocks), rtol=rtol, scale=1.0).rank)
    return Survey(len(points), constraint_rank, actuator_rank, end_effector_rank, joint_rank)
