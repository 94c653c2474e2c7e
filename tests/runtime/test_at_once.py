"""``ros_harness.ros.at_once``: the calls run at the same time, their results come in order, errors are not lost."""

from __future__ import annotations

import threading

import pytest

from ..ros_harness.ros import at_once


def test_the_calls_run_at_the_same_time_and_their_results_come_in_order() -> None:
    # each call waits for all the others at a barrier: one after another, the first would wait alone and break it
    barrier = threading.Barrier(3, timeout=30)

    def call(n: int) -> int:
        barrier.wait()
        return n * 10

    assert at_once(lambda: call(1), lambda: call(2), lambda: call(3)) == [10, 20, 30]


def test_every_call_ends_and_the_first_error_in_order_is_raised() -> None:
    ended: list[str] = []
    release = threading.Event()

    def slow() -> None:
        release.wait(60)
        ended.append("slow")

    def fails(name: str) -> None:
        release.set()
        raise ValueError(name)

    with pytest.raises(ValueError, match="first"):
        at_once(slow, lambda: fails("first"), lambda: fails("second"))
    assert ended == ["slow"]  # at_once returned only after the slow call ended
