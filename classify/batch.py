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
* rank of H^½ Df T, cut at ``rtol·σ₁(H^½ R·diag(s))`` per configuration (R: every joint's
  rate at the end-effector, :func:`classify.survey.end_effector_reference`);
* the manipulability proper values λ, the roots of det(λG − JᵀHJ) = 0
  (:func:`classify.metrics.proper_values`).

Each is the decision :func:`classify.classify` takes one configuration at a
time, with the same cuts. Where the structure allows, the arithmetic is
cheaper than one LAPACK call per matrix: singular values of 2 × 2 matrices
in closed form and of matrices whose smaller side is 3 or 4 (the larger at
most 12, stacks of 64 or more) by one-sided Jacobi sweeps over the whole
stack (:func:`classify.metrics.singular_values`), of larger wide DΦs from the
eigenvalues of their Gram matrix where certified (:func:`_gram_values`); the
kernel bases of loops that each own as many coordinates as they have rows
(Gough–Stewart, 3-RRR) from small solves per loop (:class:`ArrowStructure`),
where those blocks are well conditioned. A large mechanism whose DΦ the
single call takes block by block (:func:`manifold.handled_by_blocks`: a
pattern and k ≥ :data:`manifold.implicit.BLOCK_THRESHOLD`, the note on
sparsity of :mod:`manifold.implicit`) is taken block by block here too: the blocks of one
shape of every configuration of a chunk in one batched SVD, whose values are
DΦ's and whose vectors give the tangent bases as :func:`manifold.tangent_basis`
does (:func:`manifold.blocks.decompose`), with no SVD of the c × k DΦ and no k × k
orthogonal factor, nor the dense DΦ itself (its blocks come from its entries:
:func:`mechanisms.closure_and_entries`); actuators that are coordinate rows (a
joint-graph mechanism's) make the a × m actuator block block diagonal as
well, and its values are its blocks'
(:func:`manifold.blocks.labelled_block_singular_values`). The stack goes in
chunks of about the same memory for every mechanism (:func:`default_chunk`),
in threads with ``workers``.

What is not array work runs only where it is needed, through
:func:`classify.classify` itself: at a configuration where DΦ has less than
the survey's largest rank (a C-space singularity needs neighbours on M), at
an actuator singularity (the second-order test and the fibre certificate),
and wherever the batch's arithmetic cannot vouch for agreeing with a single
call (:func:`_unsure`): a singular value within the difference of the two
methods of its cut, where a decision could go either way, or a value whose
relative difference may exceed :data:`VALUE_ACCURACY` (near a singularity,
where the tangent basis is ill-conditioned: :func:`basis_error`). So the
batch equals repeated single calls, item by item: exactly there, and
elsewhere by the same decisions, on values that agree to 1e-9 where they are
kept (the kept margins, and the λ's where G is definite and J of full rank);
a value below a cut (a dropped margin, a λ of a rank-deficient J) is rounding
noise of size ε·κ·scale in either computation, and agrees only to that.
"""

from __future__ import annotations

import json
import numbers
from dataclasses import dataclass, field

import numpy as np

from manifold import DEFAULT_ATOL, DEFAULT_RTOL, check_rtol, handled_by_blocks, implicit, tangent_extents
from manifold.blocks import block_vectors, decompose, labelled_block_singular_values, union_of_values
from mechanisms import CLOSURE_TOLERANCE, ConfigurationError, Mechanism, closure_and_entries, closure_and_jacobian
from mechanisms.kinematics import rotation_blocks
from mechanisms.mechanism import dense_memory_estimate

from .classification import CLOSURE_BAND, classify, closure_of, not_on_m
from .metrics import JACOBI_ROWS, JACOBI_STACK, metric_root, moving_directions, proper_values, singular_values
from .model import model_of
from .progress import progress_bar
from .report import KINDS
from .survey import (end_effector_reference, model_coordinate_rows, rows_on, stacked as stacked_rows, survey_of,
                     unit_actuator_rows)
from .threads import ordered_map, thread_count

__all__ = ["Classifications", "classify_many", "kernel_bases", "default_chunk"]

#: the second-order verdict as the int8 column :attr:`Classifications.degenerate`
_DEGENERACY = {"degenerate": 1, "nondegenerate": 0, "undetermined": -1}


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
        Manipulability proper values λ₁ ≥ … ≥ λ_r, r the end-effector's expected rank (as many as J has rank
        on M, at most min(dim N, m); at least one, 0 for an end-effector that never moves), then NaN (all NaN
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


def classify_many(mechanism, points, survey=None, rtol=DEFAULT_RTOL, length_scale=None, chunk=None,
                  progress=False, workers=1):
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
    chunk : int, optional
        Configurations per chunk of array work (memory grows with it linearly); default
        :func:`default_chunk`, the same memory for every mechanism.
    progress : bool
        Show progress bars (:func:`classify.progress.progress_bar`, on stderr, after a second) over the
        chunks and the full classifications.
    workers : int
        Threads over the chunks' array work (:mod:`classify.threads`; -1: every usable core). Memory
        grows with ``workers × chunk``; the result does not depend on it.

    Returns
    -------
    Classifications
        Item i equals ``classify(model, points[i], survey=survey, rtol=rtol)``: the same kinds, ranks and
        degeneracy, the kept margins and the λ's of a definite G and full-rank J to 1e-9 relative, values below
        a cut to ε·κ(DΦ·s) of their scale (see the module notes).

    Raises
    ------
    ConfigurationError
        Naming the index of the first configuration that does not close the loops.
    """
    if not isinstance(mechanism, Mechanism) and length_scale is not None:
        raise ValueError("length_scale applies to a Mechanism; a Model carries its own end-effector metric")
    check_rtol(rtol)
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    points = np.array(points, dtype=float)  # a copy: the result's points stay the ones classified
    size = model.manifold.ambient.point_size
    if points.ndim == 0 or points.shape[-1] != size:
        raise ValueError(f"Expected points of shape (..., {size}), got {points.shape}")
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, numbers.Integral) or chunk < 1):
        raise ValueError(f"Expected chunk to be a positive integer (configurations), got {chunk!r}")
    shape = points.shape[:-1]
    flat = points.reshape(-1, size)
    chunk = default_chunk(model) if chunk is None else int(chunk)
    starts = range(0, len(flat), chunk)
    threads = thread_count(workers, len(starts))
    survey = survey_of(model, rtol) if survey is None else survey
    columns = _empty_columns(model, len(flat))
    columns["full"] = np.zeros(len(flat), dtype=bool)

    def first_order(start):
        stop = min(start + chunk, len(flat))
        _first_order(model, flat[start:stop], survey, rtol, offset=start, columns=_rows_of(columns, start, stop))
        return stop - start

    bar = progress_bar(len(flat), "classifying", shown=progress)
    for done in ordered_map(first_order, starts, threads):
        bar.update(done)
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


def default_chunk(model):
    """Configurations per chunk of :func:`classify_many` by default: the dense arrays of the whole chunk (DΦ,
    c × k, and the tangent bases, k × (k − c), as :func:`mechanisms.mechanism.dense_memory_estimate` counts them)
    within :data:`manifold.implicit.CHUNK_ENTRIES` floats (8 MiB), at least one configuration.

    A mechanism whose DΦ is taken block by block (:func:`manifold.handled_by_blocks`) has no dense DΦ here:
    its entries, its blocks and their right singular vectors (:func:`_block_entry_count`) count instead of
    c × k, beside the same four tangent bases.

    So a chunk takes about the same memory whatever the mechanism: it holds
    19,065 configurations of the five-bar (DΦ 3 × 5), 539 of the
    Gough–Stewart (30 × 36), 6 of a ladder of 100 four-bar loops (k = 400, 100 blocks 3 × 4),
    7,281 of a serial 6R arm (no DΦ, but 6 × 6 tangent bases).
    """
    coordinates, rows = model.manifold.ambient.dim, model.constraint_rows
    per_configuration = dense_memory_estimate(coordinates, rows) // 8
    if handled_by_blocks(model.manifold):
        per_configuration += _block_entry_count(model.manifold.pattern) - rows * coordinates
    return max(1, implicit.CHUNK_ENTRIES // max(1, per_configuration))


def _block_entry_count(pattern):
    """Floats of one configuration's DΦ taken block by block (:func:`manifold.blocks.decompose`): its entries and
    their padded copy (2 nnz), and for every block (r × q) its matrix, singular values and Vᴴ:
    ``2 nnz + Σ (r q + min(r, q) + q²)``."""
    total = 2 * pattern.nnz
    for group in pattern.blocks:
        count, rows, columns = group.positions.shape
        total += count * (rows * columns + min(rows, columns) + columns * columns)
    return total


def _decisions(values, tolerance):
    """Ranks (count of σ > tolerance) and margins [b, 2] of stacks of singular values, shape=[b, s]."""
    tolerance = np.broadcast_to(tolerance, values.shape[:1])
    ranks = np.count_nonzero(values > tolerance[:, None], axis=1)
    padded = np.concatenate([np.full((len(values), 1), np.nan), values, np.full((len(values), 1), np.nan)],
                            axis=1)
    rows = np.arange(len(values))
    margins = np.stack([padded[rows, ranks], padded[rows, ranks + 1]], axis=1)
    return ranks, margins


def _closure_and_jacobian(model, points, offset, entries=False):
    """DΦ·diag(s) of a chunk, shape=[b, c, k], or with `entries` DΦ's entries at the manifold's pattern,
    shape=[b, nnz] (unscaled: :func:`manifold.blocks.decompose`), after checking that every configuration closes
    its loops (as :func:`classify.classify`: |Φ| ≤ the closure tolerance and a point of M, not a spurious zero).

    For a joint-graph mechanism Φ, the half-turn test and DΦ come from one expansion of each loop
    (:func:`mechanisms.closure_and_jacobian`, :func:`mechanisms.closure_and_entries`).

    Raises
    ------
    ConfigurationError
        Naming the index (in the whole stack) of the first configuration that does not close.
    """
    manifold = model.manifold
    if model.mechanism is not None:
        rows, turns, jacobian = (closure_and_entries if entries else closure_and_jacobian)(model.mechanism, points)
        residuals = np.linalg.norm(rows, axis=-1)
        turns = turns & np.all(rotation_blocks(model.mechanism, points)[1], axis=-1)  # as classify's closes
    else:
        residuals = np.linalg.norm(manifold.constraint(points), axis=-1)
        turns = np.ones(len(points), dtype=bool)
        if manifold.is_solution is not None and not manifold.is_solution(points):
            turns = np.array([bool(manifold.is_solution(point)) for point in points])
        jacobian = (manifold.constraint_jacobian_entries if entries else manifold.constraint_jacobian)(points)
    # at the tolerance, the stack's rounding must not decide: classify's own arithmetic, one at a time
    for index in np.flatnonzero(np.abs(residuals - CLOSURE_TOLERANCE) <= CLOSURE_BAND * CLOSURE_TOLERANCE):
        residuals[index], turns[index] = closure_of(model, points[index])
    bad = np.flatnonzero(~(residuals <= CLOSURE_TOLERANCE) | ~turns)
    if len(bad):
        index = int(bad[0])
        raise ConfigurationError(not_on_m(model, points[index], residuals[index], f"configuration {offset + index}",
                                          ":"))
    if entries:
        return np.asarray(jacobian, dtype=float)
    return np.asarray(jacobian, dtype=float) * manifold.ambient.tangent_scales


def _first_order(model, points, survey, rtol, offset, columns=None):
    """Columns of the first-order classification of a chunk of configurations (see the module notes),
    written into `columns` (views of the whole stack's, :func:`_rows_of`) when given.

    The rank of DΦ·diag(s) and the tangent bases come from its blocks where the single call takes them so
    (:func:`manifold.implicit.handled_by_blocks`: :func:`manifold.blocks.decompose`, from DΦ's entries), else from
    the dense matrices."""
    count = len(points)
    scales = model.manifold.ambient.tangent_scales
    if handled_by_blocks(model.manifold):  # no dense c × k DΦ: its blocks from its entries
        jacobian = None
        shape = (count,) + model.manifold.pattern.shape
        decomposition = decompose(model.manifold, entries=_closure_and_jacobian(model, points, offset, True))
        constraint_values, constraint_tolerance = _block_constraint_values(decomposition, shape, rtol)
    else:
        jacobian = _closure_and_jacobian(model, points, offset)
        shape, decomposition = jacobian.shape, None
        constraint_values, constraint_tolerance = _constraint_values(jacobian, rtol)
    constraint_ranks, constraint_margins = _decisions(constraint_values, constraint_tolerance)
    largest = constraint_values[:, 0] if constraint_values.shape[1] else np.zeros(count)  # σ₁(DΦ·s)
    # below the survey's largest rank of DΦ: a possible C-space singularity; or where the arithmetic cannot
    # vouch for the decision or the margin: classified one at a time
    full = ((constraint_ranks < survey.constraint_rank)
            | _unsure(constraint_margins, constraint_tolerance, np.finfo(float).eps * largest))
    if columns is None:
        columns = _empty_columns(model, count)
        columns["full"] = np.zeros(count, dtype=bool)
    columns["ranks"]["cspace"][:] = constraint_ranks
    columns["margins"]["cspace"][:] = constraint_margins
    columns["tolerances"]["cspace"][:] = constraint_tolerance
    regular = np.flatnonzero(~full)
    structure = _arrow_structure(model) if decomposition is None else None
    for rank in np.unique(constraint_ranks[regular]):
        group = regular[constraint_ranks[regular] == rank]
        if decomposition is None:
            basis, amplification = _kernel_bases(jacobian[group], int(rank), structure)
        else:  # the SVDs' own vectors, as the single call's: a backward-stable basis block by block
            basis = _block_kernel_bases(decomposition, group, constraint_tolerance[group], model.manifold,
                                        int(rank))
            amplification = np.ones(len(group))
        if rank < shape[-2] and rank < shape[-1]:
            # DΦ short of its rows (an overconstrained chain): M may extend along fewer directions than ker DΦ
            # (an infinitesimal flex of a structure, manifold.tangent_extent): those are classified one at a time
            flexed = tangent_extents(model.manifold, points[group], scales[:, None] * basis) < basis.shape[-1]
            full[group[flexed]] = True
            group, basis, amplification = group[~flexed], basis[~flexed], amplification[~flexed]
            if not group.size:
                continue
        error = basis_error(largest[group], constraint_margins[group, 0], amplification)
        full[group] |= _regular_columns(model, points[group], scales[:, None] * basis, int(rank), survey, rtol,
                                        columns, group, error, blocks=decomposition is not None)
    columns["full"][:] = full | columns["singular"][:, KINDS.index("actuator")]
    return columns


#: relative band around a rank cut within which a decision is left to :func:`classify.classify` whatever the
#: error bound (:func:`_unsure`)
CUT_BAND = 1e-8

#: the largest estimate of the relative difference between a kept σ of the batch and a single call's for which
#: the batch's values stand (:func:`basis_error`); beyond it the configuration is classified one at a time. Half
#: the 1e-9 promised: the λ's and the condition number go as σ², with twice the σ's relative difference (values
#: below a cut are noise of size ε·κ·scale in both)
VALUE_ACCURACY = 5e-10

#: rounding units of a block's scale by which the batch's and a single call's singular values of one block may
#: differ beyond the tangent bases' difference (:func:`basis_error`; a fuzz measured 4.5)
BLOCK_ROUNDING = 8.0

#: the largest bound on the relative error of a singular value from the Gram matrix (:func:`_gram_values`)
GRAM_ACCURACY = 1e-10


def basis_error(largest, kept, amplification=1.0):
    """How far the batch's tangent bases may be from a single call's, as a fraction of unit length:
    ``ε·κ(J)`` with ``κ(J) = σ₁/σ_r`` of ``J = DΦ·diag(s)``, from its largest σ and its smallest kept σ
    (shape=[b] each; NaN where none is kept), shape=[b].

    Two backward-stable methods (the single call's SVD, the batch's QR) give
    the kernels of ``J + δJ`` with ``|δJ|`` of the order of ``ε σ₁(J)``,
    which differ by the order of ``ε κ(J)`` (Wedin's theorem). The worst-case
    constant (``4 k`` and more) is far from what happens: over 3,718
    configurations of the planar 3-RRR whose blocks are nearly singular, the
    batch's and the single call's kept σ's and λ's differed by at most 0.4 %
    of ``4 k ε κ(J)``, so ``ε κ(J)`` is some 7 times above the largest
    difference measured. The block-arrow solves (:func:`_arrow_bases`) may
    err more, by up to the condition number of the loops' own blocks:
    `amplification` (shape=[b]) stands for κ(J) where it is larger. Block by
    block (:func:`manifold.blocks.decompose`) both bases come from the blocks' SVDs,
    backward stable block by block, and each block's ``σ₁/σ_r`` is at most
    κ(J). A configuration without loops has the exact basis I (κ = 1). To this the
    estimate adds :data:`BLOCK_ROUNDING` ε, the rounding of a block's own
    singular values (the batch's Jacobi sweeps or closed forms, the single
    call's LAPACK), relative to the block's scale.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        condition = np.where(np.isnan(kept), 1.0, largest / kept)  # no loop rows, or nothing kept: the basis I
    return np.finfo(float).eps * (np.maximum(condition, amplification) + BLOCK_ROUNDING)


def _unsure(margins, tolerance, error, reported=True):
    """Configurations whose decision could differ from a single call's, or whose value is not known to
    :data:`VALUE_ACCURACY`, shape=[b].

    The σ's nearest the cut are the decision's margins (shape=[b, 2], from
    :func:`_decisions`: the smallest kept, the largest dropped): unsure where
    one lies within ``CUT_BAND·cut + error`` of the cut, or (where the values
    are `reported`) where `error` exceeds VALUE_ACCURACY of the kept one.
    `error` (shape=[b], or a scalar) estimates how far the batch's σ's may be
    from a single call's.
    """
    tolerance = np.broadcast_to(tolerance, margins.shape[:1])
    error = np.broadcast_to(error, margins.shape[:1])
    near = np.any(np.abs(margins - tolerance[:, None]) <= (CUT_BAND * tolerance + error)[:, None], axis=1)  # NaN: no
    if not reported:
        return near
    kept = margins[:, 0]
    return near | (np.isfinite(kept) & ~(error <= VALUE_ACCURACY * kept))


def _constraint_values(jacobian, rtol):
    """Singular values of DΦ·diag(s) and the cut of its rank, shape=[b, min(c, k)] and [b]
    (:func:`classify.metrics.singular_values`: closed forms and Jacobi for small matrices; for
    larger ones :func:`_gram_values` where it is certified accurate, LAPACK elsewhere)."""
    count, rows, columns = jacobian.shape
    if JACOBI_ROWS < rows <= columns and count >= JACOBI_STACK:
        values = _gram_values(jacobian)
    else:
        values = singular_values(jacobian)
    return values, np.maximum(rtol * (values[:, 0] if values.shape[1] else 0.0), DEFAULT_ATOL)


def _gram_values(matrices):
    """Singular values of a stack of wide matrices J from the eigenvalues of ``J Jᵀ``, with LAPACK's SVD
    wherever they are not certified to a relative :data:`GRAM_ACCURACY`, shape=[b, rows].

    Forming ``G = J Jᵀ`` (k products per entry) and a backward-stable
    symmetric eigensolver perturb each eigenvalue by at most about
    ``(c·k + 10 c) ε σ₁²``, so ``σᵢ = √λᵢ`` has relative error at most
    ``½ (c·k + 10 c) ε (σ₁/σᵢ)²``. That bound, for the smallest σ, is kept
    below :data:`GRAM_ACCURACY` (a Gough–Stewart's DΦ at a regular point has
    σ₁/σ_c ≈ 10: a bound of about 1e-11); elsewhere — any configuration near
    a rank cut, whose σ's are 1e6 apart — LAPACK's SVD of J is taken. The
    eigenvalue problem of the c × c Gram matrix costs a fraction of the SVD
    of the c × k matrix.
    """
    count, rows, columns = matrices.shape
    eigenvalues = np.linalg.eigvalsh(matrices @ np.swapaxes(matrices, -1, -2))[:, ::-1]
    smallest = eigenvalues[:, -1]
    factor = 0.5 * (rows * columns + 10 * rows) * np.finfo(float).eps
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = np.where(smallest > 0, factor * eigenvalues[:, 0] / np.where(smallest > 0, smallest, 1.0), np.inf)
    values = np.sqrt(np.clip(eigenvalues, 0.0, None))
    redo = np.flatnonzero(~(bound <= GRAM_ACCURACY))
    if len(redo):
        values[redo] = np.linalg.svd(matrices[redo], compute_uv=False)
    return values


def _block_constraint_values(decomposition, shape, rtol):
    """Singular values of DΦ·diag(s) from its blocks' and the cut of its rank, shape=[b, min(c, k)] and [b],
    as :func:`manifold.blocks.block_rank` for one point: the union of the blocks' values, padded with the
    exact zeros of the whole matrix (rows no entry touches, blocks with more rows than columns), descending.

    Parameters
    ----------
    decomposition : list of tuple
        :func:`manifold.blocks.decompose` of the chunk's DΦ·diag(s).
    shape : tuple of int
        ``(b, c, k)``: the chunk's DΦ.
    rtol : float
    """
    count, rows, columns = shape
    values = union_of_values([values for _, values, _ in decomposition], count, min(rows, columns))
    return values, np.maximum(rtol * (values[:, 0] if values.shape[1] else 0.0), DEFAULT_ATOL)


def _block_kernel_bases(decomposition, selection, tolerance, manifold, rank):
    """Orthonormal bases of ker DΦ·diag(s) at the configurations `selection` of a chunk (of one rank), from its
    blocks, shape=[g, k, k − rank]: as :func:`manifold.tangent_basis` for one point, the right singular vectors
    of each block beyond its own count of values above the whole matrix's cut (the direct sum of the blocks'
    kernels, in the order of :func:`manifold.blocks.block_vectors`), then the unit vectors of the pattern's free
    columns.

    Parameters
    ----------
    decomposition : list of tuple
        :func:`manifold.blocks.decompose` of the chunk's DΦ·diag(s).
    selection : ndarray of int, shape=[g]
        Configurations of the chunk, all with the same rank of DΦ·diag(s).
    tolerance : ndarray, shape=[g]
        The cut of the rank decision of each whole matrix.
    manifold : ImplicitManifold
    rank : int
        The rank of each whole matrix (the count of its values above the cut: the sum of the blocks').
    """
    count, size = len(selection), manifold.ambient.dim
    free = manifold.pattern.free_columns
    dimension = size - rank
    pieces = block_vectors([(group, values[selection], right[selection]) for group, values, right in decomposition],
                           tolerance, kernel=True)
    bases = np.zeros((count, size, dimension))
    start = np.zeros(count, dtype=np.intp)
    for configurations, columns, vectors in pieces:
        counts = np.bincount(configurations, minlength=count)
        first = np.cumsum(counts) - counts  # where each configuration's vectors start among the piece's
        numbers = start[configurations] + np.arange(len(configurations)) - first[configurations]
        bases[configurations[:, None], columns, numbers[:, None]] = vectors
        start += counts
    bases[:, free, np.arange(dimension - len(free), dimension)] = 1.0
    return bases


#: the largest condition number ``|C|_F |C⁻¹|_F`` of a loop's own block for which :func:`_arrow_bases` is used
ARROW_CONDITION = 1e3


@dataclass(frozen=True, eq=False)
class ArrowStructure:
    """DΦ in block-arrow form: every loop has as many columns of its own as rows.

    With the loops' own columns ``P_i`` (touched by loop i only) and the
    shared columns S (touched by several loops, or none), DΦ's rows of loop
    i read ``B_i v_S + C_i v_{P_i}`` with ``C_i`` square: where every
    ``C_i`` is invertible, ker DΦ is ``{v_S free, v_{P_i} = −C_i⁻¹ B_i v_S}``
    — a Gough–Stewart platform (a loop through leg 0 and leg i), a planar or
    spherical 3-RRR (Park & Kim 1999; Gosselin & Angeles 1990).

    Attributes
    ----------
    shared : ndarray of int, shape=[m]
    rows, own : ndarray of int, shape=[loops, R]
        Each loop's rows and own columns.
    """

    shared: np.ndarray
    rows: np.ndarray
    own: np.ndarray


def _arrow_structure(model):
    """The :class:`ArrowStructure` of a model's DΦ, or None (no joint graph, or a loop whose own columns are
    not as many as its rows: e.g. a single loop with more joints than rows)."""
    if model.mechanism is None:
        return None
    from mechanisms import constraint_pattern, kinematics_of

    pattern = constraint_pattern(model.mechanism)
    loops = len(kinematics_of(model.mechanism).loops)
    count, columns = pattern.shape
    if loops < 2 or count % loops:
        return None
    per_loop = count // loops
    touched = np.zeros((loops, columns), dtype=bool)
    touched[pattern.rows // per_loop, pattern.columns] = True
    own_columns = touched & (touched.sum(axis=0) == 1)
    if np.any(own_columns.sum(axis=1) != per_loop):
        return None
    return ArrowStructure(shared=np.flatnonzero(~own_columns.any(axis=0)),
                          rows=np.arange(count).reshape(loops, per_loop),
                          own=np.array([np.flatnonzero(row) for row in own_columns]))


def _arrow_bases(matrices, structure):
    """Orthonormal kernel bases through the block-arrow form (:class:`ArrowStructure`), shape=[b, k, m],
    and the largest ``|C_i|_F |C_i⁻¹|_F`` of each configuration's loops, shape=[b]: the bases are trusted
    where it is at most ARROW_CONDITION (elsewhere inf, and the bases zero).

    ``N = [I; −C_i⁻¹ B_i]`` (rows in column order) spans the kernel and has
    ``σ_min(N) ≥ 1``; its reduced QR factor Q is an orthonormal basis of the
    same subspace. Small solves per loop and a k×m QR instead of the k×k
    complete QR of DΦᵀ.
    """
    count, rows, columns = matrices.shape
    flat = matrices.reshape(count, rows * columns)
    own = np.take(flat, structure.rows[:, :, None] * columns + structure.own[:, None, :], axis=1)  # [b, loops, R, R]
    coupling = np.take(flat, structure.rows[:, :, None] * columns + structure.shared[None, None, :],
                       axis=1)                                                                     # [b, loops, R, m]
    largest = np.full(count, np.inf)
    bases = np.zeros((count, columns, len(structure.shared)))
    with np.errstate(all="ignore"):
        try:
            inverse = np.linalg.inv(own)
        except np.linalg.LinAlgError:  # an exactly singular block: those configurations take the general way
            singular = np.any(np.linalg.det(own) == 0.0, axis=1)
            own = np.where(singular[:, None, None, None], np.eye(rows // len(structure.rows) or 1), own)
            try:
                inverse = np.linalg.inv(own)
            except np.linalg.LinAlgError:
                return bases, largest
            inverse[singular] = np.nan
    with np.errstate(all="ignore"):
        condition = np.linalg.norm(own, axis=(-2, -1)) * np.linalg.norm(inverse, axis=(-2, -1))
    good = np.all(condition <= ARROW_CONDITION, axis=1)  # NaN (overflow) is not good
    kept = np.flatnonzero(good)
    if not len(kept):
        return bases, largest
    spanning = np.zeros((len(kept), columns, len(structure.shared)))
    spanning[:, structure.shared, np.arange(len(structure.shared))] = 1.0
    spanning[:, structure.own.ravel(), :] = -(inverse[good] @ coupling[kept]).reshape(len(kept), -1,
                                                                                       len(structure.shared))
    bases[kept] = np.linalg.qr(spanning)[0]
    largest[kept] = condition[kept].max(axis=1)
    return bases, largest


def kernel_bases(matrices, rank, structure=None):
    """Orthonormal bases of the kernels of a stack of matrices of one numerical rank, shape=[b, columns,
    columns − rank] (:func:`_kernel_bases`, without the amplification)."""
    return _kernel_bases(matrices, rank, structure)[0]


def _kernel_bases(matrices, rank, structure=None):
    """Orthonormal bases of the kernels of a stack of matrices of one numerical rank, shape=[b, columns,
    columns − rank], and how much more than a backward-stable method the bases' error may be, shape=[b]:
    1, or the block-arrow's ``|C_i|_F |C_i⁻¹|_F`` where it was used (for :func:`basis_error`).

    Of full row rank (``rank`` = rows, the usual case of loop rows), through
    the block-arrow form where `structure` gives one and the loops' own
    blocks are well conditioned (:func:`_arrow_bases`), else the last
    columns of the complete QR factors of the transposes (Householder QR:
    backward stable, and cheaper than the SVD); otherwise the right singular
    vectors beyond the rank, as :func:`manifold.tangent_basis`. Each spans
    the same subspace; a basis is only ever used through quantities that do
    not depend on which orthonormal basis it is (singular values, λ's).
    """
    count, rows, columns = matrices.shape
    stable = np.ones(count)
    if rows == 0:
        return np.broadcast_to(np.eye(columns), (count, columns, columns)), stable
    if structure is not None and rank == rows and len(structure.shared) == columns - rows:
        bases, amplification = _arrow_bases(matrices, structure)
        rest = np.flatnonzero(~np.isfinite(amplification))
        if len(rest):
            bases[rest], amplification[rest] = _kernel_bases(matrices[rest], rank)
        return bases, amplification
    if rank == rows and rows <= columns:
        orthogonal = np.linalg.qr(np.swapaxes(matrices, -1, -2), mode="complete")[0]
        return orthogonal[:, :, rank:], stable
    return np.swapaxes(np.linalg.svd(matrices, full_matrices=True)[2][:, rank:, :], -1, -2), stable


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


def _regular_columns(model, points, basis, constraint_rank, survey, rtol, columns, rows, error, blocks=False):
    """Fill `columns` at `rows`: configurations where DΦ has rank `constraint_rank` ≥ the survey's, with
    tangent bases `basis` accurate to `error` (:func:`basis_error`, shape=[g]). Returns where a decision or
    a value is not sure (:func:`_unsure`), shape=[g]: those are classified one at a time.

    Actuators that are coordinate rows are applied to the bases by picking rows (:func:`classify.survey.rows_on`).
    Where the bases come from DΦ's blocks (`blocks`: each column supported on one block or free column), the
    actuator block's singular values are then its own blocks'
    (:func:`manifold.blocks.labelled_block_singular_values`)."""
    k = model.manifold.ambient.dim
    dof = k - constraint_rank
    count = len(points)
    unit_actuators, actuator_scale = unit_actuator_rows(model)
    actuator_tolerance = max(rtol * actuator_scale, DEFAULT_ATOL)
    actuator_block = rows_on(model, "unit_actuator_rows", unit_actuators, basis)  # [g, a, m]
    coordinates = model_coordinate_rows(model, "unit_actuator_rows", unit_actuators)
    if blocks and coordinates is not None:
        components = model.manifold.pattern.column_components
        actuator_values = labelled_block_singular_values(actuator_block, components[coordinates[0]],
                                                         components[np.argmax(basis != 0.0, axis=-2)],
                                                         singular_values=singular_values)
    else:
        actuator_values = singular_values(actuator_block)
    actuator_ranks, actuator_margins = _decisions(actuator_values, actuator_tolerance)
    unsure = _unsure(actuator_margins, actuator_tolerance, actuator_scale * error)
    n = model.end_effector_dimension
    if n:
        end_effector_jacobian = np.broadcast_to(model.end_effector_jacobian(points), (count, n, k))
        root = metric_root(model.end_effector_metric)
        end_effector_rows = root @ end_effector_jacobian
        reference = end_effector_reference(model, points, end_effector_rows, root)
        end_effector_scale = _largest(np.broadcast_to(reference, (count,) + reference.shape[-2:]))
        end_effector_tolerance = np.maximum(rtol * end_effector_scale, DEFAULT_ATOL)
        end_effector_block = end_effector_rows @ basis
        end_effector_ranks, end_effector_margins = _decisions(singular_values(end_effector_block),
                                                              end_effector_tolerance)
        unsure |= _unsure(end_effector_margins, end_effector_tolerance, end_effector_scale * error)

    def stacked(selection=slice(None)):
        """The map whose kernel is the idle freedoms (:func:`classify.survey.stacked`) at the configurations
        `selection`."""
        return stacked_rows(actuator_block[selection], actuator_scale, end_effector_block[selection],
                            end_effector_scale[selection])

    raised = constraint_rank > survey.constraint_rank
    if n and (raised or survey.joint_rank < dof):  # else the stacked rank cannot raise the survey's
        joint_tolerance = max(rtol, DEFAULT_ATOL)  # reference scale 1
        joint_ranks, joint_margins = _decisions(singular_values(stacked()), joint_tolerance)
        # the decision only (these values are not reported); the stacked rows have norms at most 1
        unsure |= _unsure(joint_margins, joint_tolerance, 2.0 * error, reported=False)
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
        return unsure
    expected_end_effector = np.minimum(min(n, dof), end_effector_largest)
    columns["ranks"]["end_effector"][rows] = end_effector_ranks
    columns["expected_ranks"]["end_effector"][rows] = expected_end_effector
    columns["margins"]["end_effector"][rows] = end_effector_margins
    columns["tolerances"]["end_effector"][rows] = end_effector_tolerance
    columns["singular"][rows, KINDS.index("end_effector")] = end_effector_ranks < expected_end_effector
    # G definite on the motions that move something (with idle freedoms, on a complement of them, as classify)
    moves = dof - idle
    counts = np.maximum(1, np.minimum(expected_end_effector, moves))  # as many λ's as J has rank on M (classify)
    definite_rows = (moves > 0) & (actuator_ranks == moves)
    for kept, count in sorted({(int(a), int(b)) for a, b in zip(moves[definite_rows], counts[definite_rows])}):
        definite = np.flatnonzero((moves == kept) & (actuator_ranks == kept) & (counts == count))
        motions = basis[definite]
        if kept < dof:
            motions = motions @ moving_directions(stacked(definite), kept)
        actuator_motions = rows_on(model, "actuators", model.actuators, motions)
        values = proper_values(actuator_motions, end_effector_jacobian[definite] @ motions,
                               model.end_effector_metric, count)
        vanishing = end_effector_ranks[definite] < count
        smallest = values[:, -1]
        condition = np.where(vanishing | (smallest <= 0.0), np.nan,
                             values[:, 0] / np.where(smallest > 0.0, smallest, 1.0))
        columns["eigenvalues"][rows[definite], :values.shape[1]] = values
        columns["condition_number"][rows[definite]] = condition
    return unsure


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


def _rows_of(columns, start, stop):
    """Views of rows ``start:stop`` of every column (writing into them fills the whole stack's)."""
    return {name: ({kind: array[start:stop] for kind, array in value.items()} if isinstance(value, dict)
                   else value[start:stop]) for name, value in columns.items()}


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
