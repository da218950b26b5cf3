"""The dangerous inputs of the fuzz, each in a subprocess with 1 GB of address space and 10 s of CPU.

YAML bombs (aliases, merge keys), special files (``/dev/zero``, a FIFO) as
the mechanism file, the ``--at`` file or the ``--write`` target, files over
the size limit, a file just under it that describes a mechanism too large
for the dense algorithms, and a sample count that would allocate tens of
GiB: each must be refused (exit 2, one line on stderr) quickly, without
hanging or exhausting the memory. Cases skip where the platform lacks what
they need (``resource``, ``os.mkfifo``, ``/dev/zero``).

"Quickly" is CPU time (``RLIMIT_CPU``: the work done, whatever else the
machine runs); a wall-clock limit several times longer catches what waits
without working (a FIFO nobody writes).
"""

import os
import signal
import subprocess
import sys

import pytest

from mutations import billion_laughs, merge_key_bomb, pendulums

resource = pytest.importorskip("resource")

#: address space of the subprocess: enough for Python, NumPy and SciPy, far from what a blow-up takes
ADDRESS_SPACE = 2 ** 30
#: CPU seconds of the subprocess (past them the kernel stops it: the case fails)
TIME_LIMIT = 10
#: wall-clock seconds: a process that waits instead of working
WALL_LIMIT = 6 * TIME_LIMIT


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))
    resource.setrlimit(resource.RLIMIT_CPU, (TIME_LIMIT, TIME_LIMIT + 1))  # SIGXCPU, then SIGKILL


def _needs(condition, reason):
    if not condition:
        pytest.skip(reason)


def _fifo(folder, name):
    _needs(hasattr(os, "mkfifo"), "no FIFOs on this platform")
    path = folder / name
    os.mkfifo(path)
    return path


def _dev_zero(folder, name):
    _needs(os.path.exists("/dev/zero"), "no /dev/zero on this platform")
    path = folder / name
    path.symlink_to("/dev/zero")
    return path


def _written(folder, name, text):
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


#: id -> function(folder) returning the command's arguments
CASES = {
    "billion-laughs": lambda folder: ["classify", str(_written(folder, "laughs.yaml", billion_laughs(9)))],
    "merge-key-bomb": lambda folder: ["classify", str(_written(folder, "merges.yaml", merge_key_bomb(30)))],
    "dev-zero-as-file": lambda folder: ["classify", str(_dev_zero(folder, "zero.yaml"))],
    "fifo-as-file": lambda folder: ["classify", str(_fifo(folder, "pipe.yaml"))],
    "dev-zero-as-at-file": lambda folder: ["classify", "five-bar", "--at", f"@{_dev_zero(folder, 'zero.json')}"],
    "fifo-as-at-file": lambda folder: ["classify", "five-bar", "--at", f"@{_fifo(folder, 'pipe.json')}"],
    "fifo-as-write-target": lambda folder: ["catalog", "five-bar", "--write", str(_fifo(folder, "pipe.yaml"))],
    "two-megabyte-file": lambda folder: ["classify", str(_written(folder, "big.yaml", pendulums(28_000)))],
    "one-megabyte-yaml-of-pendulums": lambda folder: [
        "classify", str(_written(folder, "pendulums.yaml", pendulums(13_000)))],
    "samples-a-billion": lambda folder: ["compare", "five-bar", "--samples", "1000000000"],
}


@pytest.mark.parametrize("case", list(CASES))
def test_dangerous_input_is_refused_within_limits(case, tmp_path):
    arguments = CASES[case](tmp_path)
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    environment.pop("CLOSEDCHAIN_DEBUG", None)
    try:
        completed = subprocess.run([sys.executable, "-m", "classify", *arguments], capture_output=True, text=True,
                                   timeout=WALL_LIMIT, preexec_fn=_limit_memory, cwd=tmp_path, env=environment,
                                   stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        pytest.fail(f"{case}: still running after {WALL_LIMIT} s")
    assert completed.returncode not in (-signal.SIGXCPU, -signal.SIGKILL), f"{case}: more than {TIME_LIMIT} s of CPU"
    assert completed.returncode == 2, completed.stderr[-2000:]
    assert completed.stdout == ""
    assert completed.stderr.startswith("closedchain: error:") and completed.stderr.count("\n") == 1, \
        completed.stderr[-2000:]
