"""Instance processes without ROS: own session, records, adoption only of the very process recorded, and an
instance's end told the moment it comes (a pidfd per process, not a poll)."""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from iface.operate import manager as manager_module
from iface.operate import processes
from iface.operate.implementation import Implementation
from iface.operate.processes import (
    ExitWatcher,
    InstanceProcess,
    ProcessRecord,
    Records,
    StartError,
    find_executable,
    proc_cmdline,
    proc_stat,
    running,
    start,
)

IMPL = Implementation("room_sensor", "s.iface", "sha256:x", "room_sensor", "room_sensor")
SLEEPER = [sys.executable, "-c", "import time; time.sleep(120)"]
#: How long a test waits at most for what must come at once (a bound, not a measured figure).
BOUND = 10.0


def _start(tmp_path: Path, node: str = "sensor") -> InstanceProcess:
    return start(node, node, [*SLEEPER, "--ros-args", "-r", f"__node:={node}"], dict(os.environ),
                 tmp_path / "logs" / f"{node}.log", implementation=IMPL, generation=1)


def _told() -> tuple[threading.Event, list[InstanceProcess], Any]:
    told = threading.Event()
    seen: list[InstanceProcess] = []

    def then(p: InstanceProcess) -> None:
        seen.append(p)
        told.set()
    return told, seen, then


def test_a_started_process_is_recorded_and_recognised_and_a_changed_record_is_not(tmp_path: Path) -> None:
    proc = _start(tmp_path)
    try:
        assert os.getsid(proc.pid) == proc.pid, "not in a session of its own"
        assert proc.record.cmdline == (*SLEEPER, "--ros-args", "-r", "__node:=sensor")
        records = Records(tmp_path)
        records.save(proc.record)
        again = records.load("sensor")
        assert again == proc.record
        assert again.implementation() == IMPL
        assert running(again)
        assert not running(dataclasses.replace(again, start_ticks=again.start_ticks + 1)), "a recycled pid"
        assert not running(dataclasses.replace(again, cmdline=(*again.cmdline, "x"))), "another command"
    finally:
        proc.stop(5.0)
    assert not proc.alive() and not running(proc.record)
    records.remove("sensor")
    assert records.load("sensor") is None


def test_a_record_written_before_it_held_the_implementation_still_loads(tmp_path: Path) -> None:
    old = {"instance": "x", "node": "x", "pid": 1, "start_ticks": 2, "cmdline": ["a"], "package_dir": "",
           "iface_file": "x.iface", "interface_hash": "sha256:y", "generation": 1}
    (tmp_path / "processes").mkdir()
    (tmp_path / "processes" / "x.json").write_text(json.dumps(old), encoding="utf-8")
    record = Records(tmp_path).load("x")
    assert record is not None and record.implementation() is None and record.iface_file == "x.iface"


def test_an_unreadable_record_is_none(tmp_path: Path) -> None:
    (tmp_path / "processes").mkdir()
    (tmp_path / "processes" / "x.json").write_text("{", encoding="utf-8")
    assert Records(tmp_path).load("x") is None


def test_executable_found_on_the_ament_prefix_path(tmp_path: Path) -> None:
    exe = tmp_path / "prefix" / "lib" / "thermostat" / "thermostat"
    exe.parent.mkdir(parents=True)
    exe.write_text("#!/bin/sh\n")
    exe.chmod(0o755)
    env = {"AMENT_PREFIX_PATH": f"{tmp_path / 'none'}{os.pathsep}{tmp_path / 'prefix'}"}
    assert find_executable("thermostat", "thermostat", env) == str(exe)
    with pytest.raises(StartError, match="no executable other of package thermostat"):
        find_executable("thermostat", "other", env)


def test_a_replacement_s_executable_comes_from_its_install_folder_not_the_path(tmp_path: Path) -> None:
    def exe(prefix: Path, package: str, name: str) -> Path:
        path = prefix / "lib" / package / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text("#!/bin/sh\n")
        path.chmod(0o755)
        return path

    sourced = exe(tmp_path / "system", "thermostat", "thermostat")
    pro = exe(tmp_path / "ws-pro" / "install" / "thermostat_pro", "thermostat_pro", "thermostat_pro")
    env = {"AMENT_PREFIX_PATH": str(tmp_path / "system")}
    assert find_executable("thermostat", "thermostat", env) == str(sourced)
    for folder in (tmp_path / "ws-pro" / "install" / "thermostat_pro", tmp_path / "ws-pro" / "install"):
        assert find_executable("thermostat_pro", "thermostat_pro", env, str(folder)) == str(pro)
    with pytest.raises(StartError, match="no lib/thermostat/"):
        find_executable("thermostat", "thermostat", env, str(tmp_path / "ws-pro" / "install" / "thermostat_pro"))


def test_a_child_s_end_is_told_at_once_with_its_exit_status(tmp_path: Path) -> None:
    watcher = ExitWatcher()
    proc = _start(tmp_path)
    told, seen, then = _told()
    try:
        watcher.watch(proc, then)
        assert not told.wait(0.3), "told before it ended"
        os.kill(proc.pid, signal.SIGKILL)
        assert told.wait(BOUND), "the end of the process was not told"
        assert seen == [proc] and proc.ended.is_set() and proc.exit_code() == -signal.SIGKILL
        assert not proc.alive()
    finally:
        proc.stop(5.0)
        watcher.close()


def test_the_end_of_an_adopted_process_is_told_too(tmp_path: Path) -> None:
    """A process of another manager (here: the child of a process that has ended) is watched by its pidfd."""
    code = ("import subprocess, sys; p = subprocess.Popen(sys.argv[1:], start_new_session=True, "
            "stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL); print(p.pid)")
    pid = int(subprocess.run([sys.executable, "-c", code, *SLEEPER], capture_output=True, text=True, timeout=60,
                             check=True).stdout)
    stat, cmdline = proc_stat(pid), proc_cmdline(pid)
    assert stat is not None and cmdline is not None
    proc = InstanceProcess(ProcessRecord("x", "x", pid, stat[1], cmdline, "", "", "", 1))
    watcher = ExitWatcher()
    told, seen, then = _told()
    try:
        assert proc.adopted and proc.alive()
        watcher.watch(proc, then)
        os.kill(pid, signal.SIGKILL)
        assert told.wait(BOUND), "the end of the adopted process was not told"
        assert seen == [proc] and not proc.alive()
    finally:
        if proc.alive():
            os.kill(pid, signal.SIGKILL)
        watcher.close()


def test_without_pidfds_a_child_s_end_is_told_by_a_waiting_thread(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(processes, "open_pidfd", lambda pid: None)
    watcher = ExitWatcher()
    proc = _start(tmp_path)
    told, _, then = _told()
    try:
        watcher.watch(proc, then)
        os.kill(proc.pid, signal.SIGKILL)
        assert told.wait(BOUND)
        assert proc.exit_code() == -signal.SIGKILL
    finally:
        proc.stop(5.0)
        watcher.close()


def test_a_process_that_ended_before_it_was_watched_is_told_at_once(tmp_path: Path) -> None:
    proc = _start(tmp_path)
    os.kill(proc.pid, signal.SIGKILL)
    assert proc.wait(BOUND)
    watcher = ExitWatcher()
    told, _, then = _told()
    try:
        watcher.watch(proc, then)
        assert told.wait(BOUND)
    finally:
        watcher.close()


def test_the_manager_restarts_an_instance_when_its_process_ends_not_at_its_next_look(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """With the watch loop's own tick at an hour, only the told end of the process can start the restart."""
    monkeypatch.setattr(manager_module, "TICK", 3600.0)
    spec = SimpleNamespace(name="sensor", node="sensor", component="room_sensor", iface_file="s.iface",
                           interface_hash="sha256:x", package="room_sensor", executable="room_sensor",
                           restart="on-failure", snapshot_period=None, parameters=None, standby=False)
    system = SimpleNamespace(name="room", instances=(spec,))
    manager = manager_module.Manager(system, manager_module.Options(state_dir=tmp_path), dict(os.environ))
    manager.log = lambda message: None  # type: ignore[method-assign]
    m = manager.instances[0]
    restarted = threading.Event()
    monkeypatch.setattr(manager, "_start_or_fail", lambda m, why: restarted.set())
    m.process = manager._watched(_start(tmp_path))
    m.state = "active"
    m.heartbeat_ok = m.heartbeat_sent = m.watched = 1e12  # no heartbeat due, none missing
    loop = threading.Thread(target=manager.serve, daemon=True)
    loop.start()
    try:
        os.kill(m.process.pid, signal.SIGKILL)
        assert restarted.wait(BOUND), "the instance's end did not wake the manager"
        assert "process" in m.findings[-1] and "ended" in m.findings[-1]
    finally:
        manager.request_stop()
        loop.join(BOUND)
        m.process.stop(5.0)
        manager.watcher.close()
    assert not loop.is_alive()


def test_a_node_of_the_same_name_in_another_ros_domain_is_not_found(tmp_path: Path) -> None:
    """A manager without a record of an instance looks for its node's process by name; one in another ROS
    domain is another system's (a test run beside it had its instance adopted, found silent, and stopped)."""
    script = "import time; time.sleep(60)"
    mine = subprocess.Popen([sys.executable, "-c", script, "--ros-args", "-r", "__node:=twin"],
                            env={**os.environ, "ROS_DOMAIN_ID": "41"})
    theirs = subprocess.Popen([sys.executable, "-c", script, "--ros-args", "-r", "__node:=twin"],
                              env={**os.environ, "ROS_DOMAIN_ID": "42"})
    unset = {k: v for k, v in os.environ.items() if k != "ROS_DOMAIN_ID"}
    default = subprocess.Popen([sys.executable, "-c", script, "--ros-args", "-r", "__node:=twin"], env=unset)
    try:
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and len(processes.find_by_node("twin", "41")) < 1:
            time.sleep(0.05)
        assert [r.pid for r in processes.find_by_node("twin", "41")] == [mine.pid]
        assert [r.pid for r in processes.find_by_node("twin", "42")] == [theirs.pid]
        assert [r.pid for r in processes.find_by_node("twin", "0")] == [default.pid]
        assert processes.ros_domain({"ROS_DOMAIN_ID": " "}) == "0" and processes.ros_domain({}) == "0"
    finally:
        for p in (mine, theirs, default):
            p.kill()
            p.wait(timeout=10)
