"""Classification of whole stacks of configurations: :func:`classify_many` and its columnar result.

The first-order part of the Park–Kim classification (Park & Kim 1999,
Section 3; docs/design.rst, "The three kinds") is array work: for a stack of
configurations p of shape ``(..., point_size)``, Φ, DΦ·diag(s) and Df are
evaluated at once (:mod:`mechanisms.kinematics` takes stacks), and every rank
is a batched singular-value decomposition:

* rank DΦ(p)·diag(s), whose right singular vectors beyond the rank give the
  tangent basis T (orthonormal for the dimensionless metric);
* rank of the unit actuator rows on T, cut at ``rtol·σ₁`` of the unrestricted
  rows (a constant of the model);
* rank of H^½ Df T, cut at ``rtol·σ₁(H^½ Df·diag(s))`` per configuration;
* the manipulability proper values λ, the roots of det(λG − JᵀHJ) = 0
  (:func:`classify.metrics.proper_values`).

Each is the decision :func:`classify.classify` takes one configuration at a
time, with the same cuts. What is not array work runs only where it is
needed, through :func:`classify.classify` itself: at a configuration where DΦ
has less than the survey's largest rank (a C-space singularity needs
neighbours on M) and at an actuator singularity (the second-order test and
the fibre certificate). So the batch equals repeated single calls, item by
item, by construction there and by the same arithmetic elsewhere.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from manifold import DEFAULT_ATOL, DEFAULT_RTOL
from mechanisms import CLOSURE_TOLERANCE, ConfigurationError, Mechanism, closure_and_jacobian

from .classification import classify
from .metrics import metric_root, proper_values, singular_values
from .model import model_of
from .progress import progress_bar
from .report import KINDS
from .survey import survey_of, unit_actuator_rows

__all__ = ["Classifications", "classify_many", "DEFAULT_CHUNK"]

#: the second-order verdict as the int8 column :attr:`Classifications.degenerate`
_DEGENERACY = {"degenerate": 1, "nondegenerate": 0, "undetermined": -1}

#: configurations per chunk of array work: bounds the memory of the batched decompositions
DEFAULT_CHUNK = 4096


@dataclass(frozen=True, eq=False)
class Classifications:
    """The classification of a stack of configurations, column by column.

    Every array has one entry (row) per configuration, in C order of the
    batch dimensions of the points given to :func:`classify_many`.

    Attributes
    ----------
    mechanism : str
    shape : tuple of int
        The batch shape of the points.
    points : ndarray, shape=[n, point_size]
    singular : ndarray of bool, shape=[n, 3]
        Whether each kind holds, columns in :data:`classify.KINDS` order.
    dof : ndarray of int, shape=[n]
        Local dimension m of M.
    ranks, expected_ranks : dict of str to ndarray of int, shape=[n]
        Per kind; -1 for the end-effector of a model without one.
    margins : dict of str to ndarray, shape=[n, 2]
        Per kind, the smallest singular value kept and the largest dropped
        (NaN where there is none).
    tolerances : dict of str to ndarray, shape=[n]
        Per kind, the cut of the rank decision.
    eigenvalues : ndarray, shape=[n, min(dim N, k)]
        Manipulability proper values λ₁ ≥ … ≥ λ_min(dim N, m), then NaN (all NaN
        where G is not definite on T_pM, at C-space singularities and without
        end-effector).
    condition_number : ndarray, shape=[n]
        λ₁/λₙ (NaN where undefined, e.g. at an end-effector singularity).
    degenerate : ndarray of int8, shape=[n]
        1 degenerate, 0 nondegenerate actuator singularity, -1 not tested or undetermined.
    idle_freedoms, moving_idle_freedoms : ndarray of int, shape=[n]
    survey : Survey
        The survey the expected ranks come from.
    model : Model
        What was classified (for :meth:`report`).
    rtol : float
    """

    mechanism: str
    shape: tuple
    points: np.ndarray
    singular: np.ndarray
    dof: np.ndarray
    ranks: dict
    expected_ranks: dict
    margins: dict
    tolerances: dict
    eigenvalues: np.ndarray
    condition_number: np.ndarray
    degenerate: np.ndarray
    idle_freedoms: np.ndarray
    moving_idle_freedoms: np.ndarray
    survey: object
    model: object = field(repr=False)
    rtol: float = DEFAULT_RTOL
    _reports: dict = field(default_factory=dict, repr=False)

    def __len__(self):
        return len(self.points)

    def kind(self, name):
        """Whether kind `name` holds, shape=[n]."""
        return self.singular[:, KINDS.index(name)]

    def kinds(self, index):
        """The kinds that hold at configuration `index`, sorted (as :attr:`Report.kinds`)."""
        return tuple(kind for kind, holds in zip(KINDS, self.singular[index]) if holds)

    @property
    def architecture_singular(self):
        """Whether a locked-actuator freedom moves the end-effector everywhere on M (any item)."""
        return bool(np.any(self.moving_idle_freedoms > 0))

    def report(self, index):
        """The full :class:`~classify.Report` of configuration `index`.

        Equal to ``classify(model, points[index], survey=survey, rtol=rtol)``;
        computed on demand (those computed during :func:`classify_many` are kept).
        """
        index = int(index)
        if index not in self._reports:
            self._reports[index] = classify(self.model, self.points[index], survey=self.survey, rtol=self.rtol)
        return self._reports[index]

    def reports(self):
        """Every configuration's :class:`~classify.Report`, in order (one full classification each)."""
        return [self.report(index) for index in range(len(self))]

    def rows(self):
        """One JSON-ready dict per configuration: kinds, ranks, margins, λ's, the degeneracy verdict, and
        ``architecture_singular``, ``idle_freedoms``, ``moving_idle_freedoms`` as in
        :meth:`classify.report.Report.to_dict` (``architecture_singular`` is ``moving_idle_freedoms > 0``)."""
        shown = [kind for kind in KINDS if kind != "end_effector" or self.model.end_effector_dimension > 0]
        ranks = {kind: self.ranks[kind].tolist() for kind in shown}
        expected = {kind: self.expected_ranks[kind].tolist() for kind in shown}
        margins = {kind: np.where(np.isnan(self.margins[kind]), None, self.margins[kind]).tolist() for kind in shown}
        eigenvalues = [[value for value in row if value == value] or None for row in self.eigenvalues.tolist()]
        conditions = np.where(np.isnan(self.condition_number), None, self.condition_number).tolist()
        degeneracy = [None if value < 0 else bool(value) for value in self.degenerate.tolist()]
        architecture = (self.moving_idle_freedoms > 0).tolist()
        idle, moving = self.idle_freedoms.tolist(), self.moving_idle_freedoms.tolist()
        singular = self.singular.tolist()
        dof = self.dof.tolist()
        return [{
            "kinds": [kind for kind, holds in zip(KINDS, singular[index]) if holds],
            "singular": any(singular[index]),
            "dof": dof[index],
            "ranks": {kind: ranks[kind][index] for kind in shown},
            "expected_ranks": {kind: expected[kind][index] for kind in shown},
            "margins": {kind: {"smallest_kept": margins[kind][index][0], "largest_dropped": margins[kind][index][1]}
                        for kind in shown},
            "eigenvalues": eigenvalues[index],
            "condition_number": conditions[index],
            "degenerate": degeneracy[index],
            "architecture_singular": architecture[index],
            "idle_freedoms": idle[index],
            "moving_idle_freedoms": moving[index],
        } for index in range(len(self))]

    def to_dict(self):
        """The whole result for JSON: mechanism, batch shape, survey and :meth:`rows`."""
        return {"mechanism": self.mechanism, "shape": list(self.shape), "survey": self.survey.to_dict(),
                "rows": self.rows()}

    def json_lines(self):
        """:meth:`rows` as JSON lines (one object per configuration, each ending with a newline)."""
        return "".join(json.dumps(row, allow_nan=False) + "\n" for row in self.rows())

    def arrays(self):
        """Every column as a numpy array (for :func:`numpy.savez`): ``singular``, ``dof``,
        ``rank_<kind>``, ``expected_rank_<kind>``, ``margin_<kind>``, ``tolerance_<kind>``,
        ``eigenvalues``, ``condition_number``, ``degenerate``, ``idle_freedoms``, ``moving_idle_freedoms``."""
        result = {"singular": self.singular, "kinds": np.array(KINDS), "dof": self.dof,
                  "eigenvalues": self.eigenvalues, "condition_number": self.condition_number,
                  "degenerate": self.degenerate, "idle_freedoms": self.idle_freedoms,
                  "moving_idle_freedoms": self.moving_idle_freedoms}
        for kind in KINDS:
            result[f"rank_{kind}"] = self.ranks[kind]
            result[f"expected_rank_{kind}"] = self.expected_ranks[kind]
            result[f"margin_{kind}"] = self.margins[kind]
            result[f"tolerance_{kind}"] = self.tolerances[kind]
        return result


def classify_many(mechanism, points, survey=None, rtol=DEFAULT_RTOL, length_scale=None, chunk=DEFAULT_CHUNK,
                  progress=False):
    """Classify a stack of configurations at once.

    Parameters
    ----------
    mechanism : Mechanism or Model
    points : array_like, shape=[..., point_size]
        Configurations on M.
    survey : Survey, optional
        Default the model's own (:func:`classify.survey.survey_of`, computed once per model).
    rtol : float
        Relative cut of every rank decision.
    length_scale : float, optional
        L of the SE(2)/SE(3) and tool (ℝ³ × S²) end-effector metrics (a Mechanism only).
    chunk : int
        Configurations per chunk of array work (memory grows with it linearly).
    progress : bool
        Show progress bars (:func:`classify.progress.progress_bar`, on stderr, after a second) over the
        chunks and the full classifications.

    Returns
    -------
    Classifications
        Item i equals ``classify(model, points[i], survey=survey, rtol=rtol)``: the same kinds and ranks, the
        same λ's to rounding.

    Raises
    ------
    ConfigurationError
        Naming the index of the first configuration that does not close the loops.
    """
    if not isinstance(mechanism, Mechanism) and length_scale is not None:
        raise ValueError("length_scale applies to a Mechanism; a Model carries its own end-effector metric")
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    points = np.asarray(points, dtype=float)
    size = model.manifold.ambient.point_size
    if points.ndim == 0 or points.shape[-1] != size:
        raise ValueError(f"Expected points of shape (..., {size}), got {points.shape}")
    if int(chunk) < 1:
        raise ValueError(f"Expected a positive chunk size, got {chunk!r}")
    shape = points.shape[:-1]
    flat = points.reshape(-1, size)
    survey = survey_of(model, rtol) if survey is None else survey
    starts = range(0, len(flat), int(chunk))
    bar = progress_bar(len(flat), "classifying", shown=progress)
    parts = []
    for start in starts:
        parts.append(_first_order(model, flat[start:start + int(chunk)], survey, rtol, offset=start))
        bar.update(len(parts[-1]["dof"]))
    columns = _concatenated(parts, model, len(flat))
    bar.close()
    result = Classifications(
        mechanism=model.name, shape=shape, points=flat, singular=columns["singular"], dof=columns["dof"],
        ranks=columns["ranks"], expected_ranks=columns["expected_ranks"], margins=columns["margins"],
        tolerances=columns["tolerances"], eigenvalues=columns["eigenvalues"],
        condition_number=columns["condition_number"], degenerate=columns["degenerate"],
        idle_freedoms=columns["idle_freedoms"], moving_idle_freedoms=columns["moving_idle_freedoms"],
        survey=survey, model=model, rtol=rtol)
    full = np.flatnonzero(columns["full"])
    bar = progress_bar(len(full), "second-order tests", shown=progress)
    for index in full:
        _fill(result, index, result.report(index))
        bar.update(1)
    bar.close()
    return result


def _decisions(values, tolerance):
    """Ranks (count of σ > tolerance) and margins [b, 2] of stacks of singular values, shape=[b, s]."""
    tolerance = np.broadcast_to(tolerance, values.shape[:1])
    ranks = np.count_nonzero(values > tolerance[:, None], axis=1)
    padded = np.concatenate([np.full((len(values), 1), np.nan), values, np.full((len(values), 1), np.nan)],
                            axis=1)
    rows = np.arange(len(values))
    margins = np.stack([padded[rows, ranks], padded[rows, ranks + 1]], axis=1)
    return ranks, margins


def _closure_and_jacobian(model, points, offset):
    """DΦ·diag(s) of a chunk, shape=[b, c, k], after checking that every configuration closes its loops
    (as :func:`classify.classify`: |Φ| ≤ the closure tolerance and a point of M, not a spurious zero).

    For a joint-graph mechanism Φ, the half-turn test and DΦ come from one expansion of each loop
    (:func:`mechanisms.closure_and_jacobian`).

    Raises
    ------
    ConfigurationError
        Naming the index (in the whole stack) of the first configuration that does not close.
    """
    manifold = model.manifold
    if model.mechanism is not None:
        rows, turns, jacobian = closure_and_jacobian(model.mechanism, points)
        residuals = np.linalg.norm(rows, axis=-1)
        bad = np.flatnonzero(~(residuals <= CLOSURE_TOLERANCE) | ~turns)
    else:
        residuals = np.linalg.norm(manifold.constraint(points), axis=-1)
        bad = np.flatnonzero(~(residuals <= CLOSURE_TOLERANCE))
        if not len(bad) and manifold.is_solution is not None and not manifold.is_solution(points):
            bad = [index for index, point in enumerate(points) if not manifold.is_solution(point)]
        jacobian = manifold.constraint_jacobian(points)
    if len(bad):
        index = int(bad[0])
        raise ConfigurationError(f"configuration {offset + index}: not on the C-space "
                                 f"(|Φ| = {residuals[index]:.3g}); project it first")
    return np.asarray(jacobian, dtype=float) * manifold.ambient.tangent_scales


def _first_order(model, points, survey, rtol, offset):
    """Columns of the first-order classification of a chunk of configurations (see the module notes)."""
    jacobian = _closure_and_jacobian(model, points, offset)
    count = len(points)
    scales = model.manifold.ambient.tangent_scales
    constraint_values = singular_values(jacobian)
    constraint_tolerance = np.maximum(rtol * (constraint_values[:, 0] if constraint_values.shape[1] else 0.0),
                                      DEFAULT_ATOL)
    constraint_ranks, constraint_margins = _decisions(constraint_values, constraint_tolerance)
    # below the survey's largest rank of DΦ: a possible C-space singularity, classified one at a time
    full = constraint_ranks < survey.constraint_rank
    columns = _empty_columns(model, count)
    columns["ranks"]["cspace"][:] = constraint_ranks
    columns["margins"]["cspace"][:] = constraint_margins
    columns["tolerances"]["cspace"][:] = constraint_tolerance
    regular = np.flatnonzero(~full)
    for rank in np.unique(constraint_ranks[regular]):
        group = regular[constraint_ranks[regular] == rank]
        basis = scales[:, None] * _kernel_bases(jacobian[group], int(rank))  # [g, k, m]
        _regular_columns(model, points[group], basis, int(rank), survey, rtol, columns, group)
    columns["full"] = full | columns["singular"][:, KINDS.index("actuator")]
    return columns


def _kernel_bases(matrices, rank):
    """Orthonormal bases of the kernels of a stack of matrices of one numerical rank, shape=[b, columns,
    columns − rank].

    Of full row rank (``rank`` = rows, the usual case of loop rows), the last
    columns of the complete QR factors of the transposes (Householder QR:
    backward stable, and cheaper than the SVD); otherwise the right singular
    vectors beyond the rank, as :func:`manifold.tangent_basis`. Either spans
    the same subspace; a basis is only ever used through quantities that do
    not depend on which orthonormal basis it is (singular values, λ's).
    """
    count, rows, columns = matrices.shape
    if rows == 0:
        return np.broadcast_to(np.eye(columns), (count, columns, columns))
    if rank == rows and rows <= columns:
        orthogonal = np.linalg.qr(np.swapaxes(matrices, -1, -2), mode="complete")[0]
        return orthogonal[:, :, rank:]
    return np.swapaxes(np.linalg.svd(matrices, full_matrices=True)[2][:, rank:, :], -1, -2)


def _empty_columns(model, count):
    """Columns for `count` configurations, filled with 'undefined' (-1, NaN, False)."""
    proper_count = min(model.end_effector_dimension, model.manifold.ambient.dim)  # at most min(dim N, m), m ≤ k
    return {
        "singular": np.zeros((count, len(KINDS)), dtype=bool),
        "dof": np.full(count, -1, dtype=int),
        "ranks": {kind: np.full(count, -1, dtype=int) for kind in KINDS},
        "expected_ranks": {kind: np.full(count, -1, dtype=int) for kind in KINDS},
        "margins": {kind: np.full((count, 2), np.nan) for kind in KINDS},
        "tolerances": {kind: np.full(count, np.nan) for kind in KINDS},
        "eigenvalues": np.full((count, proper_count), np.nan),
        "condition_number": np.full(count, np.nan),
        "degenerate": np.full(count, -1, dtype=np.int8),
        "idle_freedoms": np.zeros(count, dtype=int),
        "moving_idle_freedoms": np.zeros(count, dtype=int),
    }


def _regular_columns(model, points, basis, constraint_rank, survey, rtol, columns, rows):
    """Fill `columns` at `rows`: configurations where DΦ has rank `constraint_rank` ≥ the survey's."""
    k = model.manifold.ambient.dim
    scales = model.manifold.ambient.tangent_scales
    dof = k - constraint_rank
    count = len(points)
    unit_actuators, actuator_scale = unit_actuator_rows(model)
    actuator_tolerance = max(rtol * actuator_scale, DEFAULT_ATOL)
    actuator_block = unit_actuators @ basis  # [g, a, m]
    actuator_ranks, actuator_margins = _decisions(singular_values(actuator_block), actuator_tolerance)
    n = model.end_effector_dimension
    if n:
        end_effector_jacobian = np.broadcast_to(model.end_effector_jacobian(points), (count, n, k))
        end_effector_rows = metric_root(model.end_effector_metric) @ end_effector_jacobian
        end_effector_scale = _largest(end_effector_rows * scales)
        end_effector_tolerance = np.maximum(rtol * end_effector_scale, DEFAULT_ATOL)
        end_effector_block = end_effector_rows @ basis
        end_effector_ranks, end_effector_margins = _decisions(singular_values(end_effector_block),
                                                              end_effector_tolerance)
    raised = constraint_rank > survey.constraint_rank
    if n and (raised or survey.joint_rank < dof):  # else the stacked rank cannot raise the survey's
        stacked = np.concatenate([
            actuator_block / max(actuator_scale, 1e-300),
            end_effector_block / np.maximum(end_effector_scale, 1e-300)[:, None, None]], axis=1)
        joint_ranks = _decisions(singular_values(stacked), max(rtol, DEFAULT_ATOL))[0]  # reference scale 1
    elif n:
        joint_ranks = np.zeros(count, dtype=int)
    # the survey raised to each configuration's own ranks (Survey.including), as classify does
    if raised:
        actuator_largest = actuator_ranks
        end_effector_largest = end_effector_ranks if n else None
        joint_largest = joint_ranks if n else None
    else:
        actuator_largest = np.maximum(survey.actuator_rank, actuator_ranks)
        end_effector_largest = np.maximum(survey.end_effector_rank, end_effector_ranks) if n else None
        joint_largest = np.maximum(survey.joint_rank, joint_ranks) if n else None
    freedom_largest = actuator_largest if not n else joint_largest
    idle = np.maximum(0, dof - freedom_largest)
    expected_actuator = dof - idle
    moving = np.minimum(dof, np.maximum(0, joint_largest - actuator_largest)) if n else np.zeros(count, dtype=int)

    columns["dof"][rows] = dof
    columns["expected_ranks"]["cspace"][rows] = constraint_rank
    columns["idle_freedoms"][rows] = idle
    columns["moving_idle_freedoms"][rows] = moving
    columns["ranks"]["actuator"][rows] = actuator_ranks
    columns["expected_ranks"]["actuator"][rows] = expected_actuator
    columns["margins"]["actuator"][rows] = actuator_margins
    columns["tolerances"]["actuator"][rows] = actuator_tolerance
    columns["singular"][rows, KINDS.index("actuator")] = actuator_ranks < expected_actuator
    if not n:
        return
    expected_end_effector = np.minimum(min(n, dof), end_effector_largest)
    columns["ranks"]["end_effector"][rows] = end_effector_ranks
    columns["expected_ranks"]["end_effector"][rows] = expected_end_effector
    columns["margins"]["end_effector"][rows] = end_effector_margins
    columns["tolerances"]["end_effector"][rows] = end_effector_tolerance
    columns["singular"][rows, KINDS.index("end_effector")] = end_effector_ranks < expected_end_effector
    definite = np.flatnonzero(actuator_ranks == dof) if dof > 0 else np.zeros(0, dtype=int)
    if len(definite):
        values = proper_values(model.actuators @ basis[definite], end_effector_jacobian[definite] @ basis[definite],
                               model.end_effector_metric, min(n, dof))
        vanishing = end_effector_ranks[definite] < min(n, dof)
        smallest = values[:, -1]
        condition = np.where(vanishing | (smallest <= 0.0), np.nan,
                             values[:, 0] / np.where(smallest > 0.0, smallest, 1.0))
        columns["eigenvalues"][rows[definite], :values.shape[1]] = values
        columns["condition_number"][rows[definite]] = condition


def _largest(matrices):
    """σ₁ of each matrix of a stack, shape=[b] (0 for empty matrices): the square root of the largest
    eigenvalue of the smaller Gram matrix (relative accuracy of the order of the rounding unit), in closed
    form for one or two rows or columns."""
    if matrices.shape[-1] == 0 or matrices.shape[-2] == 0:
        return np.zeros(len(matrices))
    transposed = np.swapaxes(matrices, -1, -2)
    gram = matrices @ transposed if matrices.shape[-2] <= matrices.shape[-1] else transposed @ matrices
    if gram.shape[-1] == 1:
        return np.sqrt(gram[:, 0, 0])
    if gram.shape[-1] == 2:
        first, second, off = gram[:, 0, 0], gram[:, 1, 1], gram[:, 0, 1]
        return np.sqrt(0.5 * (first + second) + np.hypot(0.5 * (first - second), off))
    return np.sqrt(np.clip(np.linalg.eigvalsh(gram)[:, -1], 0.0, None))


def _concatenated(parts, model, count):
    """One set of columns from the chunks' columns."""
    if not parts:
        columns = _empty_columns(model, 0)
        columns["full"] = np.zeros(0, dtype=bool)
        return columns
    result = {}
    for name, first in parts[0].items():
        if isinstance(first, dict):
            result[name] = {kind: np.concatenate([part[name][kind] for part in parts]) for kind in first}
        else:
            result[name] = np.concatenate([part[name] for part in parts])
    return result


def _fill(result, index, report):
    """Overwrite row `index` of the columns with a full report's values."""
    results = {"actuator": report.actuator, "cspace": report.cspace, "end_effector": report.end_effector}
    for column, kind in enumerate(KINDS):
        kind_result = results[kind]
        if kind_result is None:
            continue
        result.singular[index, column] = kind_result.singular
        result.ranks[kind][index] = kind_result.rank
        result.expected_ranks[kind][index] = kind_result.expected_rank
        kept, dropped = kind_result.decision.margin
        result.margins[kind][index] = [np.nan if kept is None else kept, np.nan if dropped is None else dropped]
        result.tolerances[kind][index] = kind_result.decision.tolerance
    result.dof[index] = report.dof
    result.idle_freedoms[index] = report.idle_freedoms
    result.moving_idle_freedoms[index] = report.moving_idle_freedoms
    result.eigenvalues[index] = np.nan
    result.condition_number[index] = np.nan
    if report.manipulability is not None:
        values = report.manipulability.eigenvalues
        result.eigenvalues[index, :len(values)] = values
        condition = report.manipulability.condition_number
        result.condition_number[index] = np.nan if condition is None else condition
    second = report.second_order
    result.degenerate[index] = -1 if second is None else _DEGENERACY[second.degeneracy]
