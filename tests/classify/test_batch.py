"""A stack of configurations classified at once equals one at a time, item by item (issue 11).

Every catalogue mechanism, at each of its named configurations (the papers'
singular ones among them: Park & Kim 1999, Gosselin & Angeles 1990,
Chablat et al. 2002, Chablat, Wenger & Angeles 1998, Borràs, Thomas & Torras
2011) and at configurations sampled over M with a seeded generator.
"""

import importlib
import json
import tracemalloc
import zlib

import numpy as np
import pytest

from builders import ladder
from classify import KINDS, Model, Survey, classify, model_of
from classify.batch import classify_many
from classify.survey import survey_of
from manifold import AmbientSpace, ImplicitManifold, implicit, sample_manifold, tangent_basis
from mechanisms import ConfigurationError, EndEffector, Joint, Mechanism, catalogue, home

#: the module (``classify.survey`` the attribute is the function it exports)
survey_module = importlib.import_module("classify.survey")
batch_module = importlib.import_module("classify.batch")
metrics_module = importlib.import_module("classify.metrics")


@pytest.fixture(autouse=True)
def fast_paths_on_small_stacks(monkeypatch):
    """The stacks here are small: let them take the fast paths that large stacks take (one-sided Jacobi,
    the certified Gram eigenvalues), so batch = single is checked on the path used at scale."""
    monkeypatch.setattr(metrics_module, "JACOBI_STACK", 1)
    monkeypatch.setattr(batch_module, "JACOBI_STACK", 1)


def _stack(model, seed, walk_count=3):
    """The home and a few configurations of M sampled from it (seeded)."""
    samples = sample_manifold(model.manifold, np.random.default_rng(seed), model.starts, random_count=2,
                              walk_count=walk_count)
    return np.concatenate([model.starts, samples[1:]])


def _assert_equal(result, index, report, model):
    """Row `index` of a batch equals the report of the same configuration."""
    assert result.kinds(index) == report.kinds
    assert result.dof[index] == report.dof
    assert result.idle_freedoms[index] == report.idle_freedoms
    assert result.moving_idle_freedoms[index] == report.moving_idle_freedoms
    kinds = {"actuator": report.actuator, "cspace": report.cspace, "end_effector": report.end_effector}
    for kind in KINDS:
        if kinds[kind] is None:
            assert result.ranks[kind][index] == -1
            continue
        assert result.ranks[kind][index] == kinds[kind].rank, kind
        assert result.expected_ranks[kind][index] == kinds[kind].expected_rank, kind
        kept, dropped = kinds[kind].decision.margin
        expected = [np.nan if kept is None else kept, np.nan if dropped is None else dropped]
        np.testing.assert_allclose(result.margins[kind][index], expected, rtol=1e-9, atol=1e-14)
        np.testing.assert_allclose(result.tolerances[kind][index], kinds[kind].decision.tolerance, rtol=1e-9)
    if report.manipulability is None:
        assert np.isnan(result.eigenvalues[index]).all()
    else:
        values = report.manipulability.eigenvalues
        batched = result.eigenvalues[index, :len(values)]
        kept = report.end_effector.rank  # the λ's beyond J's rank are rounding noise: both below its bound
        np.testing.assert_allclose(batched[:kept], values[:kept], rtol=1e-9, atol=1e-9 * values[0])
        basis = tangent_basis(model.manifold, result.points[index])[0]
        smallest = np.linalg.svd(model.actuators @ basis, compute_uv=False)[-1]
        noise = (report.end_effector.decision.tolerance / smallest) ** 2
        assert np.all(batched[kept:] <= noise) and np.all(values[kept:] <= noise)
        condition = report.manipulability.condition_number
        assert np.isnan(result.condition_number[index]) == (condition is None)
        if condition is not None:
            np.testing.assert_allclose(result.condition_number[index], condition, rtol=1e-9)
    second = report.second_order
    assert result.degenerate[index] == (-1 if second is None else
                                        {"degenerate": 1, "nondegenerate": 0, "undetermined": -1}[second.degeneracy])


CASES = [(entry.name, configuration) for entry in catalogue.entries()
         for configuration in (None, *entry.configurations)]


@pytest.mark.parametrize("name, configuration", CASES, ids=[f"{name}-{configuration}" for name, configuration in CASES])
def test_batch_equals_single_calls_on_the_catalogue(name, configuration):
    """Every catalogue entry at its defaults and at each named configuration, with configurations of M sampled
    from there (seeded by the case's name). A row the batch hands to :func:`classify.classify` (DΦ below the
    survey's rank, an actuator singularity: most named configurations) equals it by construction; the sampled
    rows around it, regular, test the array path close to those singularities."""
    mechanism = catalogue.entry(name).mechanism(configuration)
    model = model_of(mechanism)
    points = _stack(model, seed=zlib.crc32(f"{name}/{configuration}".encode("utf-8")))
    result = classify_many(mechanism, points)
    assert len(result) == len(points) and result.shape == (len(points),)
    for index, point in enumerate(points):
        _assert_equal(result, index, classify(mechanism, point), model)


def test_batch_shape_order_and_chunks():
    mechanism = catalogue.entry("five-bar").mechanism()
    model = model_of(mechanism)
    points = _stack(model, seed=3, walk_count=8)[:6].reshape(2, 3, -1)
    whole = classify_many(model, points)
    pieces = classify_many(model, points, chunk=1)
    assert whole.shape == (2, 3) and len(whole) == 6
    np.testing.assert_array_equal(whole.points, points.reshape(6, -1))
    for name in ("singular", "dof", "degenerate"):
        np.testing.assert_array_equal(getattr(whole, name), getattr(pieces, name))
    np.testing.assert_array_equal(whole.eigenvalues, pieces.eigenvalues)


def test_a_point_off_the_c_space_is_named_by_its_index():
    mechanism = catalogue.entry("five-bar").mechanism()
    points = np.repeat(model_of(mechanism).starts, 3, axis=0)
    points[2, 0] += 0.1
    with pytest.raises(ConfigurationError, match="configuration 2"):
        classify_many(mechanism, points)


@pytest.mark.parametrize("name, configuration", [("five-bar", "fig13_combined"), ("planar-3rrr", None),
                                                   ("gough-stewart", "eq87_parallel_legs")])
def test_threads_over_the_chunks_give_the_same_columns_bit_for_bit(name, configuration):
    """Chunks of three configurations (regular ones and, at a named configuration, singular ones classified one
    at a time) in 1, 2 or every usable thread: every column identical, not merely close."""
    mechanism = catalogue.entry(name).mechanism(configuration)
    model = model_of(mechanism)
    points = _stack(model, seed=12, walk_count=6)
    serial = classify_many(model, points, chunk=3).arrays()
    assert len(points) > 6 and serial["singular"].any() == (configuration is not None)
    for workers in (2, -1):
        threaded = classify_many(model, points, chunk=3, workers=workers).arrays()
        assert threaded.keys() == serial.keys()
        for key, column in serial.items():
            np.testing.assert_array_equal(threaded[key], column, err_msg=f"{key}, workers={workers}")


def test_threads_name_the_first_configuration_off_the_c_space_in_order():
    mechanism = catalogue.entry("five-bar").mechanism()
    points = np.repeat(model_of(mechanism).starts, 20, axis=0)
    points[[7, 15], 0] += 0.1
    with pytest.raises(ConfigurationError, match="configuration 7:"):
        classify_many(mechanism, points, chunk=2, workers=2)


@pytest.mark.parametrize("workers", [0, -2, 1.5, True, "2"])
def test_a_bad_number_of_workers_is_refused_before_the_survey(workers, monkeypatch):
    monkeypatch.setattr(batch_module, "survey_of", lambda *arguments: pytest.fail("survey computed"))
    mechanism = catalogue.entry("five-bar").mechanism()
    with pytest.raises(ValueError, match="workers"):
        classify_many(mechanism, model_of(mechanism).starts, workers=workers)


@pytest.mark.parametrize("name", ["five-bar", "planar-3rrr", "gough-stewart"])
def test_a_default_chunk_holds_the_same_dense_arrays_whatever_the_mechanism(name):
    """DΦ (c × k) and the tangent bases (k × (k − c)) of a chunk, counted as mechanisms.dense_memory_estimate
    counts them, within CHUNK_ENTRIES floats: one configuration more would exceed it."""
    model = model_of(catalogue.entry(name).mechanism())
    rows, size = model.manifold.constraint_jacobian(model.starts[0]).shape
    per_configuration = rows * size + 4 * size * (size - rows)
    chunk = batch_module.default_chunk(model)
    assert per_configuration * chunk <= implicit.CHUNK_ENTRIES < per_configuration * (chunk + 1)


def _serial_arm(joints):
    """A planar serial arm of `joints` actuated R joints (no loop: DΦ has no rows), a pose output."""
    return Mechanism("arm", "planar", [Joint(f"J{index}", "R", ("ground" if index == 0 else f"l{index}",
                                                                  f"l{index + 1}"), point=(float(index), 0.0),
                                             actuated=True) for index in range(joints)],
                     end_effector=EndEffector(f"l{joints}", (float(joints), 0.5), "pose"))


@pytest.mark.parametrize("build, count, bound", [(lambda: ladder(100), 24, 20), (lambda: _serial_arm(6), 40_000, 50)])
def test_the_memory_of_a_stack_is_bounded_by_its_chunks(build, count, bound):
    """A ladder of 100 four-bar loops (DΦ 300 × 400 in 100 blocks of 3 × 4, taken from its entries: 6
    configurations a chunk) and a serial 6R arm (no DΦ, 6 × 6 tangent bases: 7,281 a chunk): in default chunks
    the stack peaks at about 7 and 25 MiB, as one chunk at about 30 and 100 MiB. (A fixed chunk of 4,096
    configurations took some 20 GB on the ladder; chunks sized on DΦ alone put the whole arm's stack in one.)"""
    model = model_of(build())
    survey_of(model)
    points = np.repeat(model.starts[:1], count, axis=0)
    if model.mechanism.loop_count == 0:   # distinct configurations of the arm (any point closes: no loop)
        points = points + 0.3 * np.random.default_rng(0).standard_normal(points.shape)
    peaks = {}
    for chunk in (None, count):
        tracemalloc.start()
        try:
            tracemalloc.reset_peak()
            result = classify_many(model, points, chunk=chunk)
            peaks[chunk] = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        assert len(result) == count
    assert peaks[None] < bound * 2 ** 20 < peaks[count], {chunk: f"{peak / 2 ** 20:.0f} MiB"
                                                           for chunk, peak in peaks.items()}


def test_rows_json_lines_and_arrays_agree():
    mechanism = catalogue.entry("slider-crank").mechanism("fig3a_self_intersection")
    model = model_of(mechanism)
    points = np.concatenate([model.starts, _stack(model, seed=4)])
    result = classify_many(model, points)
    lines = result.json_lines().splitlines()
    assert len(lines) == len(points)
    for index, line in enumerate(lines):
        row = json.loads(line)
        assert row == result.rows()[index]
        assert tuple(row["kinds"]) == result.kinds(index)
        assert row["ranks"]["actuator"] == result.ranks["actuator"][index]
    whole = json.loads(json.dumps(result.to_dict()))
    assert whole["rows"] == result.rows() and whole["shape"] == [len(points)]
    assert whole["survey"] == result.survey.to_dict()
    arrays = result.arrays()
    np.testing.assert_array_equal(arrays["rank_cspace"], result.ranks["cspace"])
    np.testing.assert_array_equal(arrays["singular"], result.singular)
    assert result.kinds(0) == classify(mechanism, points[0]).kinds and result.kinds(0)  # fig. 3a is singular


def test_the_survey_is_computed_once_per_mechanism(monkeypatch):
    calls = []
    original = survey_module.survey

    def counted(*arguments, **options):
        calls.append(1)
        return original(*arguments, **options)

    monkeypatch.setattr(survey_module, "survey", counted)
    mechanism = catalogue.entry("five-bar").mechanism()
    model = model_of(mechanism)
    assert model_of(mechanism) is model
    points = _stack(model, seed=5)
    first = classify(mechanism, points[0])
    classify(mechanism, points[1])
    classify_many(mechanism, points)
    assert len(calls) == 1
    assert first.survey["samples"] == survey_of(model).samples


def test_the_survey_is_raised_to_the_ranks_at_a_point():
    mechanism = catalogue.entry("five-bar").mechanism()
    model = model_of(mechanism)
    point = model.starts[0]
    wrong = Survey(samples=1, constraint_rank=3, actuator_rank=1, end_effector_rank=1, joint_rank=1)
    single = classify(model, point, survey=wrong)
    batch = classify_many(model, point[None], survey=wrong)
    right = classify(model, point)
    assert single.kinds == right.kinds == batch.kinds(0)
    assert single.actuator.expected_rank == right.actuator.expected_rank == batch.expected_ranks["actuator"][0]


def test_survey_dict_round_trip_and_errors():
    survey = survey_of(model_of(catalogue.entry("slider-crank").mechanism()))
    assert Survey.from_dict(json.loads(json.dumps(survey.to_dict()))).to_dict() == survey.to_dict()
    with pytest.raises(ValueError, match="'actuator_rank'"):
        Survey.from_dict({**survey.to_dict(), "actuator_rank": -1})
    with pytest.raises(ValueError, match="'samples'"):
        Survey.from_dict({**survey.to_dict(), "samples": True})


def test_a_classified_mechanism_still_pickles_and_classifies_the_same():
    import copy
    import pickle

    from mechanisms.io import mechanism_to_dict

    mechanism = catalogue.entry("five-bar").mechanism()
    point = model_of(mechanism).starts[0]
    before = classify(mechanism, point).to_dict()
    for other in (pickle.loads(pickle.dumps(mechanism)), copy.deepcopy(mechanism)):
        assert mechanism_to_dict(other) == mechanism_to_dict(mechanism)
        assert model_of(other) is not model_of(mechanism)
        assert classify(other, point).to_dict() == before


def test_closed_form_singular_values_equal_lapack_to_rounding():
    from classify.metrics import singular_values

    rng = np.random.default_rng(8)
    for shape in [(200, 2, 2), (50, 1, 4), (50, 3, 1), (40, 3, 5), (7, 0, 3)]:
        matrices = rng.standard_normal(shape)
        if shape[1:] == (2, 2):
            matrices[:40, 1] = matrices[:40, 0] * rng.standard_normal((40, 1))  # rank one, and
            matrices[40:60] *= 1e-200  # tiny: no underflow of the determinant's scale
        expected = (np.linalg.svd(matrices, compute_uv=False) if min(shape[1:]) else np.zeros(shape[:1] + (0,)))
        values = singular_values(matrices)
        assert values.shape == expected.shape
        scale = np.max(expected, axis=-1, keepdims=True) if expected.size else 1.0
        assert np.all(np.abs(values - expected) <= 4e-15 * scale)


def test_the_closure_tolerance_is_decided_alike_one_at_a_time_and_in_a_stack():
    """Φ's rows norm to 1e-9 (the closure tolerance) as a vector, and to 1e-9 + 1 ulp as a row of a stack
    (different summation orders): classify accepted the configuration, classify_many refused it and with it
    the whole stack (found on a 5-SPU bisected to the tolerance). Both now round the norm alike."""
    rows = np.array([9.858016957364273e-13, 5.280828744662727e-11, -5.301534863258298e-10, 3.685422641280142e-10,
                     2.34647031999913e-10, -3.5436746305184156e-10, -1.6572903616637347e-10, 6.101004438083413e-10])
    count = len(rows) + 1
    ambient = AmbientSpace(("R",) * count)

    def constraint(point):  # M: the line of the last coordinate
        return np.asarray(point, dtype=float)[..., :-1]

    def jacobian(point):
        return np.broadcast_to(np.eye(count)[:-1], np.shape(point)[:-1] + (count - 1, count))

    def hessian(point):
        return np.zeros(np.shape(point)[:-1] + (count - 1, count, count))

    model = Model("line", ImplicitManifold(ambient, constraint, jacobian, hessian), np.eye(count)[-1:],
                  tuple(f"q{index}" for index in range(count)), np.zeros((1, count)))
    for scale in (1.0 - 4e-16, 1.0, 1.0 + 4e-16, 1.0 + 1e-15):
        point = np.append(scale * rows, 0.3)
        try:
            single = classify(model, point).kinds
        except ConfigurationError:
            single = "refused"
        try:
            batch = classify_many(model, point[None]).kinds(0)
        except ConfigurationError:
            batch = "refused"
        assert single == batch, scale


def test_a_rigid_structure_has_the_same_cuts_in_a_stack():
    """A rigid triangle (dof 0) with a crank and an end-effector: its actuator and end-effector blocks have no
    columns. The single call reported the absolute floor 1e-12 as their cuts, the batch rtol times their
    scales (1e-6, 1.4e-6); both now report the cut that would apply, max(rtol · scale, floor)."""
    mechanism = Mechanism("rigid triangle", "planar", [
        Joint("J1", "R", ("ground", "a"), point=(0.0, 0.0), actuated=True),
        Joint("J2", "R", ("a", "b"), point=(3.0, 4.0)),
        Joint("J3", "R", ("b", "ground"), point=(3.0, 0.0))], end_effector=EndEffector("a", (1.0, 1.0), "position"))
    point = home(mechanism)
    single, batch = classify(mechanism, point), classify_many(mechanism, point[None])
    assert single.dof == batch.dof[0] == 0
    for kind in ("actuator", "end_effector"):
        assert batch.tolerances[kind][0] == getattr(single, kind).decision.tolerance > 1e-9


def test_a_gough_stewart_configuration_at_the_closure_tolerance_is_decided_alike_alone_and_in_a_stack():
    """Φ's rows of a Gough–Stewart configuration round differently alone and in a stack (‖Φ‖ = 1e-9 alone,
    1.00000002e-9 beside the home): at the tolerance one call accepted what the other refused, and a refusal
    takes the whole stack (found by a review). The stack now decides such configurations one at a time."""
    mechanism = catalogue.entry("gough-stewart").mechanism()
    model, start = model_of(mechanism), home(mechanism)
    direction = np.random.default_rng(3).standard_normal(start.shape) * 1e-4

    def residual(step):
        return np.linalg.norm(model.manifold.constraint(start + step * direction))

    low, high = 0.0, 1.0
    while residual(high) < 1e-9:
        high *= 2.0
    for _ in range(200):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if residual(middle) <= 1e-9 else (low, middle)
    steps = [low]
    for _ in range(8):
        steps = [np.nextafter(steps[0], 0.0), *steps, np.nextafter(steps[-1], np.inf)]
    for step in steps:
        point = start + step * direction
        try:
            alone = classify(model, point).kinds
        except ConfigurationError:
            alone = "refused"
        try:
            stacked = classify_many(model, np.stack([start, point])).kinds(1)
        except ConfigurationError:
            stacked = "refused"
        assert alone == stacked, step
