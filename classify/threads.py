"""Independent pieces of array work in threads, their results in order.

NumPy's element-wise loops and LAPACK release the global interpreter lock,
so chunks of a stack of configurations (:func:`classify.classify_many`) run
side by side on several cores in one process: no copies, no pickling, and a
result that does not depend on the number of threads (each piece is computed
the same way whichever thread takes it). The convention is SciPy's
(``scipy.fft``, ``scipy.spatial.cKDTree.query``): ``workers=1`` in this
thread, ``-1`` every core the process may use.
"""

from __future__ import annotations

import contextvars
import math
import numbers
import os
from pathlib import Path

__all__ = ["available_cores", "thread_count", "ordered_map"]

#: where Linux gives a container's CPU quota: cgroup v2 ``"quota period"`` (or ``"max …"``), then cgroup v1
CGROUP_QUOTA_FILES = (Path("/sys/fs/cgroup/cpu.max"),
                      (Path("/sys/fs/cgroup/cpu/cpu.cfs_quota_us"), Path("/sys/fs/cgroup/cpu/cpu.cfs_period_us")))


def _cgroup_cores(files=CGROUP_QUOTA_FILES):
    """The cores a Linux CPU quota allows, ⌈quota / period⌉ (at least 1), or None where there is no quota or
    no file says (another platform, unreadable or malformed files: the affinity alone then counts)."""
    version_2, (quota_1, period_1) = files
    try:
        fields = version_2.read_text().split() if version_2.exists() else [quota_1.read_text(),
                                                                             period_1.read_text()]
        quota, period = int(fields[0]), int(fields[1])
    except (OSError, ValueError, IndexError):  # "max" (no quota), a missing or unreadable file
        return None
    return max(1, math.ceil(quota / period)) if quota > 0 and period > 0 else None  # v1: -1, no quota


def available_cores():
    """The cores this process may run on: its CPU affinity where the platform tells it, else the machine's,
    at most what a Linux CPU quota (a container's ``--cpus``) allows."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    quota = _cgroup_cores()
    return cores if quota is None else min(cores, quota)


def thread_count(workers, pieces):
    """The threads to run `pieces` pieces of work in: `workers` (-1: :func:`available_cores`), at most one a piece.

    Raises
    ------
    ValueError
        If `workers` is neither a positive integer nor -1.
    """
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or not (workers >= 1 or workers == -1):
        raise ValueError(f"Expected workers to be a positive integer or -1 (every core), got {workers!r}")
    return max(1, min(available_cores() if workers == -1 else int(workers), int(pieces)))


def ordered_map(work, items, threads):
    """``work(item)`` for every item, yielded in the items' order, computed in `threads` threads (1: in this one).

    An error of ``work`` is raised when its item's turn comes (so the first
    failing item in order is the one reported, as in a plain loop); the items
    not yet started are then cancelled and the running ones awaited. Each
    item runs in a copy of the caller's context, so what the caller set in
    context variables holds in every thread, as in a plain loop: NumPy's
    error state (:func:`numpy.errstate`, :func:`numpy.seterr`) from NumPy 2 on,
    where it is one (before, it was per thread, and threads started with the
    default).
    """
    if threads <= 1:
        yield from map(work, items)
        return
    from concurrent.futures import ThreadPoolExecutor

    pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="closedchain")
    try:  # pool.map submits every item from this thread, so each context is copied here
        yield from pool.map(lambda item, context: context.run(work, item), items,
                            iter(contextvars.copy_context, None))
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
