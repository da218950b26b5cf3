"""What a classification needs, whatever produced it: :class:`Model`.

A :class:`Model` bundles an implicit C-space M ⊂ K, the (weighted) actuator
selection ``E^{1/2} Dπ`` and optionally the end-effector Jacobian and metric
H. :func:`model_of` builds one from a joint-graph mechanism; a user can build
one directly from an implicit description such as Park & Kim's eq. (8) for
the five-bar, and both are classified by the same code.
"""

from __future__ import annotations

import threading
import weakref
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

import numpy as np

from manifold import ImplicitManifold
from mechanisms import (
    checked_joint_names, configuration_space, end_effector_dimension, end_effector_jacobian, home, to_displacements,
)

from mechanisms.joints import joint_coordinate_names
from mechanisms.kinematics import end_effector_reference

from .metrics import end_effector_metric, weighted_actuator_jacobian

__all__ = ["Model", "model_of", "joint_output_model", "cache_lock", "cached"]

#: per model, the lock of its :attr:`Model.cache` (weakly keyed: a model that is gone takes its lock along; not
#: a field of the model, which stays picklable)
_CACHE_LOCKS = weakref.WeakKeyDictionary()
_CACHE_LOCKS_LOCK = threading.Lock()


def cache_lock(model):
    """The re-entrant lock a model's :attr:`Model.cache` entries are computed under.

    What is kept in the cache is computed once per model: a thread that finds
    an entry missing computes it holding this lock, and another thread asking
    meanwhile waits for it rather than computing it again.

    Parameters
    ----------
    model : Model

    Returns
    -------
    threading.RLock
    """
    with _CACHE_LOCKS_LOCK:
        lock = _CACHE_LOCKS.get(model)
        if lock is None:
            lock = _CACHE_LOCKS[model] = threading.RLock()
        return lock


def cached(model, key, compute):
    """``model.cache[key]``, computed by ``compute()`` the first time, once: under :func:`cache_lock`, a thread
    asking meanwhile waits for it rather than computing it again.

    Parameters
    ----------
    model : Model
    key : hashable
    compute : callable
        ``compute() -> value``.
    """
    value = model.cache.get(key)
    if value is None:
        with cache_lock(model):
            value = model.cache.get(key)
            if value is None:
                value = model.cache[key] = compute()
    return value


@dataclass(frozen=True, eq=False)
class Model:
    """The inputs of a classification.

    Parameters
    ----------
    name : str
    manifold : ImplicitManifold
        The C-space, with constraint Jacobian and Hessian in recentred charts.
    actuators : ndarray, shape=[a, k]
        ``E^{1/2} Dπ``: rows select the actuated coordinates (real or circle
        factors), scaled by the square roots of their weights.
    coordinate_names : tuple of str
        Names of the k tangent coordinates.
    starts : ndarray, shape=[s, point_size]
        Known points of M (e.g. the home) from which the survey walks.
    end_effector_jacobian : callable, optional
        ``Df(point) -> array, shape=[n, k]`` in a chart of N.
    end_effector_metric : ndarray, shape=[n, n], optional
        H in that chart.
    end_effector_reference : callable, optional
        ``point -> array, shape=[n, r]``, in the same chart: rows whose
        ``σ₁(H^½ ·)`` is the end-effector rank decision's reference scale,
        ``diag(s)`` included (default ``Df·diag(s)``). A mechanism's rows give every
        joint coordinate the rate its screw gives the end-effector
        (:func:`mechanisms.kinematics.end_effector_reference`), so the scale
        does not depend on which joints the spanning tree puts on Df's path.
    describe : callable, optional
        ``describe(point) -> dict`` for the report (joint displacements).
    mechanism : Mechanism, optional
        The joint graph the model was made from (:func:`model_of`), if any.

    Attributes
    ----------
    cache : dict
        What is computed once per model and reused (its survey,
        :func:`classify.survey.survey_of`); not copied by ``dataclasses.replace``. Its entries are computed
        under :func:`cache_lock`, once however many threads ask.
    """

    name: str
    manifold: ImplicitManifold
    actuators: np.ndarray
    coordinate_names: tuple
    starts: np.ndarray
    end_effector_jacobian: Optional[Callable] = None
    end_effector_metric: Optional[np.ndarray] = None
    end_effector_reference: Optional[Callable] = None
    describe: Optional[Callable] = None
    mechanism: Optional[object] = None
    cache: dict = field(default_factory=dict, init=False, repr=False)

    @property
    def end_effector_dimension(self):
        return 0 if self.end_effector_metric is None else int(self.end_effector_metric.shape[0])

    @property
    def constraint_rows(self):
        """c, the rows of Φ (and of DΦ), from Φ at the first start (kept in :attr:`cache`)."""
        return cached(self, "constraint_rows", lambda: int(np.shape(self.manifold.constraint(
            np.asarray(self.starts[0], dtype=float)))[-1]))


def model_of(mechanism, length_scale=None):
    """The :class:`Model` of a joint-graph mechanism, one per mechanism object and length scale.

    The model is kept on the mechanism, so what is computed once per model
    (its survey of M, :func:`classify.survey.survey_of`) is reused by every
    later call with the same mechanism.

    Parameters
    ----------
    mechanism : Mechanism
    length_scale : float, optional
        L of the SE(2)/SE(3) and tool (ℝ³ × S²) end-effector metrics (default the characteristic length).
    """
    models = mechanism.__dict__.setdefault("_models", _Models())
    key = None if length_scale is None else float(length_scale)
    if key not in models:
        models[key] = _new_model(mechanism, length_scale)
    return models[key]


class _Models(dict):
    """The models kept on a mechanism (length scale → Model). Not pickled nor deep-copied: a mechanism
    sent to another process (a Dask worker, a process pool) arrives without them and makes its own."""

    def __reduce__(self):
        return type(self), ()


def _new_model(mechanism, length_scale):
    has_end_effector = end_effector_dimension(mechanism) > 0
    return Model(
        name=mechanism.name,
        manifold=configuration_space(mechanism),
        actuators=weighted_actuator_jacobian(mechanism),
        coordinate_names=mechanism.coordinate_names,
        starts=home(mechanism)[None],
        end_effector_jacobian=(lambda point: end_effector_jacobian(mechanism, point)) if has_end_effector else None,
        end_effector_metric=end_effector_metric(mechanism, length_scale) if has_end_effector else None,
        end_effector_reference=(lambda point: end_effector_reference(mechanism, point)) if has_end_effector else None,
        describe=lambda point: to_displacements(mechanism, point),
        mechanism=mechanism,
    )


def joint_output_model(mechanism, joint_names, where="outputs"):
    """The :class:`Model` of a mechanism whose outputs are joint coordinates (metric H = identity).

    Gosselin & Angeles allow outputs that are "joint angles or displacements"
    (Gosselin & Angeles 1990, Section II): the slider's displacement of the
    RRRP (eq. 9), the output angle φ of the Watt linkage (eq. 31).

    Parameters
    ----------
    mechanism : Mechanism
    joint_names : sequence of str
        The output joints; their coordinates, in order, are the outputs.
    where : str
        Field name for error messages.

    Returns
    -------
    Model
    """
    joint_names = checked_joint_names(mechanism, joint_names, where)
    outputs = [name for joint in joint_names for name in joint_coordinate_names(mechanism.joint(joint))]
    selection = np.eye(mechanism.ambient_dimension)[[mechanism.coordinate_names.index(name) for name in outputs]]
    base = model_of(mechanism)
    return replace(base, end_effector_jacobian=lambda point: selection,
                   end_effector_metric=np.eye(selection.shape[0]), end_effector_reference=None)
