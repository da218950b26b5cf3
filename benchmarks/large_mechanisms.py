"""Time and memory of large mechanisms against the number of joints k, with the fitted exponents.

Run from the repository root::

    .venv/bin/python benchmarks/large_mechanisms.py                 # k = 10 … 1000, about a minute
    .venv/bin/python benchmarks/large_mechanisms.py --sizes 10 100  # some sizes only
    .venv/bin/python benchmarks/large_mechanisms.py --family rsur   # spatial loops, k = 12 … 1000, a few minutes

The mechanism is a planar *ladder* (``--family ladder``, the default): four-bar parallelogram loops stacked on
the ground, four joints each, rung i joined to rung i − 1 by two parallel
links of direction (tᵢ, 1), tᵢ = 0.1 + 0.3 sin i (so that the rungs do not
all move alike). The left joint of every loop is actuated, and when k is no
multiple of 4 the k mod 4 remaining joints (actuated) hang in a chain from
the top rung; the end-effector is a point of the top rung or of the chain's
last link. Every loop touches only its own joints: DΦ has one 3×4 block per
loop, the structure :mod:`manifold.implicit` factorises block by block.
With ``--family rsur``, a stack of spatial RSUR loops (R, S, U and R joints,
seven coordinates each), each hung on the coupler of the one before, the
crank of every loop actuated and the last coupler's pose the end-effector:
DΦ has one 6×7 block per loop (``k // 4`` loops).

Each size runs in a fresh subprocess (a clean peak RSS from
``resource.getrusage``): imports and a warm-up classification of a ladder of
68 joints (past :data:`manifold.implicit.BLOCK_THRESHOLD`, so that the block
path's imports are paid too), then ``--repeats`` times the build
(``Mechanism`` and its home) and a cold ``classify.classify(mechanism,
home(mechanism))``, the survey of M included, each on a new mechanism; the
fastest is reported (the machine is shared: the others measure its load).
Then a new mechanism of the same size is classified under tracemalloc (the
peak of Python and NumPy allocations). Reported: seconds, peak RSS, RSS
above the warm-up's (what the mechanism added), the traced peak, and the
exponent b of ``value ≈ a·kᵇ`` fitted by least squares on the logarithms,
over all sizes and over k ≥ 100. Then, on the same mechanism, the other
paths a large mechanism takes (:func:`other_paths`, fastest of
``--repeats``): 50 configurations by ``classify_many`` and by a loop of
``classify``, ``project_many`` of 25 points off M, ``assemble`` with two
inputs moved, and the grid continuation of ``closedchain map`` over 5 × 5
values of two inputs, and the peak RSS after them. It prints Markdown and
writes JSON (``--out``, default ``benchmarks/results/large_mechanisms.json``, ``large_mechanisms_rsur.json``
with ``--family rsur``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
for _folder in (ROOT, ROOT / "tests"):  # the package, and the test suite's builders
    if str(_folder) not in sys.path:
        sys.path.insert(0, str(_folder))

#: the sizes k measured by default
SIZES = (10, 20, 50, 100, 200, 400, 1000)
#: the other paths timed at each size (:func:`other_paths`)
OTHER_PATHS = ("classify_many", "classify_loop", "project_many", "assemble", "map_grid")
#: seconds one size may take before it is reported as timed out
TIME_LIMIT = 600


def ladder(joint_count):
    """The ladder with exactly `joint_count` joints, at least 4: ``joint_count // 4`` four-bar loops and the
    rest as a tail (the test suite's builder, ``tests/builders.py``)."""
    from builders import ladder as ladder_of

    loops, tail = divmod(int(joint_count), 4)
    if loops < 1:
        raise ValueError(f"Expected at least 4 joints, got {joint_count}")
    return ladder_of(loops, tail)


def rsur_stack(joint_count):
    """The stack of ``joint_count // 4`` spatial RSUR loops (``tests/builders.py``), at least one."""
    from builders import rsur_stack as rsur_stack_of

    loops = int(joint_count) // 4
    if loops < 1:
        raise ValueError(f"Expected at least 4 joints, got {joint_count}")
    return rsur_stack_of(loops)


#: the mechanisms measured (``--family``): the builder of a mechanism of about k joints
FAMILIES = {"ladder": ladder, "rsur": rsur_stack}


def _peak_rss():
    """Peak resident memory of this process so far, bytes (``ru_maxrss`` is in KiB on Linux, bytes on macOS)."""
    import resource

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak if sys.platform == "darwin" else peak * 1024


def measure(joint_count, repeats=3, family="ladder"):
    """Build and classify mechanisms of the `family` with `joint_count` joints in this process; a dict for the
    JSON."""
    import tracemalloc

    from classify import classify
    from mechanisms import configuration_space, home

    build = FAMILIES[family]
    warm = build(68)
    classify(warm, home(warm))
    baseline = _peak_rss()
    timings = []
    for _ in range(repeats):
        started = time.perf_counter()
        mechanism = build(joint_count)
        point = home(mechanism)
        built = time.perf_counter()
        report = classify(mechanism, point)
        timings.append((built - started, time.perf_counter() - built))
    peak = _peak_rss()
    fresh = build(joint_count)
    tracemalloc.start()
    classify(fresh, home(fresh))
    traced = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    build_seconds, classify_seconds = min(timings, key=sum)
    others = {f"{name}_seconds": seconds for name, seconds in other_paths(mechanism, repeats).items()}
    others["paths_peak_rss_mb"] = _peak_rss() / 2 ** 20
    return {
        **others, "family": family, "coordinates": int(configuration_space(mechanism).ambient.dim),
        "k": len(mechanism.joints), "loops": mechanism.loop_count, "dof": report.dof, "kinds": list(report.kinds),
        "build_seconds": build_seconds, "classify_seconds": classify_seconds,
        "seconds": build_seconds + classify_seconds, "all_seconds": [sum(pair) for pair in timings],
        "peak_rss_mb": peak / 2 ** 20, "baseline_rss_mb": baseline / 2 ** 20,
        "added_rss_mb": (peak - baseline) / 2 ** 20, "traced_peak_mb": traced / 2 ** 20,
    }


def _fastest(function, repeats):
    """The fastest of `repeats` timed calls of `function`, seconds."""
    timings = []
    for _ in range(repeats):
        started = time.perf_counter()
        function()
        timings.append(time.perf_counter() - started)
    return min(timings)


def other_paths(mechanism, repeats, count=50):
    """Seconds of the other paths a large mechanism takes (its survey already cached on the model): `count`
    configurations by ``classify_many`` and by a loop of ``classify``, ``project_many`` of half as many points
    off M, ``assemble`` with two actuated joints moved (Gauss–Newton from the home, then 128 random starts
    for the branches), and the continuation of ``closedchain map`` over a 5 × 5 grid of them."""
    import numpy as np

    from classify import classify, classify_many, model_of
    from classify.grid_continuation import assemble_grid
    from manifold import project_many
    from mechanisms import assemble, configuration_space, from_displacements, home

    model = model_of(mechanism)
    moves = np.linspace(-0.2, 0.2, count)
    if mechanism.space == "planar":
        points = np.array([from_displacements(mechanism, {"A1": move, "B1": -move, "C1": move, "D1": -move})
                           for move in moves])  # the first loop turned: points of M
    else:  # points of M near the home, projected (not timed)
        ambient = configuration_space(mechanism).ambient
        moved = ambient.retract(np.broadcast_to(home(mechanism), (count, ambient.point_size)),
                                0.05 * np.random.default_rng(1).standard_normal((count, ambient.dim))
                                * ambient.tangent_scales)
        points, converged = project_many(configuration_space(mechanism), moved)
        points = points[np.asarray(converged, dtype=bool)]
    classify(model, points[0])
    off = points[: count // 2] + 1e-3 * np.random.default_rng(0).standard_normal(points[: count // 2].shape)
    values = np.linspace(-0.1, 0.1, 5)
    targets = np.array([from_displacements(mechanism, {"A1": first, "A2": second})
                        for first in values for second in values]) if mechanism.loop_count >= 2 else None
    held = tuple(sorted(mechanism.actuated_coordinates))
    # two inputs moved (an RSUR loop's crank turns little one way from the home)
    inputs = ({"A1": 0.1} if targets is None else {"A1": 0.1, "A2": -0.05}) if mechanism.space == "planar" else \
        {"A1": -0.05, "A2": -0.05}
    timed = {
        "classify_many": lambda: classify_many(model, points, workers=1),
        "classify_loop": lambda: [classify(model, point) for point in points],
        "project_many": lambda: project_many(configuration_space(mechanism), off),
        "assemble": lambda: assemble(mechanism, inputs),
    }
    if targets is not None:
        timed["map_grid"] = lambda: assemble_grid(mechanism, home(mechanism), targets, (5, 5), held)
    return {name: _fastest(function, repeats) for name, function in timed.items()}


def run(joint_count, repeats, family="ladder"):
    """:func:`measure` in a fresh subprocess; a dict with ``error`` where it failed or timed out."""
    arguments = [sys.executable, str(Path(__file__).resolve()), "--one", str(joint_count), "--repeats", str(repeats),
                 "--family", family]
    try:
        completed = subprocess.run(arguments, cwd=ROOT, capture_output=True, text=True, timeout=TIME_LIMIT)
    except subprocess.TimeoutExpired:
        return {"k": joint_count, "error": f"still running after {TIME_LIMIT} s"}
    if completed.returncode != 0:
        return {"k": joint_count, "error": completed.stderr.strip().splitlines()[-1:] or ["failed"]}
    return json.loads(completed.stdout.strip().splitlines()[-1])


def exponent(rows, key, smallest=0):
    """b of ``value ≈ a·kᵇ`` by least squares on the logarithms, over the rows with k ≥ `smallest` (None
    with fewer than two such rows)."""
    import numpy as np

    pairs = [(row["k"], row[key]) for row in rows if "error" not in row and row["k"] >= smallest and row[key] > 0]
    if len(pairs) < 2:
        return None
    sizes, values = np.log(np.array(pairs, dtype=float)).T
    return float(np.polyfit(sizes, values, 1)[0])


def table(rows):
    """The Markdown table of the measurements."""
    lines = ["| k | loops | build s | classify s | peak RSS MB | added RSS MB | traced peak MB | kinds | "
             + " | ".join(f"{name} s" for name in OTHER_PATHS) + " |",
             "|---:|---:|---:|---:|---:|---:|---:|---|" + "---:|" * len(OTHER_PATHS)]
    for row in rows:
        if "error" in row:
            lines.append(f"| {row['k']} | | | {row['error']} | | | | |" + " |" * len(OTHER_PATHS))
            continue
        others = " | ".join(f"{row[name + '_seconds']:.3g}" if name + "_seconds" in row else "-"
                            for name in OTHER_PATHS)
        lines.append(f"| {row['k']} | {row['loops']} | {row['build_seconds']:.3f} | {row['classify_seconds']:.2f} | "
                     f"{row['peak_rss_mb']:.0f} | {row['added_rss_mb']:.1f} | {row['traced_peak_mb']:.1f} | "
                     f"{', '.join(row['kinds']) or 'regular'} | {others} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES), metavar="K",
                        help="numbers of joints (default 10 20 50 100 200 400 1000)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per size, the fastest kept (default 3)")
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "large_mechanisms.json",
                        help="JSON output")
    parser.add_argument("--family", choices=sorted(FAMILIES), default="ladder",
                        help="planar ladders of four-bars (default) or stacks of spatial RSUR loops")
    parser.add_argument("--one", type=int, metavar="K", help=argparse.SUPPRESS)  # the subprocess of one size
    options = parser.parse_args(argv)
    if options.one is not None:
        print(json.dumps(measure(options.one, options.repeats, options.family)))
        return
    if options.family != "ladder" and options.out == parser.get_default("out"):
        options.out = options.out.with_name(f"large_mechanisms_{options.family}.json")
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from speed import machine

    rows = []
    for joint_count in options.sizes:
        rows.append(run(joint_count, options.repeats, options.family))
        print(f"k = {joint_count}: " + (rows[-1]["error"] if "error" in rows[-1] else
                                        f"{rows[-1]['seconds']:.2f} s, {rows[-1]['traced_peak_mb']:.1f} MB traced"),
              file=sys.stderr, flush=True)
    fits = {key: {"all": exponent(rows, key), "k >= 100": exponent(rows, key, 100)}
            for key in ("seconds", "classify_seconds", "added_rss_mb", "traced_peak_mb")
            + tuple(f"{name}_seconds" for name in OTHER_PATHS)}
    result = {"machine": machine(), "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
              "rows": rows, "exponents": fits}
    options.out.parent.mkdir(parents=True, exist_ok=True)
    options.out.write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(table(rows))
    print()
    print("Fitted exponent b of value ≈ a·kᵇ (least squares on logarithms):")
    for key, fit in fits.items():
        shown = {label: ("-" if value is None else f"{value:.2f}") for label, value in fit.items()}
        print(f"- {key}: {shown['all']} over all sizes, {shown['k >= 100']} over k ≥ 100")
    print(f"\nwritten to {options.out}")


if __name__ == "__main__":
    main()
