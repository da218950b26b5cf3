"""Speed of the classification: cold, warm, batched and one-at-a-time, in the same run.

Run from the repository root::

    .venv/bin/python benchmarks/speed.py            # full run (under a minute on 2 cores)
    .venv/bin/python benchmarks/speed.py --quick    # smaller stacks, fewer repeats (under 30 s)
    .venv/bin/python benchmarks/speed.py --profile five-bar   # where the batched path spends its time

For each mechanism of :data:`MECHANISMS` (catalogue entries, built with the
paper's defaults) it measures, in one process:

* **cold** ``classify(mechanism, home)`` on a mechanism object built just
  before (a new model: its survey of M is computed inside the call); the
  modules are already imported (one cold call on another object comes first);
* **survey**: the survey of M alone, on another new mechanism object;
* **warm** ``classify(model, point)`` at a regular configuration, the survey
  cached on the model: median over repeats;
* **batched** ``classify_many(model, points)`` on a stack of distinct regular
  configurations of M (see :func:`walked_configurations`): configurations/s,
  median over repeats;
* **every core** ``classify_many(model, points, workers=-1)``: the same stack,
  its chunks (:func:`classify.batch.default_chunk`) in threads on every usable
  core (:mod:`classify.threads`); configurations/s, and whether every column
  equals the one-thread result exactly;
* **loop** ``[classify(model, point) for point in points[:N]]`` on the first N
  of the same configurations: configurations/s, and the ratio batched ÷ loop;
* **reference**: ``numpy.linalg.svd(DΦ, compute_uv=False)`` of the same stack
  of constraint Jacobians (``mechanisms.constraint_jacobian``), matrices/s
  (and the full SVD with U and V, the generic way to tangent bases).

It prints a Markdown table and writes JSON (``--out``, default
``benchmarks/results/speed.json``, ``speed_quick.json`` with ``--quick``).
Nothing is asserted: speed is reported.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import os
import platform
import pstats
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from manifold import sample_manifold, scaled_jacobian  # noqa: E402
from mechanisms import catalogue, constraint_jacobian, home  # noqa: E402

from classify import classify, classify_many, model_of, survey_of  # noqa: E402
from classify.batch import default_chunk  # noqa: E402
from classify.threads import thread_count  # noqa: E402

#: seed of the walks that make the stacks of configurations
SEED = 11


@dataclass(frozen=True)
class Settings:
    """Sizes of one mechanism's measurements.

    Attributes
    ----------
    name : str
        Catalogue entry.
    batch : int
        Configurations in the batched stack (full run).
    loop : int
        Configurations classified one at a time (full run).
    quick_batch, quick_loop : int
        The same with ``--quick``.
    """

    name: str
    batch: int
    loop: int
    quick_batch: int
    quick_loop: int


#: the mechanisms of issue 11, with stack sizes that keep each under about 20 s
MECHANISMS = (
    Settings("five-bar", 20_000, 300, 4_000, 60),
    Settings("slider-crank", 20_000, 300, 4_000, 60),
    Settings("planar-3rrr", 10_000, 200, 2_000, 40),
    Settings("spherical-3rrr", 10_000, 200, 2_000, 40),
    Settings("gough-stewart", 2_000, 60, 400, 15),
)


# --------------------------------------------------------------------------- the machine

def machine():
    """Platform, CPU, cores, Python, NumPy and its BLAS, thread settings: a dict for the JSON."""
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        cpu = platform.processor() or "unknown"
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {
        "platform": platform.platform(),
        "cpu": cpu,
        "cores": os.cpu_count(),
        "usable_cores": usable,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "blas": _blas()[0],
        "blas_details": _blas()[1],
        "thread_settings": {name: os.environ[name] for name in
                            ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS") if name in os.environ},
    }


def _blas():
    """The BLAS NumPy runs on, ``(name and version, details)``: threadpoolctl's view if installed, else
    NumPy's build configuration."""
    try:
        from threadpoolctl import threadpool_info
    except ImportError:
        threadpool_info = None
    if threadpool_info is not None:
        pools = [pool for pool in threadpool_info() if pool.get("user_api") == "blas"]
        if pools:
            pool = pools[0]
            return (f"{pool.get('internal_api')} {pool.get('version')}",
                    f"{pool.get('architecture')}, {pool.get('num_threads')} threads")
    try:
        blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    except (TypeError, KeyError, AttributeError):
        return "unknown", ""
    return f"{blas.get('name')} {blas.get('version')}", " ".join(blas.get("openblas configuration", "").split())


# --------------------------------------------------------------------------- configurations

def project_stack(manifold, points, tolerance=1e-12, iterations=30, max_step=None):
    """Gauss–Newton projection of a stack of points onto M, all at once.

    The step of :func:`manifold.project` (least dimensionless length,
    ``p ← p ⊕ (−s·(DΦ(p)·s)⁺ Φ(p))``), with batched pseudo-inverses.

    Parameters
    ----------
    manifold : ImplicitManifold
    points : ndarray, shape=[n, point_size]
    tolerance : float
        Converged where ``|Φ| ≤ tolerance``.
    iterations : int
    max_step : float, optional
        Largest norm of one step.

    Returns
    -------
    projected : ndarray, shape=[n, point_size]
    converged : ndarray of bool, shape=[n]
        Where ``|Φ| ≤ tolerance`` and ``manifold.is_solution`` holds.
    """
    ambient = manifold.ambient
    scales = ambient.tangent_scales
    points = np.array(points, dtype=float)
    values = manifold.constraint(points)
    for _ in range(iterations):
        active = np.flatnonzero(np.linalg.norm(values, axis=-1) > tolerance)
        if not len(active):
            break
        inverse = np.linalg.pinv(scaled_jacobian(manifold, points[active]), rcond=1e-12)
        step = -scales * (inverse @ values[active][..., None])[..., 0]
        if max_step is not None:
            norms = np.linalg.norm(step, axis=-1, keepdims=True)
            step *= np.minimum(1.0, max_step / np.maximum(norms, 1e-300))
        points[active] = ambient.retract(points[active], step)
        values[active] = manifold.constraint(points[active])
    converged = np.linalg.norm(values, axis=-1) <= tolerance
    if manifold.is_solution is not None and converged.any() and not manifold.is_solution(points[converged]):
        converged &= np.array([ok and bool(manifold.is_solution(point)) for point, ok in zip(points, converged)])
    return points, converged


def walked_configurations(model, count, rng, walkers=500, step=0.05):
    """Distinct configurations of M, from random walks started on every assembly branch the survey sampling finds.

    The starts are :func:`manifold.sample_manifold` points of M (random
    points of K projected, and a walk from the home). ``walkers`` copies of
    them then walk together: each step moves along a random unit direction of
    T_pM (dimensionless, length `step`) and projects back onto M
    (:func:`project_stack`); a walker whose step fails stays put. Every
    accepted position is a new configuration (none is a copy of another).

    Parameters
    ----------
    model : Model
    count : int
    rng : numpy.random.Generator
    walkers : int
    step : float
        Dimensionless step length.

    Returns
    -------
    points : ndarray, shape=[count, point_size]
    """
    manifold = model.manifold
    scales = manifold.ambient.tangent_scales
    constraint_rank = survey_of(model).constraint_rank
    starts = sample_manifold(manifold, rng, model.starts, random_count=24, walk_count=8)
    current = starts[rng.integers(len(starts), size=min(walkers, count))]
    found, total = [], 0
    while total < count:
        _, _, right = np.linalg.svd(scaled_jacobian(manifold, current), full_matrices=True)
        tangent = np.swapaxes(right[:, constraint_rank:, :], -1, -2)  # [w, k, m], orthonormal in u = v / s
        direction = (tangent @ rng.standard_normal(tangent.shape[::2])[..., None])[..., 0]
        direction /= np.maximum(np.linalg.norm(direction, axis=-1, keepdims=True), 1e-300)
        moved = manifold.ambient.retract(current, step * scales * direction)
        moved, converged = project_stack(manifold, moved, max_step=step * scales.max())
        current[converged] = moved[converged]
        found.append(moved[converged])
        total += int(converged.sum())
    return np.concatenate(found)[:count]


def regular_configurations(model, count, rng):
    """`count` walked configurations where no kind is singular (so the batch takes its array path).

    Returns
    -------
    points : ndarray, shape=[count, point_size]
    seconds : float
        Time spent making them (walks and the screening classification).
    """
    started = time.perf_counter()
    kept = np.zeros((0, model.manifold.ambient.point_size))
    for _ in range(5):
        if len(kept) >= count:
            break
        candidates = walked_configurations(model, int(1.2 * (count - len(kept))) + 10, rng)
        result = classify_many(model, candidates)
        kept = np.concatenate([kept, candidates[~result.singular.any(axis=1)]])
    if len(kept) < count:
        raise RuntimeError(f"{model.name}: only {len(kept)} of {count} walked configurations are regular")
    points = kept[:count]
    return points, time.perf_counter() - started


# --------------------------------------------------------------------------- timing

def timed(function, repeats, warmups=1):
    """Median and all wall times (s) of `repeats` calls of `function` after `warmups` discarded calls."""
    for _ in range(warmups):
        function()
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        function()
        times.append(time.perf_counter() - started)
    return statistics.median(times), times


def cold_classify(name, repeats):
    """Median seconds of ``classify(new mechanism, its home)`` (the survey inside), and of the survey alone."""
    entry = catalogue.entry(name)
    classify(entry.mechanism(), home(entry.mechanism()))  # imports and first-use caches, discarded
    cold, survey_times = [], []
    for _ in range(repeats):
        mechanism = entry.mechanism()
        point = home(mechanism)
        started = time.perf_counter()
        classify(mechanism, point)
        cold.append(time.perf_counter() - started)
        model = model_of(entry.mechanism())
        started = time.perf_counter()
        survey_of(model)
        survey_times.append(time.perf_counter() - started)
    return statistics.median(cold), statistics.median(survey_times)


def measure(settings, quick, rng):
    """Every measurement of one mechanism, as a dict (times in seconds, rates in configurations/s)."""
    batch_count = settings.quick_batch if quick else settings.batch
    loop_count = settings.quick_loop if quick else settings.loop
    repeats = 2 if quick else 5
    cold, survey_seconds = cold_classify(settings.name, 2 if quick else 3)

    mechanism = catalogue.entry(settings.name).mechanism()
    model = model_of(mechanism)
    survey_of(model)
    points, making = regular_configurations(model, batch_count, rng)

    warm, warm_times = timed(lambda: classify(model, points[0]), repeats=7 if quick else 21, warmups=2)
    batched, batched_times = timed(lambda: classify_many(model, points), repeats=repeats)
    threaded, _ = timed(lambda: classify_many(model, points, workers=-1), repeats=repeats)
    chunk = default_chunk(model)
    threads = thread_count(-1, -(-batch_count // chunk))
    one_thread, every_core = classify_many(model, points).arrays(), classify_many(model, points, workers=-1).arrays()
    threads_agree = all(np.array_equal(every_core[key], column, equal_nan=column.dtype.kind == "f")
                        for key, column in one_thread.items())
    loop_points = points[:loop_count]
    loop, _ = timed(lambda: [classify(model, point) for point in loop_points], repeats=1 if quick else 3)

    # the batch equals the loop on the configurations both classified
    result = classify_many(model, loop_points)
    reports = [classify(model, point) for point in loop_points]
    agree = all(result.kinds(index) == report.kinds and result.ranks["actuator"][index] == report.actuator.rank
                for index, report in enumerate(reports))

    jacobians = constraint_jacobian(mechanism, points)
    svd_values, _ = timed(lambda: np.linalg.svd(jacobians, compute_uv=False), repeats=repeats)
    svd_full, _ = timed(lambda: np.linalg.svd(jacobians, full_matrices=True), repeats=repeats)

    batched_rate = batch_count / batched
    loop_rate = loop_count / loop
    return {
        "mechanism": settings.name,
        "joints": len(mechanism.joints),
        "point_size": int(points.shape[1]),
        "jacobian_shape": list(jacobians.shape[1:]),
        "cold_classify_ms": 1e3 * cold,
        "survey_ms": 1e3 * survey_seconds,
        "warm_classify_ms": 1e3 * warm,
        "warm_classify_best_ms": 1e3 * min(warm_times),
        "batch_count": batch_count,
        "batched_seconds": batched,
        "batched_per_second": batched_rate,
        "batched_best_per_second": batch_count / min(batched_times),
        "batched_us_per_configuration": 1e6 / batched_rate,
        "loop_count": loop_count,
        "loop_seconds": loop,
        "loop_per_second": loop_rate,
        "loop_ms_per_configuration": 1e3 / loop_rate,
        "batched_over_loop": batched_rate / loop_rate,
        "chunk": chunk,
        "threads": threads,
        "threaded_per_second": batch_count / threaded,
        "threaded_over_loop": batch_count / threaded / loop_rate,
        "threaded_equals_batched": bool(threads_agree),
        "svd_values_per_second": batch_count / svd_values,
        "svd_full_per_second": batch_count / svd_full,
        "batched_over_svd_values": batched_rate / (batch_count / svd_values),
        "batch_equals_loop": bool(agree),
        "configurations_seconds": making,
    }


# --------------------------------------------------------------------------- output

def _rate(value):
    return f"{value:.3g}" if value < 1e3 else f"{value:.2e}".replace("e+0", "e").replace("e+", "e")


def markdown(rows, machine_info, quick, load=None):
    """The results as a Markdown table, the machine (and its load average at the start) stated above it."""
    lines = [
        f"Machine: {machine_info['cpu']}, {machine_info['cores']} cores ({machine_info['usable_cores']} usable), "
        f"{machine_info['platform']}; Python {machine_info['python']}, NumPy {machine_info['numpy']}, "
        f"BLAS {machine_info['blas']}{' (--quick)' if quick else ''}"
        + ("" if load is None else f"; load average {load[0]:.1f} at the start"),
        "",
        "| mechanism | DΦ | cold classify ms | survey ms | warm classify ms | batched conf/s (µs/conf) | "
        "loop conf/s | batched ÷ loop | every core: threads, conf/s, ÷ loop | "
        "numpy SVD of DΦ, values / full, conf/s | batch = loop |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in rows:
        shape = "×".join(map(str, row["jacobian_shape"]))
        lines.append(
            f"| {row['mechanism']} | {shape} | {row['cold_classify_ms']:.0f} | {row['survey_ms']:.0f} | "
            f"{row['warm_classify_ms']:.2f} | {_rate(row['batched_per_second'])} "
            f"({row['batched_us_per_configuration']:.1f}) | {_rate(row['loop_per_second'])} | "
            f"{row['batched_over_loop']:.0f}× | {row['threads']}, {_rate(row['threaded_per_second'])}, "
            f"{row['threaded_over_loop']:.0f}× | {_rate(row['svd_values_per_second'])} / "
            f"{_rate(row['svd_full_per_second'])} | "
            f"{'yes' if row['batch_equals_loop'] and row['threaded_equals_batched'] else 'NO'} |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- profile

def stage_times(model, points):
    """Seconds per configuration of each array stage of the batched first-order path, timed apart.

    The stages call what :func:`classify.classify_many` calls (its chunk
    loop runs them once per chunk): Φ, the closure check and DΦ from one
    pass over the loops (:func:`mechanisms.closure_and_jacobian`: planar
    chains in complex form, spherical and spatial ones from prefix products
    only), the singular values of DΦ·diag(s) (one-sided Jacobi up to four
    rows, beyond them the eigenvalues of the Gram matrix where certified;
    the generic LAPACK call for comparison), the kernel
    bases (block-arrow solves where the loops allow, else the complete QR of
    the transpose; the full SVD, the generic way, for comparison), the
    actuator block and its singular values, Df, its scale and block singular
    values, the stacked map (computed only where it can raise the survey's
    rank), the proper values.
    """
    from classify.batch import _arrow_structure, _constraint_values, _largest, kernel_bases
    from manifold import DEFAULT_RTOL
    from classify.metrics import metric_root, proper_values, singular_values, unit_rows
    from classify.survey import end_effector_reference
    from mechanisms import closure_and_jacobian

    manifold = model.manifold
    count = len(points)
    k = manifold.ambient.dim
    scales = manifold.ambient.tangent_scales
    survey = survey_of(model)
    rank = survey.constraint_rank
    dof = k - rank
    stages = {}

    def stage(name, function, repeats=3):
        stages[name] = timed(function, repeats=repeats)[0] / count
        return function()

    rows, turns, jacobian = stage("Φ, closure check and DΦ in one pass (closure_and_jacobian)",
                                  lambda: closure_and_jacobian(model.mechanism, points))
    jacobian = jacobian * scales
    stage("σ(DΦ·diag(s)) and its cut (Jacobi up to 4 rows, else the certified Gram eigenvalues)",
          lambda: _constraint_values(jacobian, DEFAULT_RTOL))
    stage("[not in the path] numpy.linalg.svd of DΦ·diag(s), values only",
          lambda: np.linalg.svd(jacobian, compute_uv=False))
    structure = _arrow_structure(model)
    basis = stage("kernel bases (" + ("block-arrow solves and a k×m QR" if structure is not None
                                      else "complete QR of the transpose") + ")",
                  lambda: kernel_bases(jacobian, rank, structure))
    stage("[not in the path] full SVD of DΦ·diag(s)", lambda: np.linalg.svd(jacobian, full_matrices=True))
    basis = scales[:, None] * basis
    unit_actuators = unit_rows(model.actuators, scales)
    actuator_block = unit_actuators @ basis
    stage("actuator block A·T and its singular values", lambda: singular_values(unit_actuators @ basis))
    n = model.end_effector_dimension
    if n:
        end_effector = stage("Df (end_effector_jacobian)",
                             lambda: np.broadcast_to(model.end_effector_jacobian(points), (count, n, k)))
        root = metric_root(model.end_effector_metric)
        rows = root @ end_effector
        stage("end-effector reference scale: every joint's rate R·diag(s) (end_effector_reference) and σ₁ of "
              "H½ R·diag(s)",
              lambda: _largest(end_effector_reference(model, points, rows, root)))
        block = rows @ basis
        stage("end-effector block H½ Df T and its singular values", lambda: singular_values(block))
        skipped = "" if survey.joint_rank < dof else " [skipped: cannot raise the survey's rank]"
        stage("stacked map singular values" + skipped,
              lambda: singular_values(np.concatenate([actuator_block, block], axis=1)))
        stage("proper values (QR, solve, singular values)",
              lambda: proper_values(model.actuators @ basis, end_effector @ basis, model.end_effector_metric,
                                    min(n, dof)))
    return stages


def profile(name, count, rng, chunk=None):
    """Print the stage times and the cProfile of ``classify_many`` on `count` regular configurations of `name`."""
    mechanism = catalogue.entry(name).mechanism()
    model = model_of(mechanism)
    survey_of(model)
    points, _ = regular_configurations(model, count, rng)
    options = {} if chunk is None else {"chunk": chunk}
    total, _ = timed(lambda: classify_many(model, points, **options), repeats=3)
    print(f"## {name}: classify_many on {count} configurations: {1e6 * total / count:.1f} µs per configuration "
          f"({count / total:.3g} configurations/s)\n")
    print("| stage (timed apart, whole stack at once) | µs per configuration | share of classify_many |")
    print("|---|---|---|")
    stages = stage_times(model, points)
    for stage, seconds in stages.items():
        print(f"| {stage} | {1e6 * seconds:.2f} | {100 * seconds * count / total:.0f}% |")
    profiler = cProfile.Profile()
    profiler.enable()
    classify_many(model, points, **options)
    profiler.disable()
    stream = io.StringIO()
    pstats.Stats(profiler, stream=stream).sort_stats("tottime").print_stats(25)
    print("\ncProfile of one classify_many call, by own time:\n")
    print(stream.getvalue())
    return stages


# --------------------------------------------------------------------------- command

def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="smaller stacks and fewer repeats (under 30 s)")
    parser.add_argument("--out", type=Path, help="JSON output (default benchmarks/results/speed[_quick].json)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="only these mechanisms")
    parser.add_argument("--profile", metavar="NAME", help="profile the batched path of one mechanism and stop")
    parser.add_argument("--profile-count", type=int, default=8192, help="configurations profiled (default 8192)")
    arguments = parser.parse_args(argv)
    rng = np.random.default_rng(SEED)
    if arguments.profile:
        profile(arguments.profile, arguments.profile_count, rng)
        return 0
    selected = [settings for settings in MECHANISMS if not arguments.only or settings.name in arguments.only]
    unknown = set(arguments.only or ()) - {settings.name for settings in MECHANISMS}
    if unknown:
        parser.error(f"--only: unknown mechanism(s) {sorted(unknown)}; "
                     f"choose from {[settings.name for settings in MECHANISMS]}")
    started = time.perf_counter()
    info = machine()
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    rows = []
    for settings in selected:
        rows.append(measure(settings, arguments.quick, rng))
        print(f"{settings.name}: done ({time.perf_counter() - started:.0f} s)", file=sys.stderr)
    table = markdown(rows, info, arguments.quick, load)
    print(table)
    out = arguments.out or ROOT / "benchmarks" / "results" / ("speed_quick.json" if arguments.quick else "speed.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": info, "quick": arguments.quick, "seed": SEED,
                               "seconds": time.perf_counter() - started,
                               "load_average": {"start": load, "end": os.getloadavg() if load else None},
                               "results": rows, "table": table},
                              indent=2) + "\n")
    print(f"\nwritten {out} ({time.perf_counter() - started:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
