"""A large mechanism's batch takes DΦ from its entries at the pattern, never as the dense c × k matrices.

On the block path (:func:`manifold.handled_by_blocks`) :func:`classify.classify_many` gets Φ, the
half-turn test and DΦ's entries from one expansion of each loop (:func:`mechanisms.closure_and_entries`),
decomposes the blocks taken from the entries (:func:`manifold.blocks.decompose`) and sizes its
chunks by those entries rather than by c × k (:func:`classify.batch.default_chunk`); it still equals the
single calls item by item. The mechanisms are planar ladders (:func:`builders.ladder`) and spatial stacks
of RSUR loops (:func:`builders.rsur_stack`).
"""

import dataclasses
import tracemalloc

import numpy as np
import pytest

from builders import ladder, rsur_stack, shared_mechanism
from classify import classify, model_of
from classify import batch as batch_module
from classify.batch import classify_many, default_chunk
from classify.survey import survey_of
from manifold import handled_by_blocks, implicit, project_many
from manifold.blocks import JacobianPattern, decompose
from mechanisms import closure_and_entries, closure_and_jacobian, constraint_pattern, home
from mechanisms.mechanism import dense_memory_estimate
from test_batch_large import _assert_equal, _configurations


@pytest.mark.parametrize("mechanism", [ladder(3, 1), rsur_stack(2)], ids=["planar", "spatial"])
def test_closure_and_entries_are_closure_and_jacobian_without_the_dense_matrices(mechanism):
    """Φ, the half-turn test and DΦ's entries of a stack: the entries at the pattern are closure_and_jacobian's
    DΦ, to the bit, and Φ and the test are its own."""
    rng = np.random.default_rng(3)
    start = home(mechanism)
    points = np.stack([start, start + 0.01 * rng.standard_normal(start.shape)])
    rows, turns, entries = closure_and_entries(mechanism, points)
    dense_rows, dense_turns, jacobian = closure_and_jacobian(mechanism, points)
    pattern = constraint_pattern(mechanism)
    assert entries.shape == (2, pattern.nnz)
    np.testing.assert_array_equal(pattern.dense(entries), jacobian)
    np.testing.assert_array_equal(rows, dense_rows)
    np.testing.assert_array_equal(turns, dense_turns)


def test_the_blocks_from_the_entries_are_the_single_calls():
    """The chunk's decomposition from DΦ's entries is manifold.blocks.decompose's of each configuration, values and
    vectors to the bit (a flat loop and a nearly flat one among them)."""
    mechanism = shared_mechanism(ladder(17, 2))
    model = model_of(mechanism)
    points = _configurations(mechanism, model, seed=11, count=3)
    entries = batch_module._closure_and_jacobian(model, points[:-1], 0, entries=True)
    entries = np.concatenate([entries, model.manifold.constraint_jacobian_entries(points[-1:])])  # flat: closes
    decomposition = decompose(model.manifold, entries=entries)
    for index, point in enumerate(points):
        for (group, values, right), (stacked_group, stacked_values, stacked_right) in zip(
                decompose(model.manifold, point), decomposition):
            assert stacked_group is group
            np.testing.assert_array_equal(stacked_values[index], values)
            np.testing.assert_array_equal(stacked_right[index], right)


def _spy_on_dense(monkeypatch):
    """Record the shape of every matrix JacobianPattern.dense forms (how DΦ's entries become c × k matrices)."""
    shapes = []
    original = JacobianPattern.dense

    def dense(pattern, entries):
        matrices = original(pattern, entries)
        shapes.append(matrices.shape)
        return matrices

    monkeypatch.setattr(JacobianPattern, "dense", dense)
    return shapes


@pytest.mark.parametrize("manifold_only", [False, True], ids=["mechanism", "manifold"])
def test_the_block_path_forms_no_dense_jacobian_and_equals_single_calls(monkeypatch, manifold_only):
    """classify_many of regular configurations of a ladder past the threshold (a loop nearly flat among them)
    forms no [..., c, k] DΦ, for a joint-graph mechanism's model and for a model of its manifold alone (DΦ's
    entries from ``constraint_jacobian_entries``), and equals the single calls item by item."""
    mechanism = shared_mechanism(ladder(25, 3))
    model = model_of(mechanism)
    if manifold_only:
        model = dataclasses.replace(model, mechanism=None)  # a new cache too
    assert handled_by_blocks(model.manifold)
    points = _configurations(mechanism, model, seed=5, count=4)[:-1]  # regular: no single call
    survey_of(model)  # the survey's own decompositions are dense
    shapes = _spy_on_dense(monkeypatch)
    result = classify_many(model, points)
    monkeypatch.undo()
    dense = model.manifold.pattern.shape
    assert not result._reports and not [shape for shape in shapes if shape[-2:] == dense], shapes
    for index, point in enumerate(points):
        _assert_equal(result, index, classify(model, point))


def test_a_flat_loop_in_a_chunk_of_the_block_path_is_classified_as_a_single_call():
    """A C-space singular configuration (a loop flat) among regular ones, in the default chunk of the block path:
    each row equals the single call's."""
    mechanism = shared_mechanism(ladder(17, 2))
    model = model_of(mechanism)
    points = _configurations(mechanism, model, seed=13, count=5)
    assert default_chunk(model) >= len(points)  # one chunk
    result = classify_many(model, points)
    assert result.kinds(len(points) - 1) == ("cspace",)
    for index, point in enumerate(points):
        _assert_equal(result, index, classify(model, point))


def test_the_block_paths_chunk_counts_dphis_entries_and_stays_within_its_memory():
    """On the block path a configuration counts the four tangent bases and DΦ's blocks, not c × k: a ladder of
    100 loops (k = 400, c = 300) gets 6 configurations a chunk (3 by c × k), and classifying two chunks' worth
    allocates at most twice the chunk's memory (CHUNK_ENTRIES floats)."""
    mechanism = shared_mechanism(ladder(100))
    model = model_of(mechanism)
    coordinates, rows = model.manifold.ambient.dim, model.constraint_rows
    pattern = model.manifold.pattern
    blocks = 100 * (3 * 4 + 3 + 4 * 4)  # one 3 × 4 block a loop: its matrix, values and Vᴴ
    assert [group.positions.shape for group in pattern.blocks] == [(100, 3, 4)]
    per_configuration = 4 * coordinates * (coordinates - rows) + 2 * pattern.nnz + blocks
    assert default_chunk(model) == implicit.CHUNK_ENTRIES // per_configuration == 6
    assert implicit.CHUNK_ENTRIES // (dense_memory_estimate(coordinates, rows) // 8) == 3
    points = np.repeat(home(mechanism)[None], 2 * default_chunk(model), axis=0)
    survey_of(model)
    classify_many(model, points[:1])
    tracemalloc.start()
    try:
        classify_many(model, points)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= 2 * 8 * implicit.CHUNK_ENTRIES, peak


def test_a_spatial_stack_on_the_block_path_equals_single_calls():
    """Ten RSUR loops (k = 70, DΦ's blocks 6 × 7 from the spatial loops' entries): configurations near the home,
    projected on M, classified in a batch equal the single calls."""
    mechanism = shared_mechanism(rsur_stack(10))
    model = model_of(mechanism)
    assert handled_by_blocks(model.manifold)
    ambient = model.manifold.ambient
    moved = ambient.retract(np.broadcast_to(home(mechanism), (4, ambient.point_size)),
                            0.05 * np.random.default_rng(1).standard_normal((4, ambient.dim)) * ambient.tangent_scales)
    points, converged = project_many(model.manifold, moved)
    points = points[np.asarray(converged, dtype=bool)]
    assert len(points) >= 3
    result = classify_many(model, points)
    for index, point in enumerate(points):
        _assert_equal(result, index, classify(model, point))
