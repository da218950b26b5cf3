"""Start-up time of the ``closedchain`` command, and what its import costs.

Run from the repository root::

    .venv/bin/python benchmarks/startup.py            # about 20 s
    .venv/bin/python benchmarks/startup.py --runs 3   # fewer runs

Each command runs in a fresh subprocess ``runs + 1`` times; the first run
(cold file cache) is discarded and the median of the others is reported:

* ``closedchain --help`` and ``closedchain catalog`` (issue 11: ≤ 0.3 s, aim ≤ 0.15 s);
* ``python -c "import classify.cli"``: the import alone;
* ``closedchain classify five-bar``: a first classification from the
  command line (imports, survey of M, one classification, the report);
* ``python -c pass`` and ``python -c "import numpy"``: the floor any Python
  command with NumPy pays on this machine.

Then ``python -X importtime -c "import classify.cli"`` lists the ten most
expensive imports, by cumulative and by own time, and the same for a first
``closedchain classify five-bar`` run in-process. It prints Markdown and
writes JSON (``--out``, default ``benchmarks/results/startup.json``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
if str(ROOT / "benchmarks") not in sys.path:
    sys.path.insert(0, str(ROOT / "benchmarks"))

from speed import machine  # noqa: E402  (the same machine description as the speed benchmark)


def commands():
    """Label → argument list of each timed command (the venv's ``closedchain`` next to this Python)."""
    closedchain = str(BIN / "closedchain")
    python = sys.executable
    return {
        "closedchain --help": [closedchain, "--help"],
        "closedchain catalog": [closedchain, "catalog"],
        'python -c "import classify.cli"': [python, "-c", "import classify.cli"],
        "closedchain classify five-bar": [closedchain, "classify", "five-bar"],
        "python -c pass (floor)": [python, "-c", "pass"],
        'python -c "import numpy" (floor)': [python, "-c", "import numpy"],
    }


def wall_times(arguments, runs):
    """Wall seconds of `runs` + 1 runs of a command (output discarded); the first is dropped.

    Raises
    ------
    RuntimeError
        If the command fails (naming it and its exit status).
    """
    times = []
    for _ in range(runs + 1):
        started = time.perf_counter()
        completed = subprocess.run(arguments, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        times.append(time.perf_counter() - started)
        if completed.returncode != 0:
            raise RuntimeError(f"{' '.join(arguments)} exited {completed.returncode}: "
                               f"{completed.stderr.decode(errors='replace').strip()[-300:]}")
    return times[1:]


def import_costs(code="import classify.cli", count=10):
    """The `count` most expensive imports of running `code`, by cumulative and by own time (µs), from
    ``python -X importtime``.

    Returns
    -------
    dict
        ``{"code": ..., "total_us": ..., "modules": ..., "cumulative": [[name, µs], ...], "self": [...]}``;
        ``total_us`` sums the top-level imports.
    """
    completed = subprocess.run([sys.executable, "-X", "importtime", "-c", code], cwd=ROOT,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=True)
    rows = []
    for line in completed.stderr.decode().splitlines():
        if not line.startswith("import time:") or "self [us]" in line:
            continue
        own, cumulative, name = line[len("import time:"):].split("|")
        rows.append((name.rstrip(), int(own), int(cumulative)))
    total = sum(cumulative for name, _, cumulative in rows if not name.startswith("  "))
    by_cumulative = sorted(rows, key=lambda row: -row[2])[:count]
    by_self = sorted(rows, key=lambda row: -row[1])[:count]
    return {"code": code, "total_us": total, "modules": len(rows),
            "cumulative": [[name.strip(), cumulative] for name, _, cumulative in by_cumulative],
            "self": [[name.strip(), own] for name, own, _ in by_self]}


#: a first classification from the command line, in-process (for its import costs)
CLASSIFY_CODE = ("import os, sys; from classify.cli import main; "
                 "main(['classify', 'five-bar'], out=open(os.devnull, 'w'))")


def loaded_heavy(module="classify.cli"):
    """Which heavy packages importing `module` loads (none of them should be)."""
    heavy = ["sympy", "scipy", "matplotlib", "dask", "pyarrow", "tqdm", "yaml"]
    code = (f"import sys, {module}; "
            f"print(' '.join(name for name in {heavy!r} if name in sys.modules))")
    completed = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, check=True)
    return completed.stdout.decode().split()


def markdown(walls, costs, heavy, info):
    lines = [f"Machine: {info['cpu']}, {info['cores']} cores, {info['platform']}; Python {info['python']}, "
             f"NumPy {info['numpy']}", "",
             "| command | median wall s | min | max |", "|---|---|---|---|"]
    for label, times in walls.items():
        lines.append(f"| `{label}` | {statistics.median(times):.3f} | {min(times):.3f} | {max(times):.3f} |")
    lines.append("")
    lines.append(f"Heavy packages loaded by `import classify.cli`: {', '.join(heavy) or 'none'}")
    for title, cost in costs.items():
        lines += ["", f"`{title}`: {cost['total_us'] / 1e3:.0f} ms of imports (-X importtime), "
                      f"{cost['modules']} modules", "",
                  "| top imports by cumulative time | ms | by own time | ms |", "|---|---|---|---|"]
        for (name, cumulative), (own_name, own) in zip(cost["cumulative"], cost["self"]):
            lines.append(f"| {name} | {cumulative / 1e3:.1f} | {own_name} | {own / 1e3:.1f} |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=7, help="timed runs per command after one discarded (7)")
    parser.add_argument("--out", type=Path, default=ROOT / "benchmarks" / "results" / "startup.json")
    arguments = parser.parse_args(argv)
    if arguments.runs < 1:
        parser.error(f"--runs: expected a positive count, got {arguments.runs}")
    info = machine()
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    walls = {label: wall_times(command, arguments.runs) for label, command in commands().items()}
    costs = {"import classify.cli": import_costs(),
             "closedchain classify five-bar": import_costs(CLASSIFY_CODE)}
    heavy = loaded_heavy()
    table = markdown(walls, costs, heavy, info)
    print(table)
    arguments.out.parent.mkdir(parents=True, exist_ok=True)
    arguments.out.write_text(json.dumps({
        "machine": info, "load_average": load, "runs": arguments.runs,
        "wall_seconds": {label: {"median": statistics.median(times), "times": times} for label, times in walls.items()},
        "import_costs": costs, "heavy_packages_loaded": heavy, "table": table}, indent=2) + "\n")
    print(f"\nwritten {arguments.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
