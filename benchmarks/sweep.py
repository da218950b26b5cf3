"""Speed-up of a design sweep on a 2-worker Dask LocalCluster over the serial run (issue 11: ≥ 1.6×, aim ≥ 1.9×).

Run from the repository root::

    .venv/bin/python benchmarks/sweep.py            # about 2 minutes on 2 cores
    .venv/bin/python benchmarks/sweep.py --quick    # a smaller grid, about 20 s

One grid of designs of a catalogue entry (:func:`classify.sweep.sweep`), run
``repeats`` times each way, alternately, in the same process:

* *serial*: ``sweep(entry, grid, samples)``, one chunk after the other in
  this process;
* *cluster*: the same call with a ``distributed.Client`` of
  :func:`classify.sweep.local_cluster` (2 worker processes of one thread),
  started once before the timed runs (its start-up is timed apart and
  reported, not included: a cluster serves many sweeps).

The speed-up is the median serial time over the median cluster time. Each
timed run's rows are checked equal to the first serial run's (the test suite
checks it thoroughly). A 2-core machine shared with other work gives less
than 2× whatever the code does: the JSON records the load average at the
start and the end, and the time the workers spent in tasks.

Prints Markdown and writes JSON (``--out``, default
``benchmarks/results/sweep.json``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT / "benchmarks") not in sys.path:
    sys.path.insert(0, str(ROOT / "benchmarks"))

from speed import machine  # noqa: E402  (the same machine description as the speed benchmark)

from classify.sweep import local_cluster, sweep  # noqa: E402

#: (entry, grid, samples per design) of the full and the quick runs
SETTINGS = {
    False: ("five-bar", ["proximal=6:10:6", "distal=4:6:6"], 300),
    True: ("five-bar", ["proximal=6:10:6", "distal=4:6:4"], 200),
}


def _load():
    return list(os.getloadavg()) if hasattr(os, "getloadavg") else None


def timed_sweep(name, grid, samples, client=None):
    """(seconds, the result as JSON text) of one sweep: two runs agree when their texts are equal."""
    start = time.perf_counter()
    result = sweep(name, grid, samples, seed=0, client=client)
    return time.perf_counter() - start, json.dumps(result.to_dict(), sort_keys=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a smaller grid, fewer repeats")
    parser.add_argument("--repeats", type=int, default=None, help="timed runs each way (default 3, quick 2)")
    parser.add_argument("--out", default=None, help="JSON file (default benchmarks/results/sweep[_quick].json)")
    arguments = parser.parse_args(argv)
    from distributed import Client

    name, grid, samples = SETTINGS[arguments.quick]
    repeats = arguments.repeats or (2 if arguments.quick else 3)
    load_start = _load()
    timed_sweep(name, grid, 4)  # imports and first-call costs, in this process, before any timing
    start = time.perf_counter()
    cluster = local_cluster(2)
    client = Client(cluster)
    cluster_start_seconds = time.perf_counter() - start
    try:
        client.run(timed_sweep, name, grid, 4)  # the same warm-up in each worker
        serial, parallel, reference = [], [], None
        for _ in range(repeats):
            seconds, rows = timed_sweep(name, grid, samples)
            reference = rows if reference is None else reference
            serial.append(seconds)
            seconds, rows = timed_sweep(name, grid, samples, client=client)
            if rows != reference:
                raise SystemExit("the cluster's rows differ from the serial run's: a defect, not a timing")
            parallel.append(seconds)
    finally:
        client.close()
        cluster.close()
    designs = len(json.loads(reference)["rows"])
    result = {
        "machine": machine(),
        "quick": arguments.quick,
        "mechanism": name,
        "grid": grid,
        "designs": designs,
        "samples_per_design": samples,
        "repeats": repeats,
        "serial_seconds": serial,
        "cluster_seconds": parallel,
        "cluster_start_seconds": cluster_start_seconds,
        "speed_up": statistics.median(serial) / statistics.median(parallel),
        "load_average": {"start": load_start, "end": _load()},
    }
    print(f"Machine: {result['machine']['cpu']}, {result['machine']['cores']} cores, "
          f"load average {load_start[0]:.2f} at the start\n" if load_start else "")
    print("| sweep | designs × samples | serial s (median) | 2-worker cluster s (median) | speed-up |")
    print("|---|---|---|---|---|")
    print(f"| {name} {' '.join(grid)} | {designs} × {samples} | {statistics.median(serial):.2f} | "
          f"{statistics.median(parallel):.2f} | {result['speed_up']:.2f}× |")
    print(f"\nCluster start-up (not in the times above): {cluster_start_seconds:.2f} s")
    out = Path(arguments.out) if arguments.out else ROOT / "benchmarks" / "results" / (
        "sweep_quick.json" if arguments.quick else "sweep.json")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
