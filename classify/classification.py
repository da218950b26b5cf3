"""The Park-Kim classification of a configuration (Park & Kim 1999, Section 3).

Each kind is a rank drop below the rank expected of it (docs/design.rst, "The
three kinds"):

* C-space: ``rank DΦ(p) < r``, r the rank of DΦ on M near p;
* actuator: ``rank G(p) < min(m, largest rank of G on M)``;
* end-effector: ``rank J(p) < min(dim N, m, largest rank of J on M)``.

All ranks come from :func:`manifold.numerical_rank` and carry their margins.
At a C-space singularity, G and J are computed on ker DΦ(p) and flagged.
"""

from __future__ import annotations

import numpy as np

from manifold import DEFAULT_RTOL, local_rank, numerical_rank, tangent_basis
from mechanisms import CLOSURE_TOLERANCE, ConfigurationError, Mechanism

from .metrics import manipulability, metric_root
from .model import model_of
from .report import KindResult, Report
from .second_order import idle_slice, second_order_test
from .survey import survey as survey_mechanism

__all__ = ["classify", "classify_many"]


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
        Largest ranks over M; computed (from the home and `point`) when not given.
        Pass one survey to classify many configurations consistently.
    rng : numpy.random.Generator, optional
        For local sampling, the survey and the second-order test; default
        ``numpy.random.default_rng(0)`` (deterministic).
    rtol : float
        Relative cut of every rank decision (:func:`manifold.numerical_rank`).
    length_scale : float, optional
        L of the SE(2)/SE(3) end-effector metric (default the characteristic
        length). Only for a Mechanism: a Model carries its own H.

    Returns
    -------
    Report

    Raises
    ------
    ConfigurationError
        If `point` does not close the loops.
    """
    rng = np.random.default_rng(0) if rng is None else rng
    if not isinstance(mechanism, Mechanism) and length_scale is not None:
        raise ValueError("length_scale applies to a Mechanism; a Model carries its own end-effector metric")
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    point = np.asarray(point, dtype=float)
    manifold = model.manifold
    residual = float(np.linalg.norm(manifold.constraint(point)))
    if residual > CLOSURE_TOLERANCE or (manifold.is_solution is not None and not manifold.is_solution(point)):
        raise ConfigurationError(f"the configuration is not on the C-space (|Φ| = {residual:.3g}); project it first")
    names = model.coordinate_names
    k = manifold.ambient.dim
    notes = []

    # C-space: rank of DΦ at p against the rank on M near p
    jacobian = manifold.constraint_jacobian(point)
    basis, constraint_decision = tangent_basis(manifold, point, rtol=rtol)
    near = local_rank(manifold, point, rng, rtol=rtol)
    dof = k - near.rank
    cspace_singular = constraint_decision.rank < near.rank
    cspace_extra = {}
    if cspace_singular:
        cspace_extra = {"kernel_dimension": int(basis.shape[1]), "tangent_cone_dimension": int(dof),
                        "tangent_cone_span": _secant_span(manifold, point, near.neighbours)}
        notes.append("C-space singularity: actuator and end-effector ranks are computed on ker DΦ(p), "
                     "which is larger than the tangent spaces of M nearby")
    lost = _kernel_beyond(jacobian, constraint_decision.rank, near.rank) if cspace_singular else np.zeros((k, 0))
    cspace = KindResult(cspace_singular, constraint_decision.rank, near.rank, constraint_decision, lost,
                        cspace_extra)

    if survey is None:
        survey = survey_mechanism(model, rng, starts=np.concatenate([model.starts, point[None]]), rtol=rtol)

    # actuator: G = (E^½ T)ᵀ(E^½ T)
    weighted = model.actuators
    actuator_scale = _largest_singular_value(weighted)
    actuator_block = weighted @ basis
    actuator_decision = numerical_rank(actuator_block, rtol=rtol, scale=actuator_scale)
    expected_actuator = min(dof, survey.actuator_rank)
    actuator_singular = actuator_decision.rank < expected_actuator
    idle = max(0, dof - survey.actuator_rank)
    actuator_kernel = basis @ _kernel(actuator_block, actuator_decision.rank)
    actuator = KindResult(actuator_singular, actuator_decision.rank, expected_actuator, actuator_decision,
                          actuator_kernel if actuator_singular else np.zeros((k, 0)),
                          {"on_kernel_of_constraint": True} if cspace_singular else {})

    # end-effector: J = Df T
    end_effector = None
    end_effector_block = None
    n = model.end_effector_dimension
    if n:
        root = metric_root(model.end_effector_metric)
        full = model.end_effector_jacobian(point)
        end_effector_block = full @ basis
        weighted_block = root @ end_effector_block
        decision = numerical_rank(weighted_block, rtol=rtol, scale=_largest_singular_value(root @ full))
        expected = min(n, dof, survey.end_effector_rank)
        singular = decision.rank < expected
        kernel = basis @ _kernel(weighted_block, decision.rank) if singular else np.zeros((k, 0))
        end_effector = KindResult(singular, decision.rank, expected, decision, kernel,
                                  {"on_kernel_of_constraint": True} if cspace_singular else {})

    # manipulability proper values, where G is definite on T_pM
    proper = None
    if n and not cspace_singular and actuator_decision.rank == basis.shape[1] and basis.shape[1] > 0:
        proper = manipulability(actuator_block, end_effector_block,
                                model.end_effector_metric, min(n, dof), rank=end_effector.rank)

    # second order, at regular points of M only
    second = None
    if actuator_singular and cspace_singular:
        notes.append("the second-order test is not run at a C-space singularity: degeneracy undetermined")
    if actuator_singular and not cspace_singular:
        tested, tested_basis = manifold, basis
        if idle:
            tested, _ = idle_slice(manifold, point, basis, near.neighbours, weighted, idle, rtol=rtol)
            if tested is None:
                notes.append("idle freedoms: no neighbour on M to find their directions; "
                             "the second-order test is not run")
            else:
                tested_basis = tangent_basis(tested, point, rtol=rtol)[0]
                notes.append(f"second-order test on a slice of M through p transverse to the {idle} idle "
                             f"freedom(s) (their directions: the limit of ker G at neighbours on M)")
        if tested is not None:
            second = second_order_test(tested, point, tested_basis, weighted, rng, rtol=rtol,
                                       scale=actuator_scale)
    if idle:
        notes.append(f"{idle} idle freedom(s): G has rank at most {survey.actuator_rank} on M")
    moving = min(idle, survey.moving_idle_freedoms)
    if moving:
        notes.append(f"{moving} of the idle freedoms move the end-effector: with the actuators locked the "
                     f"end-effector is not fixed anywhere on M — an architecture singularity, unless the task "
                     f"ignores that motion (e.g. the spin of an axisymmetric tool)")

    return Report(
        mechanism=model.name, dof=dof, ambient_dimension=k, coordinate_names=names,
        displacements={} if model.describe is None else model.describe(point), cspace=cspace, actuator=actuator,
        end_effector=end_effector, manipulability=proper, second_order=second,
        idle_freedoms=idle, survey=survey.to_dict(), notes=tuple(notes), moving_idle_freedoms=moving,
    )


def classify_many(mechanism, points, survey=None, rng=None, **options):
    """Classify a stack of configurations with one shared survey.

    Parameters
    ----------
    mechanism : Mechanism or Model
    points : array_like, shape=[..., point_size]
    survey : Survey, optional
    rng : numpy.random.Generator, optional
    **options
        Passed to :func:`classify`.

    Returns
    -------
    reports : list of Report, in C order of the batch dimensions
    """
    rng = np.random.default_rng(0) if rng is None else rng
    length_scale = options.pop("length_scale", None)
    if not isinstance(mechanism, Mechanism) and length_scale is not None:
        raise ValueError("length_scale applies to a Mechanism; a Model carries its own end-effector metric")
    model = model_of(mechanism, length_scale) if isinstance(mechanism, Mechanism) else mechanism
    points = np.asarray(points, dtype=float)
    flat = points.reshape(-1, points.shape[-1])
    if survey is None:
        survey = survey_mechanism(model, rng, starts=np.concatenate([model.starts, flat]))
    return [classify(model, point, survey=survey, rng=rng, **options) for point in flat]


def _largest_singular_value(matrix):
    """σ₁ of a matrix (0 for an empty one): the reference scale of a restricted map's rank."""
    return float(np.linalg.norm(matrix, 2)) if np.size(matrix) else 0.0


def _kernel_beyond(jacobian, rank, expected):
    """The directions of ker DΦ(p) in excess of the nearby tangent spaces (the weakest rows' partners)."""
    _, _, right = np.linalg.svd(jacobian, full_matrices=True)
    return right[rank:expected].T


def _secant_span(manifold, point, neighbours):
    """Numerical rank of the secants from p to nearby points of M (span of the tangent cone)."""
    if not len(neighbours):
        return 0
    secants = manifold.ambient.inverse_retract(point, neighbours)
    secants = secants / np.linalg.norm(secants, axis=1, keepdims=True)
    return int(numerical_rank(secants, rtol=1e-2).rank)
