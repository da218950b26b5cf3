"""The batched classification of a large mechanism works block by block, as a single call does.

:func:`classify.classify` takes the rank of DΦ·diag(s) and the tangent basis
block by block once the manifold has a pattern and k ≥ BLOCK_THRESHOLD
(:func:`manifold.tangent_basis`); :func:`classify.classify_many` does the same
over a whole chunk (one batched SVD per shape of block, the blocks taken from
DΦ's entries), so it neither forms nor decomposes the dense c × k DΦ nor forms
a k × k orthogonal factor, and it equals the single calls item by item. The mechanisms are planar ladders of
parallelogram loops (:func:`builders.ladder`: one 3 × 4 block of DΦ per loop),
whose loops own more columns than rows (no block-arrow form).
"""

import numpy as np
import pytest

from builders import ladder, recorded_svd_shapes, shared_mechanism
from classify import KINDS, classify, model_of
from classify import batch as batch_module
from classify.batch import classify_many
from manifold import handled_by_blocks, sample_manifold, tangent_basis
from classify.survey import model_coordinate_rows, rows_on, survey_of
from manifold.blocks import decompose, labelled_block_singular_values
from mechanisms import from_displacements


def _tilt(index):
    """tᵢ of loop i of :func:`builders.ladder`: its links have direction (tᵢ, 1)."""
    return 0.1 + 0.3 * np.sin(index)


def _loop_turned(loop, angle):
    """Displacements that turn loop `loop`'s two links by `angle` and keep the rungs above it level (a
    parallelogram's motion: A and C by `angle`, B and D back by −`angle`)."""
    return {f"A{loop}": angle, f"B{loop}": -angle, f"C{loop}": angle, f"D{loop}": -angle}


def _flattened(loop):
    """Displacements that lay loop `loop`'s links along its rungs: the loop folds flat, its block of DΦ drops
    to rank 2 (a C-space singularity)."""
    return _loop_turned(loop, -np.arctan2(1.0, _tilt(loop)))


def _configurations(mechanism, model, seed, count):
    """Configurations of M: the home walked on M, every loop turned at random, a loop nearly flat (a regular
    point whose block is ill-conditioned), and a loop flat (singular)."""
    rng = np.random.default_rng(seed)
    loops = sum(1 for joint in mechanism.joints if joint.name.startswith("A"))
    tail = [joint.name for joint in mechanism.joints if joint.name.startswith("T")]
    walked = sample_manifold(model.manifold, rng, model.starts, random_count=0, walk_count=3)
    turned = []
    for _ in range(count):
        displacements = {name: float(rng.uniform(-0.5, 0.5)) for name in tail}
        for loop in range(1, loops + 1):
            displacements.update(_loop_turned(loop, float(rng.uniform(-0.4, 0.4))))
        turned.append(from_displacements(mechanism, displacements))
    nearly_flat = {**_loop_turned(2, -np.arctan2(1.0, _tilt(2)) * (1 - 1e-3)), "A5": 0.1, "B5": -0.1,
                   "C5": 0.1, "D5": -0.1}
    singular = {**_flattened(3), **_loop_turned(1, 0.2)}
    return np.concatenate([walked, turned, [from_displacements(mechanism, nearly_flat),
                                            from_displacements(mechanism, singular)]])


def _assert_equal(result, index, report):
    """Row `index` of a batch equals the report of the same configuration: kinds, ranks, margins, cuts, λ's."""
    assert result.kinds(index) == report.kinds
    assert result.dof[index] == report.dof
    assert result.idle_freedoms[index] == report.idle_freedoms
    for kind in KINDS:
        expected = getattr(report, kind)
        assert result.ranks[kind][index] == expected.rank, kind
        assert result.expected_ranks[kind][index] == expected.expected_rank, kind
        kept, dropped = expected.decision.margin
        margin = [np.nan if kept is None else kept, np.nan if dropped is None else dropped]
        np.testing.assert_allclose(result.margins[kind][index], margin, rtol=1e-9, atol=1e-14, err_msg=kind)
        np.testing.assert_allclose(result.tolerances[kind][index], expected.decision.tolerance, rtol=1e-9)
    if report.manipulability is None:
        assert np.isnan(result.eigenvalues[index]).all()
        return
    values = report.manipulability.eigenvalues
    np.testing.assert_allclose(result.eigenvalues[index, :len(values)], values, rtol=1e-9)
    np.testing.assert_allclose(result.condition_number[index], report.manipulability.condition_number, rtol=1e-9)


@pytest.mark.parametrize("loops, tail", [(17, 2), (50, 3)], ids=["k=70", "k=203"])
def test_a_large_ladder_in_a_batch_equals_single_calls(loops, tail):
    """Just above BLOCK_THRESHOLD and at k ≈ 200, in chunks of 4: walked and randomly turned configurations, a
    loop nearly flat (κ of its block ≈ 1e3) and a loop flat (a C-space singularity, left to classify)."""
    mechanism = shared_mechanism(ladder(loops, tail))
    model = model_of(mechanism)
    assert handled_by_blocks(model.manifold) and batch_module._arrow_structure(model) is None
    points = _configurations(mechanism, model, seed=loops, count=6)
    result = classify_many(model, points, chunk=4)
    reports = [classify(model, point) for point in points]
    assert reports[-1].kinds == ("cspace",) and reports[-1].cspace.rank == model.constraint_rows - 1
    assert not any(report.kinds for report in reports[:-1])
    for index, report in enumerate(reports):
        _assert_equal(result, index, report)


def test_the_kernel_bases_are_the_single_calls_block_by_block():
    """Two configurations of one rank whose rank-deficient blocks differ (loop 1 flat in one, loop 2 in the
    other): each basis is the single call's tangent basis, column for column."""
    mechanism = shared_mechanism(ladder(17, 2))
    model = model_of(mechanism)
    manifold = model.manifold
    points = np.stack([from_displacements(mechanism, _flattened(1)), from_displacements(mechanism, _flattened(2)),
                       from_displacements(mechanism, {**_loop_turned(4, 0.3), "T1": 0.2})])
    decomposition = decompose(manifold, entries=manifold.constraint_jacobian_entries(points))
    values, tolerance = batch_module._block_constraint_values(decomposition, (len(points),) + manifold.pattern.shape,
                                                              1e-6)
    expected = [tangent_basis(manifold, point) for point in points]
    for index, (basis, decision) in enumerate(expected):
        np.testing.assert_array_equal(values[index], decision.singular_values)
        assert tolerance[index] == decision.tolerance
    for selection in ([0, 1], [2]):
        rank = expected[selection[0]][1].rank
        bases = batch_module._block_kernel_bases(decomposition, np.array(selection), tolerance[selection], manifold,
                                                 rank)
        for basis, index in zip(bases, selection):
            np.testing.assert_allclose(manifold.ambient.tangent_scales[:, None] * basis, expected[index][0],
                                       atol=1e-15)


def test_the_batch_decomposes_no_matrix_as_large_as_dphi(monkeypatch):
    """No SVD, QR or symmetric eigenproblem of the batch's has a side as long as DΦ's c rows (or its k
    columns): the blocks (3 × 4), the actuator and end-effector blocks on the tangent spaces (a few × m)."""
    mechanism = shared_mechanism(ladder(25, 3))
    model = model_of(mechanism)
    survey_of(model)
    points = _configurations(mechanism, model, seed=5, count=4)[:-1]  # regular: no single call
    calls = []
    for name in ("svd", "qr", "eigvalsh", "eigh"):
        original = getattr(np.linalg, name)
        monkeypatch.setattr(np.linalg, name, lambda matrix, *arguments, _original=original, **options:
                            calls.append(np.shape(matrix)) or _original(matrix, *arguments, **options))
    result = classify_many(model, points)
    monkeypatch.undo()
    assert not result.singular.any() and not result._reports
    rows, columns = model.constraint_rows, model.manifold.ambient.dim
    assert calls and max(max(shape[-2:]) for shape in calls) < rows < columns, sorted(set(calls))
    assert (len(points), 25, 3, 4) in calls  # the loops' blocks of every configuration, in one call


def test_a_stack_decomposes_block_by_block_as_its_configurations_one_by_one():
    """manifold.blocks.decompose of a stack of configurations [2, 3, point_size] (DΦ from its entries) and of
    the stack's dense DΦ·diag(s) (as classify_many has it): each configuration's blocks, values and vectors,
    are the single configuration's, to the bit (a flat loop and a nearly flat one among them)."""
    mechanism = shared_mechanism(ladder(17, 2))
    model = model_of(mechanism)
    manifold = model.manifold
    points = _configurations(mechanism, model, seed=7, count=4)[-6:].reshape(2, 3, -1)
    jacobian = manifold.constraint_jacobian(points) * manifold.ambient.tangent_scales
    from_entries, from_jacobian = decompose(manifold, points), decompose(manifold, jacobian=jacobian)
    assert [values.shape[:2] for _, values, _ in from_entries] == [(2, 3)] * len(manifold.pattern.blocks)
    for index in np.ndindex(2, 3):
        single = decompose(manifold, points[index])
        for stacked in (from_entries, from_jacobian):
            for (group, values, right), (stacked_group, stacked_values, stacked_right) in zip(single, stacked):
                assert stacked_group is group
                np.testing.assert_array_equal(stacked_values[index], values)
                np.testing.assert_array_equal(stacked_right[index], right)


def test_the_actuator_rows_on_the_tangent_bases_are_decomposed_block_by_block(monkeypatch):
    """On a ladder the actuators are coordinate rows: picked from the bases they are the product Dπ·T to the bit,
    and G = Dπ·T is block diagonal (one 1 × 1 block per loop, one per actuated joint of the tail), whose values
    are the dense SVD's to 1e-12 of σ₁; classify_many takes no SVD of G (only of DΦ's blocks, 3 × 4, and of
    the end-effector's 2 rows) and equals the single calls."""
    mechanism = shared_mechanism(ladder(25, 3))
    model = model_of(mechanism)
    manifold = model.manifold
    points = _configurations(mechanism, model, seed=5, count=4)[:-1]  # regular
    decomposition = decompose(manifold, entries=manifold.constraint_jacobian_entries(points))
    _, tolerance = batch_module._block_constraint_values(decomposition, (len(points),) + manifold.pattern.shape, 1e-6)
    rank = model.constraint_rows
    bases = manifold.ambient.tangent_scales[:, None] * batch_module._block_kernel_bases(
        decomposition, np.arange(len(points)), tolerance, manifold, rank)
    unit_actuators, _ = batch_module.unit_actuator_rows(model)
    for matrix, name in ((unit_actuators, "unit_actuator_rows"), (model.actuators, "actuators")):
        assert model_coordinate_rows(model, name, matrix) is not None
        np.testing.assert_array_equal(rows_on(model, name, matrix, bases), matrix @ bases)
    columns, _ = model_coordinate_rows(model, "unit_actuator_rows", unit_actuators)
    components = manifold.pattern.column_components
    block = unit_actuators @ bases
    values = labelled_block_singular_values(block, components[columns], components[np.argmax(bases != 0.0, axis=-2)])
    dense = np.linalg.svd(block, compute_uv=False)
    assert np.all(np.abs(values - dense) <= 1e-12 * dense[:, :1])
    survey_of(model)  # the survey's own decompositions are dense
    calls = recorded_svd_shapes(monkeypatch)
    result = classify_many(model, points)
    monkeypatch.undo()
    assert calls and max(min(shape[-2:]) for shape in calls) <= 3, sorted(set(calls))
    for index, point in enumerate(points):
        _assert_equal(result, index, classify(model, point))
