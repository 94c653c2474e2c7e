"""Fast DDS's event-thread deadlock (eProsima/Fast-DDS#6502, open), found through ``/proc``.

A receive thread that removes a remote writer holds the discovery (PDP) mutex and waits in
``ResourceEvent::unregister_timer`` for the participant's event thread (``dds.ev.N``) to end its round; the
event thread is in that round, checking a remote participant's lease, and waits for the PDP mutex. Neither
moves again: the participant hears nothing more and is no longer heard (seen in Jazzy's Fast DDS 2.14.5 in a
driver of the tests' manager scenario, 2026-11-30; gdb's stacks in docs/testing.md). What ``/proc`` shows of it: the
event thread sits in ``futex(FUTEX_WAIT)`` on one address with no timeout (a mutex; its idle wait is a
condition with a timeout) and spends no CPU. Linux only; elsewhere nothing is found.

The manager watches its own process (``watch``) and ends when it finds it, so that a manager started again
(launch respawns it) adopts the instances; the tests' drivers look at theirs when a call goes unanswered.
"""

from __future__ import annotations

import os
import platform
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ISSUE = "eProsima/Fast-DDS#6502"
#: futex's syscall number where the test machines run.
FUTEX = {"x86_64": 202, "aarch64": 98}.get(platform.machine(), -1)
FUTEX_WAIT = 0  # the operation, once FUTEX_PRIVATE_FLAG (128) and FUTEX_CLOCK_REALTIME (256) are masked off
EVENT_THREAD = "dds.ev."


@dataclass(frozen=True)
class Stuck:
    """An event thread of a Fast DDS participant blocked on one mutex."""

    pid: int
    tid: int
    thread: str
    mutex: int

    def describe(self) -> str:
        return (f"pid {self.pid} ({_cmdline(self.pid)}): its Fast DDS event thread {self.thread} (tid {self.tid}) "
                f"waits on mutex {self.mutex:#x} and spends no CPU ({ISSUE}, a deadlock)")


def _read(path: Path) -> str:
    try:
        return path.read_text(errors="replace")
    except OSError:
        return ""


def _cmdline(pid: int) -> str:
    words = _read(Path(f"/proc/{pid}/cmdline")).split("\0")
    return " ".join(w for w in words if w)[:200] or "gone"


def _on_a_mutex(pid: int) -> dict[int, tuple[str, int, str]]:
    """Each event thread of ``pid`` now in ``futex(FUTEX_WAIT)`` without a timeout: tid -> (name, address, CPU)."""
    found: dict[int, tuple[str, int, str]] = {}
    tasks = Path(f"/proc/{pid}/task")
    try:
        tids = [int(t.name) for t in tasks.iterdir()]
    except (OSError, ValueError):
        return found
    for tid in tids:
        name = _read(tasks / str(tid) / "comm").strip()
        if not name.startswith(EVENT_THREAD):
            continue
        fields = _read(tasks / str(tid) / "syscall").split()
        if len(fields) < 5 or not fields[0].isdigit() or int(fields[0]) != FUTEX:
            continue
        address, op, timeout = int(fields[1], 16), int(fields[2], 16), int(fields[4], 16)
        if op & ~(128 | 256) == FUTEX_WAIT and timeout == 0:
            cpu = " ".join(_read(tasks / str(tid) / "stat").rsplit(")", 1)[-1].split()[11:13])  # utime stime
            found[tid] = (name, address, cpu)
    return found


def _confirmed(first: dict[int, dict[int, tuple[str, int, str]]], settle: float) -> list[Stuck]:
    """Of the threads ``_on_a_mutex`` found in each process, those found the same ``settle`` seconds later."""
    if not any(first.values()):
        return []
    time.sleep(settle)
    out = []
    for pid, seen in sorted(first.items()):
        now = _on_a_mutex(pid)
        out += [Stuck(pid, tid, name, address) for tid, (name, address, cpu) in sorted(seen.items())
                if now.get(tid) == (name, address, cpu)]
    return out


def stuck(pid: int, settle: float = 1.0, ignore: frozenset[int] = frozenset()) -> list[Stuck]:
    """The event threads of ``pid`` blocked on the same mutex, spending no CPU, ``settle`` seconds apart
    (``ignore``: thread ids already known)."""
    return _confirmed({pid: {tid: seen for tid, seen in _on_a_mutex(pid).items() if tid not in ignore}}, settle)


def in_domain(domain: str | None, settle: float = 1.0) -> list[Stuck]:
    """Every process this user may read whose ``ROS_DOMAIN_ID`` is ``domain`` (None: any process) and whose
    Fast DDS is deadlocked."""
    pids = [int(entry.name) for entry in Path("/proc").iterdir()
            if entry.name.isdigit() and (domain is None or
                                         f"\0ROS_DOMAIN_ID={domain}\0" in "\0" + _read(entry / "environ"))]
    return _confirmed({pid: _on_a_mutex(pid) for pid in pids}, settle)


def note(domain: str | None = None) -> str:
    """A failed step's line naming each deadlocked participant of this domain (``ROS_DOMAIN_ID``), if any."""
    domain = domain if domain is not None else os.environ.get("ROS_DOMAIN_ID", "0")
    found = in_domain(domain)
    return "".join(f"\n--- Fast DDS deadlocked: {s.describe()}" for s in found)


def watch(pid: int, found: Callable[[Stuck], None], interval: float = 2.5,
          stop: threading.Event | None = None) -> threading.Thread:
    """A daemon thread that calls ``found`` once when an event thread of ``pid`` is blocked on one mutex, spending
    no CPU, at each of four looks over twice ``interval`` (two ``stuck`` in a row); ``stop`` ends it."""
    ended = stop or threading.Event()

    def run() -> None:
        while not ended.is_set():
            first = stuck(pid, settle=interval)
            if first and (again := stuck(pid, settle=interval)):
                same = [s for s in again if s in first]
                if same:
                    found(same[0])
                    return
            if not first:
                ended.wait(interval)

    thread = threading.Thread(target=run, name="iface-dds-watch", daemon=True)
    thread.start()
    return thread
