"""``iface.live.deadlock``: a Fast DDS event thread blocked on a mutex is found; idle and other threads are not.

A stand-in process names its threads as Fast DDS does (``prctl(PR_SET_NAME)``) and blocks them with libc's own
calls: ``dds.ev.0`` on a mutex that the main thread holds (the deadlock's signature), ``dds.ev.1`` in a wait with
a timeout (an idle event thread), ``dds.shm.7411`` on the same mutex (a receive thread, not the event thread).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import pytest

from iface.live import deadlock as dds_deadlock
from tests.conftest import ROOT

from . import conftest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux") or dds_deadlock.FUTEX < 0,
                                reason="reads /proc/PID/task/TID/syscall (Linux, x86_64 or aarch64)")

STAND_IN = textwrap.dedent("""
    import ctypes, sys, threading, time
    libc = ctypes.CDLL(None, use_errno=True)
    mutex = ctypes.create_string_buffer(64)  # zeroed: PTHREAD_MUTEX_INITIALIZER
    libc.pthread_mutex_lock(mutex)
    started = threading.Barrier(4)

    def named(name, then):
        libc.prctl(15, name.encode(), 0, 0, 0)  # PR_SET_NAME
        started.wait()
        then()

    threading.Thread(target=named, args=("dds.ev.0", lambda: libc.pthread_mutex_lock(mutex)), daemon=True).start()
    threading.Thread(target=named, args=("dds.ev.1", lambda: threading.Event().wait(120)), daemon=True).start()
    threading.Thread(target=named, args=("dds.shm.7411", lambda: libc.pthread_mutex_lock(mutex)), daemon=True).start()
    started.wait()
    print("ready", flush=True)
    sys.stdin.read()
""")


@pytest.fixture
def stand_in() -> Iterator[subprocess.Popen[str]]:
    env = {**os.environ, "ROS_DOMAIN_ID": "4242"}
    proc = subprocess.Popen([sys.executable, "-c", STAND_IN], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True, env=env)
    try:
        assert proc.stdout is not None and proc.stdout.readline().strip() == "ready"
        _wait_on_the_mutex(proc.pid, ("dds.ev.0", "dds.shm.7411"))
        yield proc
    finally:
        proc.kill()
        proc.wait(timeout=10)


def _wait_on_the_mutex(pid: int, names: tuple[str, ...]) -> None:
    """Until each thread named so waits in futex(FUTEX_WAIT) without a timeout (past the barrier is not yet there)."""
    end = time.monotonic() + 30
    while True:
        blocked = []
        for name in names:
            fields = Path(f"/proc/{pid}/task/{_tid(pid, name)}/syscall").read_text().split()
            blocked.append(len(fields) > 4 and fields[0] == str(dds_deadlock.FUTEX) and
                           int(fields[2], 16) & ~384 == 0 and int(fields[4], 16) == 0)
        if all(blocked):
            return
        assert time.monotonic() < end, f"{names} not blocked on the mutex within 30 s"
        time.sleep(0.01)


def _tid(pid: int, name: str) -> int:
    return next(int(t) for t in os.listdir(f"/proc/{pid}/task")
                if open(f"/proc/{pid}/task/{t}/comm").read().strip() == name)


def test_the_event_thread_blocked_on_a_mutex_is_found_and_nothing_else(stand_in: subprocess.Popen[str]) -> None:
    found = dds_deadlock.stuck(stand_in.pid, settle=0.3)
    assert [(s.pid, s.tid, s.thread) for s in found] == [(stand_in.pid, _tid(stand_in.pid, "dds.ev.0"), "dds.ev.0")]
    text = found[0].describe()
    assert f"pid {stand_in.pid}" in text and "dds.ev.0" in text and "eProsima/Fast-DDS#6502" in text


def test_a_thread_already_known_is_left_out(stand_in: subprocess.Popen[str]) -> None:
    known = frozenset({_tid(stand_in.pid, "dds.ev.0")})
    assert dds_deadlock.stuck(stand_in.pid, settle=0.3, ignore=known) == []


def test_the_processes_of_a_domain_are_looked_at_and_named(stand_in: subprocess.Popen[str]) -> None:
    assert [s.pid for s in dds_deadlock.in_domain("4242", settle=0.3)] == [stand_in.pid]
    assert dds_deadlock.in_domain("4243", settle=0.3) == []
    assert "--- Fast DDS deadlocked: pid" in dds_deadlock.note("4242")


def test_a_process_without_fast_dds_or_gone_has_nothing() -> None:
    assert dds_deadlock.stuck(os.getpid(), settle=0.1) == []
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True,
                          check=True)
    assert dds_deadlock.stuck(int(done.stdout), settle=0.1) == []


def test_a_failed_tests_report_names_each_deadlocked_process(stand_in: subprocess.Popen[str]) -> None:
    report = SimpleNamespace(failed=True, sections=[])
    hook = conftest.pytest_runtest_makereport(SimpleNamespace(), SimpleNamespace(when="call"))  # type: ignore[arg-type]
    next(hook)
    with pytest.raises(StopIteration):
        hook.send(SimpleNamespace(get_result=lambda: report))
    assert [title for title, _ in report.sections] == ["Fast DDS deadlocks"]
    assert f"pid {stand_in.pid}" in report.sections[0][1]


def test_watch_tells_a_deadlock_once_after_three_looks(stand_in: subprocess.Popen[str]) -> None:
    told: list[dds_deadlock.Stuck] = []
    done = threading.Event()
    start = time.monotonic()
    def found(stuck: dds_deadlock.Stuck) -> None:
        told.append(stuck)
        done.set()

    thread = dds_deadlock.watch(stand_in.pid, found, interval=0.2)
    assert done.wait(30), "not told"
    assert time.monotonic() - start >= 0.4  # blocked at looks over twice the interval
    thread.join(10)
    assert not thread.is_alive() and [s.thread for s in told] == ["dds.ev.0"]


def test_watch_tells_nothing_of_a_process_that_is_not_deadlocked() -> None:
    told: list[dds_deadlock.Stuck] = []
    stop = threading.Event()
    thread = dds_deadlock.watch(os.getpid(), told.append, interval=0.05, stop=stop)
    time.sleep(1.0)
    stop.set()
    thread.join(10)
    assert told == [] and not thread.is_alive()


def test_a_manager_whose_fast_dds_deadlocks_ends_with_exit_3_and_says_why() -> None:
    """The manager's own watch (``watch_own_dds``, which ``manager.run`` starts) over the stand-in's threads."""
    script = STAND_IN.replace('print("ready", flush=True)\nsys.stdin.read()',
                              "from iface.operate.manager import watch_own_dds\nwatch_own_dds(0.2)\ntime.sleep(60)")
    assert script != STAND_IN
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=False,
                          env={**os.environ, "PYTHONPATH": str(ROOT / "server")})
    assert done.returncode == 3, done.stderr
    assert "dds.ev.0" in done.stderr and "a manager started again adopts the instances" in done.stderr, done.stderr
