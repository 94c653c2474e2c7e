"""Standbys: spare processes the manager keeps for a fast restart (``standby = "true"``, docs/system.md).

A standby is the instance's (or its container's) command line with ``--standby``: the runtime blocks
SIGUSR1, sets a handler for it, starts ROS with a hidden node of no endpoints (its DDS participant up
and discovered ahead) and waits; on SIGUSR1 it makes the component's (the container's) node and goes
on as a process just started. ``Standby`` holds one such process and counts those that ended before
they were told (after ``TRIES`` in a row, none is started again: a runtime without ``--standby``);
``tell`` gives the signal, only to a standby that has its handler. ``seen`` tells once when the manager's
graph first shows the standby's node: from then on its participant and its endpoints' discovery are up (a
standby started within seconds of a crash may take that long to be discovered: docs/system.md).
"""

from __future__ import annotations

import contextlib
import os
import signal
import time
from collections.abc import Callable, Collection
from dataclasses import dataclass

from .processes import InstanceProcess, StartError, catches

#: Standbys that may end in a row before they are told, before none is started any more.
TRIES = 3
#: The hidden node a standby holds until it is told, and its pid (both runtimes).
NODE = "_iface_standby_{pid}"
#: The environment variable that tells a standby the process it ends with (the manager's pid: the runtimes'
#: ``STANDBY_PARENT``).
PARENT = "IFACE_STANDBY_PARENT"


def environment(env: dict[str, str]) -> dict[str, str]:
    """``env`` for a standby started by this process: it ends when this process ends."""
    return {**env, PARENT: str(os.getpid())}


@dataclass
class Standby:
    """The spare process of an instance or a container, and how many ended before they were told."""

    process: InstanceProcess | None = None
    #: Standbys that ended before they were told, since the last one that was.
    ended: int = 0
    #: When the process was started (monotonic), and whether its node was seen in the graph since.
    started: float = 0.0
    discovered: bool = False

    def keep(self, launch: Callable[[], InstanceProcess]) -> str | None:
        """Start a standby with ``launch`` when none runs; what to report (one that ended before it was told,
        one that could not start), else None."""
        spare = self.process
        if spare is not None and spare.alive():
            return None
        said = None
        if spare is not None:
            self.process = None
            self.ended += 1
            said = (f"standby pid {spare.pid} ended (exit {spare.exit_code()}) before it was needed"
                    + (f"; {TRIES} in a row: restarts go without one" if self.ended >= TRIES else ""))
        if self.ended >= TRIES:
            return said
        try:
            self.process = launch()
            self.started, self.discovered = time.monotonic(), False
        except (StartError, OSError) as e:
            self.ended = TRIES
            return f"no standby: {e}"
        return said

    def seen(self, nodes: Callable[[], Collection[str]]) -> str | None:
        """What to report when the standby's node is in ``nodes()`` (the graph's node names) for the first time,
        else None; the graph is read only while a running standby is not seen yet."""
        spare = self.process
        if spare is None or self.discovered or not spare.alive() or NODE.format(pid=spare.pid) not in nodes():
            return None
        self.discovered = True
        return f"standby pid {spare.pid} discovered {time.monotonic() - self.started:.2f} s after it started"

    def take(self, usable: Callable[[InstanceProcess], bool] = lambda _p: True) -> InstanceProcess | None:
        """The standby, told to make its node, when it is ``usable`` and ready; else None (one there is stopped)."""
        spare, self.process = self.process, None
        if spare is None:
            return None
        if usable(spare) and tell(spare):
            self.ended = 0
            return spare
        spare.stop(2.0)
        return None

    def stop(self) -> None:
        """Stop the standby, if there is one."""
        spare, self.process = self.process, None
        if spare is not None:
            spare.stop(2.0)


def tell(spare: InstanceProcess) -> bool:
    """SIGUSR1 to a standby that has its handler for it (until then the signal would end it); whether it was sent."""
    if spare.alive() and catches(spare.pid, signal.SIGUSR1):
        with contextlib.suppress(ProcessLookupError):
            os.kill(spare.pid, signal.SIGUSR1)
            return True
    return False


__all__ = ["NODE", "PARENT", "TRIES", "Standby", "environment", "tell"]
