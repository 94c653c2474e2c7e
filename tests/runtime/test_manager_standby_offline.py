"""The manager's standbys without ROS 2 (``standby = "true"``): a spare process started for an active instance,
told with SIGUSR1 to become the instance when its process ends (no new process started), another spare started
after; a spare made for another implementation not taken; spares that end by themselves given up after
``TRIES``; none left running after down. The instance's executable is a stand-in that keeps the
runtime's ``--standby`` contract (iface_runtime_py, iface_runtime_cpp: wait for SIGUSR1, end with the parent);
the runtimes themselves are driven by test_manager.py."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import pytest

from iface.operate import manager as manager_module
from iface.operate.manager import Managed, Manager, Options
from iface.operate.processes import catches, proc_cmdline
from iface.operate.standby import TRIES

#: How long a test waits at most for what must come at once (a bound, not a measured figure).
BOUND = 10.0

STAND_IN = """\
import os, signal, sys, time
if "--standby" in sys.argv:
    if os.environ.get("STANDBY_FAILS"):
        sys.exit(2)
    time.sleep(float(os.environ.get("STANDBY_SLOW", "0")))  # a runtime still importing
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGUSR1})
    signal.signal(signal.SIGUSR1, lambda *_: None)
    parent = os.getppid()
    while signal.sigtimedwait({signal.SIGUSR1}, 0.05) is None:
        if os.getppid() != parent:
            sys.exit(0)
    open(os.path.join(os.environ["TOLD"], str(os.getpid())), "w").close()
time.sleep(120)
"""


def _spec(standby: bool = True) -> SimpleNamespace:
    return SimpleNamespace(name="sensor", node="sensor", component="room_sensor", iface_file="s.iface",
                           interface_hash="sha256:x", package="room_sensor", executable="room_sensor",
                           restart="on-failure", snapshot_period=None, parameters=None, after=(), line=1,
                           container=None, runtime="rclpy", plugin=None, intra_process=False, standby=standby)


def _stand_in(tmp_path: Path, package: str, executable: str) -> dict[str, str]:
    """The stand-in installed as ``lib/<package>/<executable>`` of a prefix; an environment that finds it."""
    exe = tmp_path / "prefix" / "lib" / package / executable
    exe.parent.mkdir(parents=True)
    exe.write_text(f"#!{sys.executable}\n{STAND_IN}", encoding="utf-8")
    exe.chmod(0o755)
    (tmp_path / "told").mkdir()
    return {**os.environ, "AMENT_PREFIX_PATH": str(tmp_path / "prefix"), "TOLD": str(tmp_path / "told")}


@pytest.fixture
def manager(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Manager]:
    """A manager of one instance whose executable is the stand-in; bring-up marks it active without ROS."""
    env = _stand_in(tmp_path, "room_sensor", "room_sensor")
    system = SimpleNamespace(name="room", instances=(_spec(),))
    mgr = Manager(system, Options(state_dir=tmp_path / "state"), env)
    mgr.log = lambda message: None  # type: ignore[method-assign]

    def bring_up(m: Managed, proc: object) -> None:
        m.state = "active"
        m.heartbeat_ok = m.heartbeat_sent = m.watched = 1e12  # no heartbeat due, none missing

    monkeypatch.setattr(mgr, "_bring_up", bring_up)
    yield mgr
    for m in mgr.instances:
        for p in (m.process, m.standby.process):
            if p is not None:
                p.stop(5.0)
    mgr.watcher.close()


def _until(what: str, predicate: object) -> None:
    end = time.monotonic() + BOUND
    while not predicate():  # type: ignore[operator]
        assert time.monotonic() < end, what
        time.sleep(0.02)


def test_an_active_instance_gets_a_standby_which_becomes_it_when_its_process_ends(
        manager: Manager, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(manager_module, "TICK", 3600.0)  # only a process's end wakes the loop
    m = manager.instances[0]
    manager._start(m)
    first = m.process
    assert first is not None and "--standby" not in (proc_cmdline(first.pid) or ())
    manager._keep_standby(m)
    spare = m.standby.process
    assert spare is not None and spare.pid != first.pid
    assert "--standby" in (proc_cmdline(spare.pid) or ()) and f"__node:={m.node}" in (proc_cmdline(spare.pid) or ())
    environ = Path(f"/proc/{spare.pid}/environ").read_bytes().split(b"\0")
    assert f"IFACE_STANDBY_PARENT={os.getpid()}".encode() in environ  # it ends with this manager
    assert not any(e.startswith(b"IFACE_STANDBY_PARENT=") for e in Path(f"/proc/{first.pid}/environ").read_bytes()
                   .split(b"\0"))
    manager._keep_standby(m)
    assert m.standby.process is spare  # one at a time
    _until("the standby has no handler for SIGUSR1", lambda: catches(spare.pid, signal.SIGUSR1))
    loop = threading.Thread(target=manager.serve, daemon=True)
    loop.start()
    try:
        os.kill(first.pid, signal.SIGKILL)
        _until("the standby was not made the instance", lambda: m.process is spare and m.state == "active")
        _until("the standby was not told", lambda: (tmp_path / "told" / str(spare.pid)).exists())
        assert m.restarts == 1 and "ended" in m.findings[-1]
        assert manager.records.load(m.name).pid == spare.pid  # type: ignore[union-attr]
        manager.wake.set()  # the loop's next look (its tick is an hour here)
        _until("no new standby after the restart",
               lambda: m.standby.process is not None and m.standby.process.pid != spare.pid)
        assert not (tmp_path / "told" / str(m.standby.process.pid)).exists()  # type: ignore[union-attr]
    finally:
        manager.request_stop()
        loop.join(BOUND)
    assert not loop.is_alive()
    standby = m.standby.process
    m.process.stop(5.0)  # type: ignore[union-attr]
    manager._down(m)
    assert m.standby.process is None and standby is not None and standby.wait(BOUND)


def test_the_manager_says_once_when_its_graph_first_shows_a_standby(manager: Manager) -> None:
    """A standby is discovered when the manager's graph shows its hidden node (``_iface_standby_<pid>``): said
    once, in the log, for each standby; another node's name does not count."""
    m = manager.instances[0]
    said: list[str] = []
    names: list[str] = []
    manager.log = said.append  # type: ignore[method-assign]
    manager.node = SimpleNamespace(get_node_names_and_namespaces=lambda: [(n, "/") for n in names])
    manager._start(m)
    manager._keep_standby(m)
    spare = m.standby.process
    assert spare is not None
    names.extend(["sensor", "_iface_standby_1", f"_iface_standby_{spare.pid}0"])
    manager._keep_standby(m)
    assert not [x for x in said if "discovered" in x]
    names.append(f"_iface_standby_{spare.pid}")
    manager._keep_standby(m)
    manager._keep_standby(m)
    seen = [x for x in said if "discovered" in x]
    assert len(seen) == 1 and seen[0].startswith(f"sensor: standby pid {spare.pid} discovered ")
    assert seen[0].endswith(" s after it started")
    spare.stop(5.0)
    manager._keep_standby(m)  # it ended before it was told: another one, not seen yet
    following = m.standby.process
    assert following is not None and following.pid != spare.pid
    manager._keep_standby(m)
    assert len([x for x in said if "discovered" in x]) == 1
    names.append(f"_iface_standby_{following.pid}")
    manager._keep_standby(m)
    assert [x for x in said if "discovered" in x][-1].startswith(f"sensor: standby pid {following.pid} discovered ")


def test_a_standby_made_for_what_the_instance_ran_before_a_replacement_is_not_taken(manager: Manager) -> None:
    m = manager.instances[0]
    manager._start(m)
    manager._keep_standby(m)
    old = m.standby.process
    assert old is not None
    _until("the standby has no handler for SIGUSR1", lambda: catches(old.pid, signal.SIGUSR1))
    m.process.stop(5.0)  # type: ignore[union-attr]
    m.generation += 1  # a replacement committed: the instance runs NEW (its node, generation, implementation)
    manager._start(m)
    assert m.process is not None and m.process.pid != old.pid
    assert old.wait(BOUND) and m.standby.process is None


def test_a_standby_not_ready_for_its_signal_is_stopped_and_a_process_started_instead(manager: Manager) -> None:
    """Until the standby has its handler for SIGUSR1 (its runtime still importing), the signal would end it: a crash that
    soon after the standby's start starts a process as without one."""
    m = manager.instances[0]
    manager._start(m)
    manager.env["STANDBY_SLOW"] = "60"
    manager._keep_standby(m)
    early = m.standby.process
    assert early is not None and not catches(early.pid, signal.SIGUSR1)
    assert m.standby.take() is None
    assert early.wait(BOUND) and m.standby.process is None
    m.process.stop(5.0)  # type: ignore[union-attr]
    manager._start(m)
    assert m.process is not None and m.process.pid != early.pid and m.state == "active"


def test_standbys_that_end_by_themselves_are_given_up_after_a_few(manager: Manager) -> None:
    m = manager.instances[0]
    manager._start(m)
    manager.env["STANDBY_FAILS"] = "1"  # a runtime without --standby: argparse ends it (exit 2)
    pids = []
    for _ in range(TRIES + 2):
        manager._keep_standby(m)
        if m.standby.process is not None:
            pids.append(m.standby.process.pid)
            assert m.standby.process.wait(BOUND)
    assert len(pids) == TRIES and m.standby.process is None
    assert "ended (exit 2) before it was needed" in m.findings[0]
    assert f"{TRIES} in a row: restarts go without one" in m.findings[-1]


def test_an_instance_without_standby_gets_none_and_a_stopped_one_loses_its_own(manager: Manager) -> None:
    m = manager.instances[0]
    manager._start(m)
    m.spec = _spec(standby=False)
    manager._keep_standby(m)
    assert m.standby.process is None
    m.spec = _spec()
    manager._keep_standby(m)
    spare = m.standby.process
    assert spare is not None
    m.spec = SimpleNamespace(**{**vars(_spec()), "restart": "never"})
    assert not manager._may_restart(m, "process 1 ended (exit 1)", clean=False)
    assert m.state == "stopped" and m.standby.process is None and spare.wait(BOUND)


def test_a_container_of_an_instance_with_a_standby_has_a_standby_container_that_takes_its_place(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """In a container, ``standby = "true"`` is the container's: a spare container process (``--standby``,
    ``__node:=`` the container's name) told to start when the container ends, instead of a process started."""
    env = _stand_in(tmp_path, "iface_runtime_cpp", "iface_container")
    specs = [SimpleNamespace(**{**vars(_spec(standby=standby)), "name": name, "node": name, "container": "box",
                                "runtime": "rclcpp"}) for name, standby in (("ticker", False), ("tally", True))]
    mgr = Manager(SimpleNamespace(name="plant", instances=tuple(specs)), Options(state_dir=tmp_path / "state"), env)
    mgr.log = lambda message: None  # type: ignore[method-assign]
    mgr.link = SimpleNamespace(forget=lambda node: None)  # type: ignore[assignment]
    monkeypatch.setattr(manager_module, "ContainerCalls",
                        lambda link, name: SimpleNamespace(ready=lambda *args, **kwargs: None))
    host = mgr._host("box", env)
    first = host.process
    try:
        assert first is not None and "--standby" not in (proc_cmdline(first.pid) or ())
        for m in mgr.instances:
            m.state, m.process = "active", first
        mgr.instances[1].state = "inactive"
        mgr._keep_host_standby(host)
        assert host.standby.process is None  # only for an active instance that says standby
        mgr.instances[1].state = "active"
        mgr._keep_host_standby(host)
        spare = host.standby.process
        assert spare is not None and (proc_cmdline(spare.pid) or ())[-4:] == ("--standby", "--ros-args", "-r",
                                                                             "__node:=box")
        _until("the standby container has no handler for SIGUSR1", lambda: catches(spare.pid, signal.SIGUSR1))
        first.stop(5.0)
        mgr._start_host(host)
        assert host.process is spare and host.standby.process is None and host.restarts == 1
        _until("the standby container was not told", lambda: (tmp_path / "told" / str(spare.pid)).exists())
        assert mgr.container_records.load("box").pid == spare.pid  # type: ignore[union-attr]
        mgr._keep_host_standby(host)
        following = host.standby.process
        assert following is not None and following.pid != spare.pid
        mgr._stop_host(host)
        assert following.wait(BOUND) and spare.wait(BOUND) and not mgr.hosts
    finally:
        for p in (first, host.process, host.standby.process):
            if p is not None:
                p.stop(5.0)
        mgr.watcher.close()
