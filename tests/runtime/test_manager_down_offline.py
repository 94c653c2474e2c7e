"""The manager's down without ROS 2: each instance deactivated and shut down in reverse order; the next one is
not kept waiting for the process of one that confirmed its shutdown, whose end is awaited after; one whose
shutdown was not confirmed is awaited before the next is touched. The lifecycle calls are a fake's; the
processes are real (a stand-in that runs until it is told to end)."""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from iface.live.link import LinkError
from iface.nodes.system import InstanceSpec, SystemSpec
from iface.operate.handover import ACTIVE, DEACTIVATE
from iface.operate.manager import Manager, Options

#: Seconds a stand-in takes to end once it is told to (a process tearing down its node).
ENDING = 0.5


def _spec(name: str, after: tuple[str, ...] = ()) -> InstanceSpec:
    return InstanceSpec(name=name, node=name, component="room_sensor", iface_file=Path("s.iface"),
                        interface_hash="sha256:x", package="room_sensor", executable="room_sensor",
                        restart="on-failure", snapshot_period=None, after=after, parameters=None, line=1)


class Lifecycle:
    """The manager's link: every node active; a shutdown ends the node's process ``ENDING`` s later.

    ``events`` records each transition and each process's end, in the order they happen.
    """

    def __init__(self, manager: Manager, failing: str = "") -> None:
        self.manager, self.failing = manager, failing
        self.events: list[str] = []
        self.lock = threading.Lock()

    def lifecycle_state(self, node: str, timeout: float) -> int:
        return ACTIVE

    def transition(self, node: str, transition: int, timeout: float) -> None:
        self._event(f"{'deactivate' if transition == DEACTIVATE else 'shutdown'} {node}")
        if transition != DEACTIVATE:
            self._end_later(node)
            if node == self.failing:
                raise LinkError(f"{node}/change_state: no answer")

    def _end_later(self, node: str) -> None:
        process = next(m.process for m in self.manager.instances if m.path == node)
        assert process is not None

        def end() -> None:
            time.sleep(ENDING)
            self._event(f"ended {node}")
            process.stop(5.0)

        threading.Thread(target=end, daemon=True).start()

    def _event(self, what: str) -> None:
        with self.lock:
            self.events.append(what)


@pytest.fixture
def logged() -> list[str]:
    """The manager's log lines."""
    return []


@pytest.fixture
def manager(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, logged: list[str]) -> Iterator[Manager]:
    """A manager of /sensor and /thermostat (after it), each a running stand-in; snapshots are not taken."""
    exe = tmp_path / "prefix" / "lib" / "room_sensor" / "room_sensor"
    exe.parent.mkdir(parents=True)
    exe.write_text(f"#!{sys.executable}\nimport time\ntime.sleep(120)\n", encoding="utf-8")
    exe.chmod(0o755)
    env = {**os.environ, "AMENT_PREFIX_PATH": str(tmp_path / "prefix")}
    system = SystemSpec(name="room", version=None, file=tmp_path / "room.iface",
                        instances=(_spec("sensor"), _spec("thermostat", ("sensor",))))
    mgr = Manager(system, Options(state_dir=tmp_path / "state"), env)
    mgr.log = logged.append  # type: ignore[method-assign,assignment]
    monkeypatch.setattr(mgr, "_snapshot", lambda m, why: None)
    monkeypatch.setattr(mgr, "_bring_up", lambda m, proc: setattr(m, "state", "active"))
    for m in mgr.instances:
        mgr._start(m)
    yield mgr
    for m in mgr.instances:
        if m.process is not None:
            m.process.stop(5.0)
    mgr.watcher.close()


def _downs(logged: list[str]) -> list[str]:
    return [line for line in logged if line.endswith(": down")]


def test_down_shuts_down_in_reverse_order_and_awaits_the_processes_after(manager: Manager, logged: list[str]) -> None:
    link = Lifecycle(manager)
    manager.link = link  # type: ignore[assignment]
    manager.down()
    assert link.events[:4] == ["deactivate /thermostat", "shutdown /thermostat", "deactivate /sensor",
                               "shutdown /sensor"], link.events  # the sensor is not kept waiting
    assert sorted(link.events[4:]) == ["ended /sensor", "ended /thermostat"], link.events
    assert _downs(logged) == ["thermostat: down", "sensor: down"]
    assert all(m.state == "down" and m.process is not None and not m.process.alive() for m in manager.instances)


def test_an_instance_whose_shutdown_is_not_confirmed_ends_before_the_next_is_deactivated(manager: Manager, logged: list[str]) -> None:
    link = Lifecycle(manager, failing="/thermostat")
    manager.link = link  # type: ignore[assignment]
    manager.down()
    assert link.events == ["deactivate /thermostat", "shutdown /thermostat", "ended /thermostat",
                           "deactivate /sensor", "shutdown /sensor", "ended /sensor"], link.events
    assert _downs(logged) == ["thermostat: down", "sensor: down"]
    thermostat = manager.instances[1]
    assert any("no answer" in f for f in thermostat.findings), thermostat.findings
