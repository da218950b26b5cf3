"""A single classification of a large mechanism decides the actuator rank block by block.

Past BLOCK_THRESHOLD coordinates :func:`classify.classify` takes DΦ block by
block (:func:`manifold.tangent_basis`: each column of the tangent basis on one
block of DΦ's pattern); with actuators that are coordinate rows the actuator
block G = Dπ·T is then block diagonal after permuting its rows and columns,
and its singular values are its blocks'
(:func:`manifold.blocks.labelled_block_singular_values`), the scale of the
unit actuator rows their largest column norm. The reports equal those of the
dense path (BLOCK_THRESHOLD out of reach) on a planar ladder of parallelogram
loops and a stack of spatial RSUR loops.
"""

import numpy as np
import pytest

from builders import ladder, recorded_svd_shapes, rsur_stack
from classify import KINDS, classify, model_of
from classify.survey import survey_of, unit_actuator_rows
from manifold import handled_by_blocks, implicit, sample_manifold
from mechanisms import from_displacements


def _flattened(loop):
    """Displacements of :func:`builders.ladder` that lay loop `loop`'s links along its rungs (links of
    direction (tᵢ, 1), tᵢ = 0.1 + 0.3 sin i, turned by −atan2(1, tᵢ)): its block of DΦ drops to rank 2."""
    angle = -np.arctan2(1.0, 0.1 + 0.3 * np.sin(loop))
    return {f"A{loop}": angle, f"B{loop}": -angle, f"C{loop}": angle, f"D{loop}": -angle}


def _points(mechanism, model, flattened):
    """Points of M walked from the model's start, and (`flattened`) a C-space singularity of a ladder."""
    points = sample_manifold(model.manifold, np.random.default_rng(3), model.starts, random_count=0, walk_count=2)
    if flattened:
        points = np.concatenate([points, [from_displacements(mechanism, _flattened(3))]])
    return points


def _assert_same(report, expected):
    """Kinds, ranks and their cuts, margins (1e-9 relative) and proper values of two reports."""
    assert report.kinds == expected.kinds and report.dof == expected.dof
    assert report.idle_freedoms == expected.idle_freedoms
    for kind in KINDS:
        found, wanted = getattr(report, kind), getattr(expected, kind)
        assert (found.rank, found.expected_rank) == (wanted.rank, wanted.expected_rank), kind
        np.testing.assert_allclose(found.decision.tolerance, wanted.decision.tolerance, rtol=1e-9, err_msg=kind)
        for value, other in zip(found.decision.margin, wanted.decision.margin):
            assert (value is None) == (other is None), kind
            if value is not None:
                np.testing.assert_allclose(value, other, rtol=1e-9, atol=1e-14, err_msg=kind)
    if expected.manipulability is not None:
        np.testing.assert_allclose(report.manipulability.eigenvalues, expected.manipulability.eigenvalues, rtol=1e-9)


@pytest.mark.parametrize("build, flattened", [(lambda: ladder(17, 2), True), (lambda: rsur_stack(12), False)],
                         ids=["ladder k=70", "rsur k=84"])
def test_a_single_call_block_by_block_equals_the_dense_one(monkeypatch, build, flattened):
    """Each configuration (walked on M; on the ladder a flat loop too, where G is taken on ker DΦ) classified
    block by block and with the block path out of reach (a model of its own: σ₁ of the unit actuator rows and
    G's SVD dense): the same kinds, ranks, cuts, margins and proper values. The ladder's dense model takes its
    own survey (dense), of the same ranks; the stack's is given the block one's (a dense survey of the stack
    projects whole and takes a minute: tests/classify/test_survey_large.py)."""
    mechanism = build()
    model = model_of(mechanism)
    assert handled_by_blocks(model.manifold)
    points = _points(mechanism, model, flattened)
    reports = [classify(model, point) for point in points]
    monkeypatch.setattr(implicit, "BLOCK_THRESHOLD", 10 ** 9)
    dense_model = model_of(build())
    assert not handled_by_blocks(dense_model.manifold)
    np.testing.assert_allclose(unit_actuator_rows(model)[1], unit_actuator_rows(dense_model)[1], rtol=1e-14)
    survey = survey_of(model)
    if flattened:
        dense_survey = survey_of(dense_model)
        assert (dense_survey.constraint_rank, dense_survey.actuator_rank, dense_survey.end_effector_rank,
                dense_survey.joint_rank) == (survey.constraint_rank, survey.actuator_rank, survey.end_effector_rank,
                                             survey.joint_rank)
    for point, report in zip(points, reports):
        _assert_same(report, classify(dense_model, point, survey=None if flattened else survey))
    assert not flattened or reports[-1].kinds == ("cspace",)


def test_a_single_call_takes_no_svd_of_the_actuator_block(monkeypatch):
    """At k = 400 (a ladder of 99 loops and 4 tail joints: G is 103 × 103 at a regular point) a single call
    after the survey decomposes nothing with both sides longer than 8: G by its 1 × 1 blocks, and the stacked
    map of the idle-freedom decision not at all (the survey's joint rank is already min(a + n, m))."""
    mechanism = ladder(99, 4)
    model = model_of(mechanism)
    assert model.manifold.ambient.dim == 400
    survey_of(model)
    point = _points(mechanism, model, False)[-1]
    calls = recorded_svd_shapes(monkeypatch)
    report = classify(model, point)
    monkeypatch.undo()
    assert not report.kinds and report.actuator.rank == 103
    assert not [shape for shape in calls if min(shape[-2:]) > 8], sorted(set(calls))
