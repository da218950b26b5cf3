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

import numbers
import os

__all__ = ["available_cores", "thread_count", "ordered_map"]


def available_cores():
    """The cores this process may run on (its CPU affinity where the platform tells it)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


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
    not yet started are then cancelled and the running ones awaited.
    """
    if threads <= 1:
        yield from map(work, items)
        return
    from concurrent.futures import ThreadPoolExecutor

    pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="closedchain")
    try:
        yield from pool.map(work, items)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
