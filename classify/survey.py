"""Global survey of a mechanism's C-space: the largest ranks reached on M.

docs/design.rst: the expected ranks of G and J are ``min(m, the largest rank G
reaches on M)`` and ``min(dim N, m, the largest rank J reaches on M)``. The
largest ranks are estimated from points of M spread over several assembly
branches (:func:`manifold.sample_manifold`); the estimate and the number of
samples are reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from manifold import DEFAULT_RTOL, largest_rank, numerical_rank, sample_manifold, tangent_basis

from .metrics import metric_root

__all__ = ["Survey", "survey"]


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
        by its own largest singular value (None without end-effector). Where
        both largest ranks are reached, ``joint_rank − actuator_rank`` is the
        number of locked-actuator freedoms that move the end-effector.
    """

    samples: int
    constraint_rank: int
    actuator_rank: int
    end_effector_rank: object
    joint_rank: object = None

    @property
    def moving_idle_freedoms(self):
        """How many of the idle freedoms move the end-effector (0 without end-effector).

        An idle freedom that moves the end-effector means that, with the
        actuators locked, the end-effector is not fixed anywhere on M: an
        architecture singularity (e.g. a Gough–Stewart platform with similar
        hexagons, Gosselin & Angeles 1990 eq. 87), or
        a motion the task ignores (the spin of an axisymmetric tool).
        """
        return 0 if self.joint_rank is None else max(0, self.joint_rank - self.actuator_rank)

    def to_dict(self):
        return {"samples": self.samples, "constraint_rank": self.constraint_rank,
                "actuator_rank": self.actuator_rank, "end_effector_rank": self.end_effector_rank,
                "joint_rank": self.joint_rank}


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
    bases = [tangent_basis(manifold, point, rtol=rtol)[0] for point in points]
    actuators = model.actuators
    actuator_scale = float(np.linalg.norm(actuators, 2)) if actuators.size else 0.0
    constraint_rank = largest_rank(manifold.constraint_jacobian, points, rtol=rtol)
    actuator_rank = largest_rank(lambda index: actuators @ bases[index], range(len(points)), rtol=rtol,
                                 scale=actuator_scale)
    end_effector_rank = joint_rank = None
    if model.end_effector_dimension > 0:
        root = metric_root(model.end_effector_metric)
        actuator_unit = actuators / actuator_scale if actuator_scale else actuators
        end_effector_rank = joint_rank = 0
        for point, basis in zip(points, bases):
            jacobian = root @ model.end_effector_jacobian(point)
            scale = float(np.linalg.norm(jacobian, 2))
            end_effector_rank = max(end_effector_rank,
                                    numerical_rank(jacobian @ basis, rtol=rtol, scale=scale).rank)
            stacked = np.vstack([actuator_unit @ basis, jacobian @ basis / max(scale, 1e-300)])
            joint_rank = max(joint_rank, numerical_rank(stacked, rtol=rtol, scale=1.0).rank)
    return Survey(len(points), constraint_rank, actuator_rank, end_effector_rank, joint_rank)
