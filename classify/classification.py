"""The Park-Kim classification of a configuration (Park & Kim 1999, Section 3).

Each kind is a rank drop below the rank expected of it (docs/design.rst, "The
three kinds"):

* C-space: ``rank DΦ(p) < r``, r the rank of DΦ on M near p;
* actuator: ``rank G(p) < m − i``, i the idle freedoms: m minus the largest
  rank on M of the stacked map (E^½Dπ T; H^½Df T) (of G without
  end-effector). An idle freedom is a direction of ker G that is also in
  ker J, generically on M: it moves neither an actuator nor the
  end-effector (a leg's spin between two ball joints; the spin of a 5-SPU's
  tool about its own axis once the end-effector is ``output: tool``). A
  locked-actuator freedom that moves the end-effector (a direction of
  ker G outside ker J, generically on M; there are
  ``largest rank of the stacked map − largest rank of G`` of them) is not
  idle: where there is one everywhere on M, the design is architecturally
  singular and every configuration is an actuator singularity (Gosselin &
  Angeles 1990, eq. 87), flagged in the report (``architecture_singular``,
  ``moving_idle_freedoms``);
* end-effector: ``rank J(p) < min(dim N, m, largest rank of J on M)``.

All ranks come from :func:`manifold.numerical_rank` on dimensionless maps
(DΦ·diag(s), unit actuator rows, H^½Df over its own scale) and carry their
margins: no verdict depends on the unit of length or on actuator weights.
At a C-space singularity, G and J are computed on ker DΦ(p) and flagged.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from manifold import (
    DEFAULT_RTOL, EXTENT_CUT, check_rtol, local_rank, numerical_rank, scaled_jacobian, tangent_basis, tangent_extent,
)
from mechanisms import CLOSURE_TOLERANCE, ConfigurationError, Mechanism
from mechanisms.kinematics import closure_failure

from .metrics import manipulability, moving_directions
from .model import model_of
from .report import KindResult, Report
from .second_order import idle_slice, second_order_test
from .survey import actuator_decision as decide_actuator, decision_blocks, freedom_rows, rows_on, stacked, survey_of, \
    unit_actuator_rows

__all__ = ["classify"]


def _kernel(matrix, rank):
    """Orthonormal basis of the kernel of a matrix given its numerical rank, shape=[columns, columns − rank]."""
    _, _, right = np.linalg.svd(matrix, full_matrices=True)
    return right[rank:].T


def classify(mechanism, point, survey=None, rng=None, rtol=DEFAULT_RTOL, length_scale=None):
    """Classify one configuration of a mechanism.

    Parameters
    ----------
    mechanism : Mechanism or Model
        A joint graph, or any :class:`~classify.model.Model` (e.g. an implicit description).
    point : array_like, shape=[point_size]
        A configuration on M (see :func:`mechanisms.configuration`).
    survey : Survey, optional
        Largest ranks over M; default the model's own, computed once and kept
        (:func:`classify.survey.survey_of`). Either is raised to the ranks
        at `point` where they exceed it (:meth:`Survey.including`).
    rng : numpy.random.Generator, optional
        For the sampling near `point` (local rank, where needed) and the
        second-order test; default ``numpy.random.default_rng(0)``
        (deterministic). The survey has its own seed.
    rtol : float
        Relative cut of every rank decision (:func:`manifold.numerical_rank`).
    length_scale : float, optional
        L of the SE(2)/SE(3) and tool (ℝ³ × S²) end-effector metrics
        (default the characteristic length). Only for a Mechanism: a Model
        carries its own H.

    Returns
    -------
    Report

    Raises
    ------
    ConfigurationError
        If `point` does not close the loops.
    """
    rng = np.random.default_rng(0) if rng is None else rng
    check_rtol(rtol)
    if not isinstance(mechanism, Mechanism) and length_scale is not None:
        raise ValueError("length_scale applies to a Mechanism; a Model carries its own end-effector metric")
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    point = np.asarray(point, dtype=float)
    manifold = model.manifold
    loop_rows = manifold.constraint(point)
    residual, closes = closure_of(model, point, loop_rows)
    if not (residual <= CLOSURE_TOLERANCE and closes):
        raise ConfigurationError(not_on_m(model, point, residual, "the configuration"))
    names = model.coordinate_names
    k = manifold.ambient.dim
    scales = manifold.ambient.tangent_scales
    notes = []
    if np.shape(loop_rows)[-1] == 0:
        notes.append("no loop: an open (serial) chain, M is all of K; check the joints' links if a loop was meant")

    # C-space: rank of DΦ at p against the rank on M near p (dimensionless: DΦ·diag(s)). Where DΦ has the
    # largest rank the survey found on M, p is a regular point of M and no neighbour is needed.
    basis, constraint_decision = tangent_basis(manifold, point, rtol=rtol)
    distance = _distance_bound(residual, constraint_decision)
    if distance > rtol:
        notes.append(f"p closes the loops within the closure tolerance (‖Φ‖ = {residual:.2g}) but may lie up to "
                     f"{distance:.2g} from M (‖Φ‖ over the smallest kept singular value of DΦ·diag(s), "
                     f"{constraint_decision.margin[0]:.2g}: DΦ is nearly singular here); a decision within that of "
                     f"its cut may differ on M: project p onto M (--project)")
    survey = survey_of(model, rtol) if survey is None else survey
    nearby = _Neighbourhood(manifold, point, rng, rtol)
    near_rank = (constraint_decision.rank if constraint_decision.rank >= survey.constraint_rank
                 else nearby.local.rank)
    dof = k - near_rank
    cspace_singular = constraint_decision.rank < near_rank
    cspace_extra = {}
    if cspace_singular:
        cspace_extra = {"kernel_dimension": int(basis.shape[1]), "tangent_cone_dimension": int(dof),
                        "tangent_cone_span": _secant_span(manifold, point, nearby.local.neighbours)}
        notes.append("C-space singularity: actuator and end-effector ranks are computed on ker DΦ(p), "
                     "which is larger than the tangent spaces of M nearby")
    lost = (scales[:, None] * _kernel_beyond(scaled_jacobian(manifold, point), constraint_decision.rank, near_rank)
            if cspace_singular else np.zeros((k, 0)))
    expected_constraint = near_rank
    rows = int(np.shape(loop_rows)[-1])
    if not cspace_singular and dof and constraint_decision.rank < rows:
        # DΦ(p) short of its rows at the rank M has near p: M may still extend along fewer directions than
        # ker DΦ(p) has (an infinitesimal flex of a structure that cannot move, where M is a point)
        extent = tangent_extent(manifold, point, basis)
        if extent.extent < dof:
            cspace_singular, lost = True, extent.still
            expected_constraint = min(rows, k - extent.extent)
            cspace_extra = {"kernel_dimension": int(basis.shape[1]), "tangent_cone_dimension": extent.extent,
                            "tangent_cone_span": extent.extent,
                            # the margin of this verdict: the secants' singular values against their cut
                            "secant_singular_values": [float(value) for value in extent.singular_values],
                            "secant_cut": EXTENT_CUT}
            secants = ", ".join(f"{value:.2g}" for value in extent.singular_values)
            notes.append(f"C-space singularity: M extends along {extent.extent} of the {dof} directions of "
                         f"ker DΦ(p) (secants' singular values {secants}; cut {EXTENT_CUT}); the others are "
                         f"infinitesimal motions no motion of M follows (a structure flat or stretched); actuator "
                         f"and end-effector ranks are computed on ker DΦ(p)")
            dof = extent.extent
    cspace = KindResult(cspace_singular, constraint_decision.rank, expected_constraint, constraint_decision, lost,
                        cspace_extra)

    # actuator: G = (E^½ T)ᵀ(E^½ T), decided on the unit actuator rows (weights and units do not matter)
    blocks = decision_blocks(model, point, basis)
    actuator_block, actuator_scale, end_effector_block, end_effector_scale = blocks
    actuator_decision = decide_actuator(model, actuator_block, basis, actuator_scale, rtol=rtol)
    n = model.end_effector_dimension
    end_effector_decision = numerical_rank(end_effector_block, rtol=rtol, scale=end_effector_scale) if n else None
    if not cspace_singular:  # at a C-space singularity ker DΦ(p) is larger than the tangent spaces of M
        survey = _including_point(survey, constraint_decision.rank, actuator_decision, end_effector_decision,
                                  lambda: numerical_rank(stacked(*blocks), rtol=rtol, scale=1.0),
                                  len(model.actuators) + n, basis.shape[1])
    else:  # DΦ's rank still proves what M reaches (a flex where the survey missed a larger rank)
        survey = survey.including(constraint_decision.rank)
    idle = survey.idle_freedoms(dof)
    expected_actuator = dof - idle
    actuator_singular = actuator_decision.rank < expected_actuator
    expected_end_effector = min(n, dof, survey.end_effector_rank) if n else 0
    end_effector_singular = bool(n) and end_effector_decision.rank < expected_end_effector
    # with idle freedoms ker G and ker J contain them: the slice of M transverse to them, and their directions at
    # p (the limit of the idle kernels at neighbours, classify.second_order.idle_slice), where a kind is singular
    sliced, idle_directions = None, None
    if idle and not cspace_singular and (actuator_singular or end_effector_singular):
        sliced, idle_directions = idle_slice(manifold, point, basis, nearby.local.neighbours,
                                             lambda q: freedom_rows(model, q), idle, rtol=rtol)
    actuator_kernel = (_lost(basis, actuator_block, actuator_decision.rank, idle_directions, scales)
                       if actuator_singular else np.zeros((k, 0)))
    actuator = KindResult(actuator_singular, actuator_decision.rank, expected_actuator, actuator_decision,
                          actuator_kernel, {"on_kernel_of_constraint": True} if cspace_singular else {})

    # end-effector: J = Df T, decided on H^½ J over σ₁(H^½ R·diag(s)), R every joint's rate (survey.decision_rows)
    end_effector = None
    if n:
        decision = end_effector_decision
        kernel = (_lost(basis, end_effector_block, decision.rank, idle_directions, scales)
                  if end_effector_singular else np.zeros((k, 0)))
        end_effector = KindResult(end_effector_singular, decision.rank, expected_end_effector, decision, kernel,
                                  {"on_kernel_of_constraint": True} if cspace_singular else {})

    # manipulability proper values, where G is definite on T_pM (in the user's units and weights)
    # (with idle freedoms, on a complement of them: G and JᵀHJ both vanish on them, metrics.moving_directions)
    proper = None
    moves = basis.shape[1] - idle
    if n and not cspace_singular and moves > 0 and actuator_decision.rank == moves:
        motions = basis if not idle else basis @ moving_directions(stacked(*blocks), moves)
        # as many λ's as J has rank on M (at least one: 0 for an end-effector that never moves): a direction the
        # end-effector never moves (a planar mechanism written in space: z) would add a λ = 0 everywhere
        proper = manipulability(rows_on(model, "actuators", model.actuators, motions),
                                model.end_effector_jacobian(point) @ motions,
                                model.end_effector_metric, max(1, min(end_effector.expected_rank, moves)),
                                rank=end_effector.rank)

    # second order, at regular points of M only
    second = None
    if actuator_singular and cspace_singular:
        notes.append("the second-order test is not run at a C-space singularity: degeneracy undetermined")
    if actuator_singular and not cspace_singular:
        unit_actuators = unit_actuator_rows(model)[0]
        tested, tested_basis = manifold, basis
        if idle:
            tested = sliced
            if tested is None:
                notes.append("idle freedoms: no neighbour on M to find their directions; "
                             "the second-order test is not run")
            else:
                tested_basis = tangent_basis(tested, point, rtol=rtol)[0]
                notes.append(f"second-order test on a slice of M through p transverse to the {idle} idle "
                             f"freedom(s) (their directions: the limit of the idle kernels at neighbours on M)")
        if tested is not None:
            second = second_order_test(tested, point, tested_basis, unit_actuators, rng, rtol=rtol,
                                       scale=actuator_scale, whole=manifold if idle else None)
    if idle:
        notes.append(f"{idle} idle freedom(s): motions that move neither an actuator nor the end-effector")
    moving = min(dof, survey.moving_idle_freedoms)
    if moving:
        notes.append(f"architecture singularity: {moving} locked-actuator freedom(s) move the end-effector at "
                     f"every configuration of M (G has rank at most {survey.actuator_rank} on M), so every "
                     f"configuration is an actuator singularity — unless the task ignores that motion: if it is "
                     f"the spin of an axisymmetric tool, make the end-effector 'output: tool' (point and axis), "
                     f"which that spin does not move")

    return Report(
        mechanism=model.name, dof=dof, ambient_dimension=k, coordinate_names=names,
        displacements={} if model.describe is None else model.describe(point), cspace=cspace, actuator=actuator,
        end_effector=end_effector, manipulability=proper, second_order=second,
        idle_freedoms=idle, survey=survey.to_dict(), notes=tuple(notes), moving_idle_freedoms=moving,
    )


def _lost(basis, block, rank, idle_directions, scales):
    """The lost directions of a kind, joint-rate vectors [k, ·]: ker(`block`) on the tangent basis, less the idle
    freedoms' directions where there are some (dimensionless, [k, ι]: they move neither an actuator nor the
    end-effector, and are no lost motion), orthonormal for ⟨·,·⟩_s."""
    kernel = basis @ _kernel(block, rank)
    if idle_directions is None or not idle_directions.shape[1]:
        return kernel
    unit = kernel / scales[:, None]
    unit = unit - idle_directions @ (idle_directions.T @ unit)
    count = max(0, kernel.shape[1] - idle_directions.shape[1])
    return scales[:, None] * np.linalg.svd(unit, full_matrices=False)[0][:, :count]


def _kernel_beyond(jacobian, rank, expected):
    """The directions of ker DΦ(p)·diag(s) in excess of the nearby tangent spaces (dimensionless)."""
    _, _, right = np.linalg.svd(jacobian, full_matrices=True)
    return right[rank:expected].T


def _secant_span(manifold, point, neighbours):
    """Numerical rank of the dimensionless secants from p to nearby points of M (span of the tangent cone)."""
    if not len(neighbours):
        return 0
    secants = manifold.ambient.inverse_retract(point, neighbours) / manifold.ambient.tangent_scales
    secants = secants / np.linalg.norm(secants, axis=1, keepdims=True)
    return int(numerical_rank(secants, rtol=1e-2).rank)


class _Neighbourhood:
    """Points of M near p and the largest rank of DΦ among them (:func:`manifold.local_rank`), sampled on
    first use only: at a point where DΦ has the survey's largest rank no neighbour is needed."""

    def __init__(self, manifold, point, rng, rtol):
        self._arguments = (manifold, point, rng, rtol)

    @cached_property
    def local(self):
        manifold, point, rng, rtol = self._arguments
        return local_rank(manifold, point, rng, rtol=rtol)


#: relative band about the closure tolerance in which a stack's ‖Φ‖ is computed again one configuration at a
#: time (:func:`closure_of`): Φ's rows come from sums of terms of order 1, so at ‖Φ‖ = 1e-9 their rounding,
#: which depends on the stack's shape (a Gough-Stewart configuration's ‖Φ‖ was 1e-9 alone, 1.00000002e-9 in a
#: stack of two), is about 1e-8 of it
CLOSURE_BAND = 1e-5


def closure_of(model, point, rows=None):
    """‖Φ(p)‖ and whether p is a point of M rather than a spurious zero of Φ (a loop at a half-turn): the
    closure decision of :func:`classify`, which :func:`classify.batch.classify_many` takes again for a
    configuration within :data:`CLOSURE_BAND` of the tolerance (a point there must not be accepted alone and
    refused in a stack). From Φ alone (no DΦ, which a large mechanism never forms densely).

    Parameters
    ----------
    model : Model
    point : ndarray, shape=[point_size]
    rows : ndarray, shape=[c], optional
        Φ(p), when already computed.

    Returns
    -------
    residual : float
    closes : bool
    """
    point = np.asarray(point, dtype=float)
    manifold = model.manifold
    rows = manifold.constraint(point) if rows is None else rows
    residual = float(np.linalg.norm(np.atleast_2d(rows), axis=-1)[0])
    return residual, manifold.is_solution is None or bool(manifold.is_solution(point))


def not_on_m(model, point, residual, what, separator=" is"):
    """Why `point` is refused (:func:`mechanisms.kinematics.closure_failure`): a ball joint's block that is no
    rotation, named (Φ's rotation rows ``½ vee(R − Rᵀ)`` do not see it), a loop closing only at a half-turn, else
    its residual; ``what`` + ``separator`` start the message."""
    if model.mechanism is not None:
        failure = closure_failure(model.mechanism, point, CLOSURE_TOLERANCE)
        if failure is not None and failure[0] == "rotation":
            return f"{what}: {failure[1]}: not a point of the C-space"
        if failure is not None and failure[0] == "half-turn":
            return f"{what}: {failure[1]}"
    return f"{what}{separator} not on the C-space (|Φ| = {residual:.3g}); project it first"


def _distance_bound(residual, decision):
    """An upper bound of the dimensionless distance from p to M to first order: the Gauss-Newton step
    ‖(DΦ·s)⁺ Φ‖ ≤ ‖Φ‖ / σ_r, σ_r the smallest kept singular value of DΦ·diag(s) (0 without rows or rank).
    :func:`classify` notes it where it exceeds rtol, the relative size of its rank cuts: a heuristic (the
    singular values move by about the distance times the curvature of Φ, taken as of order 1)."""
    kept = decision.margin[0]
    return 0.0 if kept is None or not residual else residual / kept


def _including_point(survey, constraint_rank, actuator_decision, end_effector_decision, joint_decision, rows,
                     columns):
    """The survey raised to the ranks at p (:meth:`Survey.including`); the stacked map's rank
    (`joint_decision()`, a callable; the map is `rows` × `columns`) is computed only where an end-effector makes
    it count and it could raise the survey's: not where DΦ has the survey's rank and the survey's joint rank
    already is ``min(rows, columns)``, which no rank of the map exceeds."""
    if constraint_rank < survey.constraint_rank:
        return survey
    if end_effector_decision is None:
        return survey.including(constraint_rank, actuator_decision.rank)
    if constraint_rank == survey.constraint_rank and survey.joint_rank is not None \
            and survey.joint_rank >= min(rows, columns):
        return survey.including(constraint_rank, actuator_decision.rank, end_effector_decision.rank, None)
    return survey.including(constraint_rank, actuator_decision.rank, end_effector_decision.rank,
                            joint_decision().rank)
