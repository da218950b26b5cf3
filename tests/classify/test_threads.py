"""Threads over independent pieces of work (classify.threads): results in order, the first error in order."""

import threading
import time

import pytest

from classify.threads import available_cores, ordered_map, thread_count


def test_thread_count_follows_the_scipy_convention_and_the_pieces():
    assert thread_count(1, 10) == 1
    assert thread_count(8, 3) == 3
    assert thread_count(-1, 10_000) == available_cores() >= 1
    assert thread_count(4, 0) == 1


@pytest.mark.parametrize("workers", [0, -2, 2.0, False, None])
def test_thread_count_refuses_what_is_not_a_number_of_workers(workers):
    with pytest.raises(ValueError, match=r"workers .*positive integer or -1.*got"):
        thread_count(workers, 5)


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_ordered_map_yields_in_the_items_order(threads):
    def work(item):
        time.sleep(0.001 * (item % 3))  # later items may finish first
        return item * item

    assert list(ordered_map(work, range(20), threads)) == [item * item for item in range(20)]


def test_ordered_map_uses_other_threads():
    names = set(ordered_map(lambda item: threading.current_thread().name, range(8), 2))
    assert threading.current_thread().name not in names and all(name.startswith("closedchain") for name in names)


def test_ordered_map_raises_the_first_error_in_order_and_cancels_the_rest():
    """Item 1 fails late, item 3 early: item 1's error is the one raised, as in a loop, and the items not
    started when it comes are not run."""
    started = []

    def work(item):
        started.append(item)
        if item == 1:
            time.sleep(0.05)
            raise ValueError("item 1")
        if item == 3:
            raise ValueError("item 3")
        time.sleep(0.01)
        return item

    with pytest.raises(ValueError, match="item 1"):
        list(ordered_map(work, range(100), 2))
    assert len(started) < 100


NUMPY_1 = pytest.mark.skipif(int(__import__("numpy").__version__.split(".")[0]) < 2,
                             reason="NumPy's error state is a context variable from NumPy 2 on")


@NUMPY_1
@pytest.mark.parametrize("threads", [1, 2])
def test_every_thread_runs_under_the_callers_numpy_error_state(threads):
    """np.errstate is a context variable: a thread started without the caller's context would warn where the
    caller asked for an error (and a result could then depend on the number of threads)."""
    import numpy as np

    with np.errstate(divide="raise", invalid="ignore"):
        states = list(ordered_map(lambda item: np.geterr(), range(6), threads))
    assert all(state["divide"] == "raise" and state["invalid"] == "ignore" for state in states)


@NUMPY_1
def test_a_raising_error_state_raises_in_threads_as_in_one_thread():
    import numpy as np

    def work(item):
        return np.float64(item + 1) / np.float64(0.0)

    with np.errstate(divide="raise"):
        with pytest.raises(FloatingPointError):
            list(ordered_map(work, range(4), 2))


def _quota_files(tmp_path, version_2=None, version_1=None):
    """CGROUP_QUOTA_FILES under tmp_path, with the given texts (None: the file is missing)."""
    files = (tmp_path / "cpu.max", (tmp_path / "cpu.cfs_quota_us", tmp_path / "cpu.cfs_period_us"))
    if version_2 is not None:
        files[0].write_text(version_2)
    if version_1 is not None:
        files[1][0].write_text(version_1[0])
        files[1][1].write_text(version_1[1])
    return files


@pytest.mark.parametrize("version_2, version_1, cores", [
    ("150000 100000\n", None, 2),         # --cpus=1.5: two threads
    ("50000 100000\n", None, 1),
    ("max 100000\n", None, None),         # no quota
    (None, ("300000\n", "100000\n"), 3),  # cgroup v1
    (None, ("-1\n", "100000\n"), None),   # v1, no quota
    (None, None, None),                   # no cgroup files (another platform)
    ("garbage\n", None, None),
])
def test_a_cgroup_cpu_quota_bounds_the_cores(tmp_path, version_2, version_1, cores):
    from classify.threads import _cgroup_cores

    assert _cgroup_cores(_quota_files(tmp_path, version_2, version_1)) == cores


def test_available_cores_is_at_most_the_quota(monkeypatch):
    import classify.threads as threads

    monkeypatch.setattr(threads, "_cgroup_cores", lambda: 1)
    assert threads.available_cores() == 1
    monkeypatch.setattr(threads, "_cgroup_cores", lambda: None)
    assert threads.available_cores() >= 1
