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
