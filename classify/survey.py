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

from manifold import (
    DEFAULT_RTOL, handled_by_blocks, jacobian_ranks, numerical_rank, rank_of_values, sample_manifold, tangent_basis,
    tangent_extent,
)
from manifold.blocks import labelled_block_singular_values

from .metrics import coordinate_rows, coordinate_singular_values, largest_singular_value, metric_root, unit_rows
from .model import cached

__all__ = ["Survey", "survey", "survey_of", "decision_rows", "decision_blocks", "actuator_decision", "freedom_rows",
           "stacked", "unit_actuator_rows", "model_coordinate_rows", "rows_on", "SURVEY_SEED"]

#: seed of the survey a model keeps (:func:`survey_of`): the same survey in every call and process
SURVEY_SEED = 0


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
    margins : dict or None
        The margins of those decisions over the samples, per kind (``"constraint"``, ``"actuator"``,
        ``"end_effector"``, ``"joint"``): ``{"kept": largest σ_r / cut, "dropped": largest σ_{r+1} / cut}``
        with r the kind's rank, each singular value over the cut at its own sample (None where there is no
        such value): how clearly the rank was reached somewhere, and how near a sample came to a larger one.
        DΦ's are over every sample; the others over the samples visited until every rank reached its upper
        bound (the survey stops there: no sample can then raise a rank, and ``dropped`` is None).
        A design whose ``moving_idle_freedoms`` (an architecture singularity) rest on an actuator ``dropped``
        near 1 is near the cut. None for a survey raised by a configuration (:meth:`including`) or read
        without them.
    """

    samples: int
    constraint_rank: int
    actuator_rank: int
    end_effector_rank: object
    joint_rank: object = None
    margins: object = None

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

    def including(self, constraint_rank, actuator_rank=None, end_effector_rank=None, joint_rank=None):
        """This survey with the ranks of one more point of M: each largest rank raised to the point's.

        A point of M where DΦ has a larger rank than the survey found proves
        the survey missed part of M; the other ranks of a point count only
        where DΦ has its largest rank (at a C-space singularity ker DΦ is
        larger than the tangent spaces of M), and only when given.

        Parameters
        ----------
        constraint_rank : int
            Rank of DΦ·diag(s) at the point.
        actuator_rank, end_effector_rank, joint_rank : int, optional
            Ranks of the unit actuator rows, H^½Df and the stacked map on ker DΦ at the point.

        Returns
        -------
        Survey
            `self` when nothing is raised.
        """
        if constraint_rank > self.constraint_rank:
            raised = Survey(self.samples, constraint_rank, 0, None if self.end_effector_rank is None else 0,
                            None if self.joint_rank is None else 0)
            return raised.including(constraint_rank, actuator_rank, end_effector_rank, joint_rank)
        if constraint_rank < self.constraint_rank or actuator_rank is None:
            return self
        ranks = (max(self.actuator_rank, actuator_rank),
                 _larger(self.end_effector_rank, end_effector_rank), _larger(self.joint_rank, joint_rank))
        if ranks == (self.actuator_rank, self.end_effector_rank, self.joint_rank):
            return self
        return Survey(self.samples, self.constraint_rank, *ranks)

    def to_dict(self):
        result = {"samples": self.samples, "constraint_rank": self.constraint_rank,
                  "actuator_rank": self.actuator_rank, "end_effector_rank": self.end_effector_rank,
                  "joint_rank": self.joint_rank}
        if self.margins is not None:
            result["margins"] = {kind: dict(values) for kind, values in self.margins.items()}
        return result

    @classmethod
    def from_dict(cls, data, where="survey"):
        """The survey of :meth:`to_dict` (e.g. the ``survey`` block of a JSON report).

        Raises
        ------
        ValueError
            Naming the field, if a field is missing or not a non-negative integer (``null`` allowed for
            ``end_effector_rank`` and ``joint_rank``).
        """
        if not isinstance(data, dict):
            raise ValueError(f"{where}: expected an object with the fields of a survey, got {type(data).__name__}")
        values = {}
        for name in ("samples", "constraint_rank", "actuator_rank", "end_effector_rank", "joint_rank"):
            value = data.get(name)
            optional = name in ("end_effector_rank", "joint_rank")
            if value is None and optional:
                values[name] = None
                continue
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise ValueError(f"{where}: field {name!r}: expected a non-negative integer, got {value!r}")
            values[name] = value
        values["margins"] = _margins_from_dict(data.get("margins"), where)
        return cls(**values)


#: the kinds of a survey's margins
MARGIN_KINDS = ("constraint", "actuator", "end_effector", "joint")


def _margins_from_dict(data, where):
    """The margins of :meth:`Survey.to_dict` (None when absent), checked field by field."""
    if data is None:
        return None
    if not isinstance(data, dict) or set(data) - set(MARGIN_KINDS):
        raise ValueError(f"{where}: field 'margins': expected an object with the kinds {', '.join(MARGIN_KINDS)}")
    margins = {}
    for kind, values in data.items():
        if not isinstance(values, dict) or set(values) != {"kept", "dropped"}:
            raise ValueError(f"{where}: field 'margins.{kind}': expected an object with 'kept' and 'dropped'")
        for name, value in values.items():
            if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float))
                                      or not value >= 0 or value == float("inf")):
                raise ValueError(f"{where}: field 'margins.{kind}.{name}': expected a finite number ≥ 0 or null, "
                                 f"got {value!r}")
        margins[kind] = {name: None if value is None else float(value) for name, value in values.items()}
    return margins


def _margins(decisions, ranks):
    """Per kind, the largest σ_r / cut and σ_{r+1} / cut over its decisions at the samples (kind → list of
    RankDecision), r the kind's rank in `ranks` (:attr:`Survey.margins`)."""
    margins = {}
    for kind, found in decisions.items():
        rank = ranks[kind]
        kept = [float(decision.singular_values[rank - 1]) / decision.tolerance for decision in found
                if 0 < rank <= len(decision.singular_values)]
        dropped = [float(decision.singular_values[rank]) / decision.tolerance for decision in found
                   if rank < len(decision.singular_values)]
        margins[kind] = {"kept": max(kept) if kept else None, "dropped": max(dropped) if dropped else None}
    return margins


def _larger(first, second):
    """The larger of two ranks, None when the first is None (no end-effector)."""
    return first if first is None or second is None else max(first, second)


def survey_of(model, rtol=DEFAULT_RTOL):
    """The survey of a model, computed once and kept on the model.

    The survey belongs to the mechanism, not to a call: the first call
    samples M from ``model.starts`` with ``numpy.random.default_rng(SURVEY_SEED)``;
    every later call with the same model (and `rtol`) returns the same
    :class:`Survey` without sampling M again. :func:`classify.model_of`
    returns one model per mechanism object, so classifying a second
    configuration of a mechanism does not resample M.

    Parameters
    ----------
    model : Model
    rtol : float

    Returns
    -------
    Survey
    """
    # concurrent callers (threads) wait for the one survey rather than repeat it
    return cached(model, ("survey", float(rtol)), lambda: survey(model, np.random.default_rng(SURVEY_SEED), rtol=rtol))


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
        σ₁ of :func:`end_effector_reference` (``H^½ Df·diag(s)`` for a model without reference rows; for a
        mechanism, the rate every joint coordinate's screw gives the end-effector, which no order of the joints
        changes).
    """
    actuators, actuator_scale = unit_actuator_rows(model)
    if not model.end_effector_dimension:
        return actuators, actuator_scale, None, None
    root = metric_root(model.end_effector_metric)
    jacobian = root @ model.end_effector_jacobian(point)
    reference = end_effector_reference(model, point, jacobian, root)
    return actuators, actuator_scale, jacobian, largest_singular_value(reference)


def end_effector_reference(model, points, rows, root):
    """The rows whose σ₁ is the end-effector decision's reference scale at `points` (one or a stack): ``H^½``
    (`root`) times the model's ``end_effector_reference`` rows, or ``rows·diag(s)`` (`rows` = ``H^½ Df`` there)
    when the model has none."""
    if model.end_effector_reference is None:
        return rows * model.manifold.ambient.tangent_scales
    return root @ model.end_effector_reference(points)


def unit_actuator_rows(model):
    """``unit_rows(E^½ Dπ)`` of a model and σ₁ of those rows·diag(s): constants of the model, computed
    once and kept in ``model.cache``.

    For a manifold handled block by block (:func:`manifold.handled_by_blocks`) whose actuators are
    coordinate rows (:func:`classify.metrics.coordinate_rows`), σ₁ is the largest column norm of the rows·diag(s)
    (:func:`classify.metrics.coordinate_singular_values`), without an SVD of the a × k rows.

    Returns
    -------
    rows : ndarray, shape=[a, k]
    scale : float
    """
    def compute():
        scales = model.manifold.ambient.tangent_scales
        rows = unit_rows(model.actuators, scales)
        coordinates = coordinate_rows(rows) if handled_by_blocks(model.manifold) else None
        if coordinates is None:
            return rows, largest_singular_value(rows * scales)
        columns, factors = coordinates
        values = coordinate_singular_values(columns, factors * scales[columns])
        return rows, float(values[0]) if len(values) else 0.0

    return cached(model, "unit_actuator_rows", compute)


def model_coordinate_rows(model, name, matrix):
    """:func:`classify.metrics.coordinate_rows` of `matrix`, a constant of the model named `name` (e.g.
    ``"actuators"``, ``"unit_actuator_rows"``), kept in ``model.cache``: ``(columns [a], factors [a])`` or None."""
    return cached(model, ("coordinate_rows", name), lambda: coordinate_rows(matrix) or ()) or None


def rows_on(model, name, matrix, basis):
    """``matrix @ basis`` (shape=[a, k] and [..., k, m]) for `matrix` a constant of the model named `name`,
    shape=[..., a, m]: where its rows are coordinate rows (:func:`model_coordinate_rows`), the basis's rows at
    their columns times their factors, the same numbers (one nonzero term per entry) without the a·k·m
    products."""
    coordinates = model_coordinate_rows(model, name, matrix)
    if coordinates is None:
        return matrix @ basis
    columns, factors = coordinates
    return factors[:, None] * basis[..., columns, :]


def decision_blocks(model, point, basis):
    """:func:`decision_rows` restricted to a tangent basis (from :func:`manifold.tangent_basis`): the
    blocks ``[a, m]`` and ``[n, m]`` (None without end-effector) with the same scales."""
    actuator, actuator_scale, end_effector, end_effector_scale = decision_rows(model, point)
    return (rows_on(model, "unit_actuator_rows", actuator, basis), actuator_scale,
            None if end_effector is None else end_effector @ basis, end_effector_scale)


def actuator_decision(model, block, basis, scale, rtol=DEFAULT_RTOL):
    """The rank decision of the actuator block ``unit_rows(E^½ Dπ)·T`` (:func:`decision_blocks`), as
    ``numerical_rank(block, rtol, scale=scale)``.

    Where the manifold is handled block by block, the actuators are coordinate rows and every column of the
    basis T lies on one component of DΦ's pattern (a block or a free column, as :func:`manifold.tangent_basis`
    gives it there), the block is block diagonal after permuting rows and columns, and its singular values
    are its blocks' (:func:`manifold.blocks.labelled_block_singular_values`): no SVD of the a × m block.

    Parameters
    ----------
    model : Model
    block : ndarray, shape=[a, m]
    basis : ndarray, shape=[k, m]
    scale : float
        σ₁ of the unit actuator rows·diag(s) (:func:`unit_actuator_rows`).
    rtol : float

    Returns
    -------
    RankDecision
    """
    labels = _actuator_labels(model, basis)
    if labels is None:
        return numerical_rank(block, rtol=rtol, scale=scale)
    values = labelled_block_singular_values(block[None], *labels)[0]
    return rank_of_values(values, rtol=rtol, scale=scale)


def _actuator_labels(model, basis):
    """The components of DΦ's pattern (:attr:`manifold.blocks.JacobianPattern.column_components`) of the actuated
    coordinates [a] and of the basis's columns [m], when the actuator block on `basis` is block diagonal by them
    (:func:`actuator_decision`); else None."""
    manifold = model.manifold
    if not handled_by_blocks(manifold):
        return None
    coordinates = model_coordinate_rows(model, "unit_actuator_rows", unit_actuator_rows(model)[0])
    if coordinates is None:
        return None
    components = manifold.pattern.column_components
    support = basis != 0.0
    column_labels = components[np.argmax(support, axis=0)]
    if np.any(support & (components[:, None] != column_labels)):
        return None
    return components[coordinates[0]], column_labels


def stacked(actuator, actuator_scale, end_effector, end_effector_scale):
    """The actuator rows over their scale, with the end-effector rows over theirs below them (if any):
    the map whose kernel is the idle freedoms, decided with reference scale 1.

    Of one configuration (blocks [a, m] and [n, m], scales numbers) or of a stack of them (blocks [g, a, m] and
    [g, n, m], each scale a number or shape=[g]): shape=[..., a + n, m]."""
    def over(rows, scale):
        return rows / np.maximum(scale, 1e-300)[..., None, None]

    rows = [over(actuator, actuator_scale)]
    if end_effector is not None:
        rows.append(over(end_effector, end_effector_scale))
    return np.concatenate(rows, axis=-2)


def freedom_rows(model, point):
    """The stacked dimensionless rows at `point` whose kernel on T_qM is the idle freedoms, shape=[a + n, k]
    (the actuator rows alone without end-effector)."""
    return stacked(*decision_rows(model, point))


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
    decisions = {"constraint": jacobian_ranks(manifold, points, rtol=rtol)}  # one stack
    ranks = [decision.rank for decision in decisions["constraint"]]
    constraint_rank = max(ranks)
    rows = np.size(manifold.constraint(points[0]))
    dof = manifold.ambient.dim - constraint_rank
    actuator_rank = 0
    end_effector_rank = joint_rank = None if not model.end_effector_dimension else 0
    # upper bounds of each rank on M: once every one is reached, no further sample can raise them
    bounds = (min(len(model.actuators), dof), min(model.end_effector_dimension, dof),
              min(len(model.actuators) + model.end_effector_dimension, dof))
    flexes = None  # whether M extends along fewer directions than ker DΦ, decided at the first sample visited
    for point, rank in zip(points, ranks):
        if rank < constraint_rank:
            continue  # a C-space singularity: ker DΦ is larger than the tangent spaces of M
        basis = tangent_basis(manifold, point, rtol=rtol)[0]
        if flexes is not False and rank < rows and basis.shape[1]:
            # DΦ short of its rows: M may extend along fewer directions than ker DΦ (a part of the mechanism
            # that only flexes, at every point of M); the ranks are those on the directions M extends along.
            # Such a part flexes at every sample or at none but the special ones, so a first sample without
            # flexes spares the others the test (an overconstrained mechanism that moves, as Bennett's)
            extent = tangent_extent(manifold, point, basis)
            flexes = bool(flexes) or extent.extent < basis.shape[1]
            basis = extent.moving
        blocks = decision_blocks(model, point, basis)
        actuator, actuator_scale, end_effector, end_effector_scale = blocks
        here = {"actuator": actuator_decision(model, actuator, basis, actuator_scale, rtol=rtol)}
        if end_effector is not None:
            here["end_effector"] = numerical_rank(end_effector, rtol=rtol, scale=end_effector_scale)
            here["joint"] = numerical_rank(stacked(*blocks), rtol=rtol, scale=1.0)
        for kind, decision in here.items():
            decisions.setdefault(kind, []).append(decision)
        actuator_rank = max(actuator_rank, here["actuator"].rank)
        if end_effector is None:
            if actuator_rank == bounds[0]:
                break
            continue
        end_effector_rank = max(end_effector_rank, here["end_effector"].rank)
        joint_rank = max(joint_rank, here["joint"].rank)
        if (actuator_rank, end_effector_rank, joint_rank) == bounds:
            break
    largest = {"constraint": constraint_rank, "actuator": actuator_rank, "end_effector": end_effector_rank,
               "joint": joint_rank}
    return Survey(len(points), constraint_rank, actuator_rank, end_effector_rank, joint_rank,
                  _margins(decisions, largest))
