"""The generated launch files under the real ``ros2 launch``, looked at with the ``ros2`` command, on every release.

- The component launch file (``ros2 launch PACKAGE PACKAGE.launch.py``): the node under ``namespace:=`` and
  ``node_name:=``, the parameters of ``params_file:=`` over the installed file's, a topic and an action
  remapped by their launch arguments (the action found at its new name, and a goal sent there accepted and
  answered: Jazzy's rcl does not remap action names, the launch file remaps the action's five parts).
- The system launch file (``generate SYSTEM --target launch``): every instance active with the parameters of
  its file; ``activate:=false`` leaves them unconfigured, ``namespace:=`` puts them under it.
- ``manager:=true``: the manager starts the instances; a ``kill -9`` of one brings it back active with its
  snapshot, a ``kill -9`` of the manager brings a new one (launch respawns it) that adopts them all, a
  replacement goes through; ``iface-lsp system status`` answers throughout.
- Every time, one SIGINT to ``ros2 launch``: it exits 0 and no process it (or the manager) started runs.

``ros2`` graph queries ask the ros2 daemon of the test's domain, which each test starts and stops with ``ros2
daemon start``/``stop`` (as a user's shell has one), with bounded retries (ros_harness/ros2cli.py); processes are
started from Python with their own handles. The components come from the session's workspace
(conftest.py), built once per release.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from ..ros_harness.ros import ROOT, at_once, environment
from ..ros_harness.ros2cli import (
    TRANSITION_DONE,
    TRANSITION_TARGET,
    Launched,
    cmdline,
    iface_lsp_on_path,
    ros2,
    service_call,
    stop_leftovers,
    transition,
)
from .conftest import Workspace

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

SYSTEM = """/** The launch tests' system. */
system launch_room version "1.0.0"
include "room_sensor.iface"
include "thermostat.iface"

instance sensor : room_sensor (parameters = "sensor.yaml")
instance thermostat : thermostat (restart = "on-failure", snapshot = "1s", after = "sensor",
                                  parameters = "thermostat.yaml")
"""
SENSOR_YAML = "/**:\n  ros__parameters:\n    rate_hz: 5.0\n"
THERMOSTAT_YAML = "/**:\n  ros__parameters:\n    hysteresis: 1.25\n"
UP = 60  # seconds a system may take to come up on a loaded machine (a bound, not a measure)


@dataclass
class Setup:
    """The environment of ``ros2 launch`` (the session's workspace sourced, ``iface-lsp`` on PATH), a folder."""

    env: dict[str, str]
    release: str
    ws: Workspace
    root: Path

    def launch(self, *args: str, log: str) -> Launched:
        return Launched(["ros2", "launch", *args], self.env, self.root / "logs" / f"{log}.log", cwd=self.root)

    def iface(self, *args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
        return subprocess.run(["iface-lsp", *args], env=self.env, capture_output=True, text=True, timeout=timeout,
                              check=False)


@pytest.fixture
def setup(ros_workspace: Workspace, ros_release: str, tmp_path: Path) -> Iterator[Setup]:
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    env["PATH"] = iface_lsp_on_path(tmp_path / "bin", ROOT, sys.executable) + os.pathsep + env["PATH"]
    # the domain's ros2 daemon answers the graph queries from the graph it keeps: without it each `ros2` command
    # discovers the whole graph itself (2-5 s a question here, the module 248 -> 167 s with it on Kilted). It is a
    # detached process that would outlive the test: stopped by its own command
    started = ros2(env, "daemon", "start", graph=False, within=0)
    assert started.code == 0, started
    yield Setup(env, ros_release, ros_workspace, tmp_path)
    stopped = ros2(env, "daemon", "stop", graph=False, within=0)
    # whatever the test started still running after it (a failed test: the manager's restart of an instance as
    # launch took it down once outlived it for an hour): killed, and a failure of the test. The daemon is one of
    # them (its environment names the test's folder): one that outlived its stop fails the test here
    left = stop_leftovers(f"{tmp_path}{os.sep}")
    assert stopped.code == 0, stopped
    assert not left, f"still running after the test, killed: {left}"


@pytest.fixture
def system(setup: Setup) -> tuple[Path, Path]:
    """The system file (beside its components and parameter files) and its generated launch file."""
    folder = setup.root / "system"
    folder.mkdir()
    for name in ("room_sensor", "thermostat"):
        shutil.copy(ROOT / "examples" / f"{name}.iface", folder)
    (folder / "launch_room.iface").write_text(SYSTEM, encoding="utf-8")
    (folder / "sensor.yaml").write_text(SENSOR_YAML, encoding="utf-8")
    (folder / "thermostat.yaml").write_text(THERMOSTAT_YAML, encoding="utf-8")
    done = setup.iface("generate", str(folder / "launch_room.iface"), "--target", "launch", "--out",
                       str(setup.root / "launch"))
    assert done.returncode == 0, done.stderr
    return folder / "launch_room.iface", setup.root / "launch" / "launch_room.launch.py"


def _ok(answer: object, *expected: str) -> str:
    text = answer.out  # type: ignore[attr-defined]
    assert answer.code == 0 and all(e in text for e in expected), str(answer)  # type: ignore[attr-defined]
    return str(text)


def _state(setup: Setup, node: str, expected: str) -> str:
    """``ros2 lifecycle get NODE`` says ``expected`` (asked again while the node comes up, within a bound)."""
    return _ok(ros2(setup.env, "lifecycle", "get", node, until=f"{expected} [", within=UP, daemon=True), f"{expected} [")


def _transition(setup: Setup, node: str, label: str) -> None:
    """``ros2 lifecycle set NODE LABEL`` succeeds and the node is then in the transition's target state."""
    _ok(transition(setup.env, node, label, daemon=True), TRANSITION_DONE)
    _state(setup, node, TRANSITION_TARGET[label])


def _param(setup: Setup, node: str, name: str) -> str:
    answer = ros2(setup.env, "param", "get", node, name, daemon=True)
    return _ok(answer).strip()


def _interrupted(launched: Launched) -> None:
    """One SIGINT: ``ros2 launch`` exits 0 and nothing it started still runs."""
    seen = dict(launched.watch())
    assert seen, f"no process under ros2 launch:\n{launched.log()[-3000:]}"
    code = launched.interrupt(timeout=120)
    left = launched.left_running(within=15)
    assert code == 0, f"ros2 launch exit {code}:\n{launched.log()[-3000:]}"
    assert not left, f"still running after SIGINT: {[(pid, cmdline(pid)) for pid in left]}\n{launched.log()[-3000:]}"


# ---- the component launch file ----------------------------------------------------------------------------


def test_the_component_launch_file_starts_its_node_with_namespace_name_and_parameter_file(setup: Setup) -> None:
    params = setup.root / "arm.yaml"
    params.write_text("/**:\n  ros__parameters:\n    max_speed: 2.5\n", encoding="utf-8")
    launched = setup.launch("robot_arm", "robot_arm.launch.py", "namespace:=/lab", "node_name:=arm2",
                            f"params_file:={params}", "joint_state:=/lab/js", log="robot_arm")
    try:
        _ok(ros2(setup.env, "node", "list", until="/lab/arm2", within=UP, daemon=True), "/lab/arm2")
        # the questions that change nothing are asked at once: each `ros2` command's wait overlaps the others'
        _, launch_file, installed = at_once(lambda: _state(setup, "/lab/arm2", "unconfigured"),
                                            lambda: _param(setup, "/lab/arm2", "max_speed"),
                                            lambda: _param(setup, "/lab/arm2", "rate_hz"))
        assert launch_file == "Double value is: 2.5"  # the launch's file
        assert installed == "Double value is: 250.0"  # the installed file's
        _transition(setup, "/lab/arm2", "configure")
        # the same transition again (as a caller sends it after a lost answer): refused, the node lives on (Jazzy's
        # rclpy 7.1 lets the state machine's error end the process; the runtime answers success: false)
        again = service_call(setup.env, setup.release, "/lab/arm2/change_state", "lifecycle_msgs/srv/ChangeState",
                             "{transition: {id: 1}}")
        _ok(again, "success=False")
        _, info = at_once(lambda: _state(setup, "/lab/arm2", "inactive"),
                          lambda: _ok(ros2(setup.env, "node", "info", "/lab/arm2", until="/lab/js", daemon=True),
                                      "/lab/js: robot_arm_msgs/msg/JointState"))
        assert "/arm/joint_state" not in info, info
        _interrupted(launched)
    finally:
        launched.stop()


def test_an_action_remapped_by_the_component_launch_file_takes_goals_at_its_new_name(setup: Setup) -> None:
    """Jazzy's rcl remaps no action name: without its five parts remapped, /station/travel would stay."""
    launched = setup.launch("every_member", "every_member.launch.py", "node_name:=peer", "travel:=/far/travel",
                            "work:=/far/work", log="every_member")
    try:
        _state(setup, "/peer", "unconfigured")
        for label in ("configure", "activate"):
            _transition(setup, "/peer", label)
        actions, services = at_once(
            lambda: _ok(ros2(setup.env, "action", "list", graph=False, until="/far/travel"), "/far/travel"),
            lambda: _ok(ros2(setup.env, "service", "list", until="/far/work", daemon=True), "/far/work"))
        assert "/station/travel" not in actions, actions
        assert "/station/work" not in services and "/station/travel/_action/send_goal" not in services, services
        goal = "{waypoints: [{x: 1.0, y: 2.0}, {x: 3.0, y: 4.0}]}"
        sent = ros2(setup.env, "action", "send_goal", "/far/travel", "every_member_msgs/action/Travel", goal,
                    graph=False, timeout=60, within=0)
        _ok(sent, "Goal accepted", "reached: true", "visited: 2", "SUCCEEDED")
        _interrupted(launched)
    finally:
        launched.stop()


# ---- the system launch file -------------------------------------------------------------------------------


def test_the_system_launch_file_brings_every_instance_up_with_its_parameters(setup: Setup,
                                                                             system: tuple[Path, Path]) -> None:
    _, launch_file = system
    launched = setup.launch(str(launch_file), log="system")
    try:
        at_once(lambda: _state(setup, "/sensor", "active"), lambda: _state(setup, "/thermostat", "active"))
        rate, hysteresis = at_once(lambda: _param(setup, "/sensor", "rate_hz"),
                                   lambda: _param(setup, "/thermostat", "hysteresis"))
        assert rate == "Double value is: 5.0"
        assert hysteresis == "Double value is: 1.25"
        _interrupted(launched)
    finally:
        launched.stop()


def test_activate_false_and_a_namespace(setup: Setup, system: tuple[Path, Path]) -> None:
    _, launch_file = system
    launched = setup.launch(str(launch_file), "activate:=false", "namespace:=/ns", log="system-ns")
    try:
        at_once(lambda: _state(setup, "/ns/sensor", "unconfigured"),
                lambda: _state(setup, "/ns/thermostat", "unconfigured"))
        hysteresis, nodes = at_once(lambda: _param(setup, "/ns/thermostat", "hysteresis"),
                                    lambda: _ok(ros2(setup.env, "node", "list", daemon=True)))
        assert hysteresis == "Double value is: 1.25"
        assert not re.search(r"^/(sensor|thermostat)$", nodes, re.MULTILINE), nodes
        _interrupted(launched)
    finally:
        launched.stop()


# ---- manager:=true ----------------------------------------------------------------------------------------


def test_manager_true_refuses_a_namespace_and_starts_nothing(setup: Setup, system: tuple[Path, Path]) -> None:
    _, launch_file = system
    launched = setup.launch(str(launch_file), "manager:=true", "namespace:=/ns", log="managed-ns")
    try:
        code = launched.proc.wait(timeout=60)
        assert code != 0 and "namespace:= is not supported with manager:=true" in launched.log(), launched.log()
        assert "process started" not in launched.log(), launched.log()
    finally:
        launched.stop()


def _status(setup: Setup, system_file: Path) -> tuple[int, dict[str, dict[str, object]]]:
    done = setup.iface("system", "status", str(system_file), "--format", "json")
    if done.returncode not in (0, 1):
        return done.returncode, {}
    return done.returncode, {i["name"]: i for i in json.loads(done.stdout)["instances"]}


def _until(setup: Setup, system_file: Path, what: str, predicate: object,
           within: float = UP) -> dict[str, dict[str, object]]:
    end = time.monotonic() + within
    last: dict[str, dict[str, object]] = {}
    while time.monotonic() < end:
        code, last = _status(setup, system_file)
        if last and predicate(code, last):  # type: ignore[operator]
            return last
        time.sleep(0.5)
    raise AssertionError(f"{what}: not within {within:g} s; last status {last}")


def _saved(setup: Setup, system_file: Path, instance: str) -> dict[str, object]:
    done = setup.iface("system", "snapshot", str(system_file), instance)
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads(Path(json.loads(done.stdout)["files"][0]).read_text())["values"]


def _manager_pids(launched: Launched) -> list[int]:
    return [pid for pid in launched.watch() if "manager" in cmdline(pid) and "iface" in " ".join(cmdline(pid))]


def test_manager_true_gives_a_supervised_system_that_one_sigint_takes_down(setup: Setup,
                                                                          system: tuple[Path, Path]) -> None:
    system_file, launch_file = system
    state = setup.root / "state"
    launched = setup.launch(str(launch_file), "manager:=true", f"state_dir:={state}", log="managed")
    try:
        up = _until(setup, system_file, "every instance active",
                    lambda code, s: code == 0 and all(i["state"] == "active" for i in s.values()))
        launched.watch()
        _, hysteresis = at_once(lambda: _state(setup, "/thermostat", "active"),
                                lambda: _param(setup, "/thermostat", "hysteresis"))
        assert hysteresis == "Double value is: 1.25"
        _ok(service_call(setup.env, setup.release, "/thermostat/set_point", "thermostat_msgs/srv/SetPoint",
                         "{celsius: 23.5}"), "accepted=True")
        assert _saved(setup, system_file, "thermostat")["set_point"] == 23.5

        # kill -9 of an instance: the manager starts it again, restores its snapshot, activates it
        os.kill(int(up["thermostat"]["pid"]), signal.SIGKILL)  # type: ignore[call-overload]
        back = _until(setup, system_file, "the thermostat restarted",
                      lambda code, s: code == 0 and s["thermostat"]["restarts"] == 1
                      and s["thermostat"]["pid"] not in (0, up["thermostat"]["pid"]))
        launched.watch()
        set_point, _ = at_once(lambda: _saved(setup, system_file, "thermostat")["set_point"],
                               lambda: _state(setup, "/thermostat", "active"))
        assert set_point == 23.5

        # kill -9 of the manager: launch starts a new one, which adopts every instance (none started twice)
        managers = _manager_pids(launched)
        assert len(managers) == 1, managers
        os.kill(managers[0], signal.SIGKILL)
        end = time.monotonic() + UP
        while time.monotonic() < end and _manager_pids(launched) in ([], managers):
            time.sleep(0.5)
        assert _manager_pids(launched) not in ([], managers), launched.log()[-3000:]
        adopted = _until(setup, system_file, "a new manager answering",
                         lambda code, s: code == 0 and all(i["state"] == "active" for i in s.values()))
        assert {n: i["pid"] for n, i in adopted.items()} == {n: i["pid"] for n, i in back.items()}, adopted

        # a replacement through the manager: NEW from a copy of the install folder, OLD's state carried
        new = setup.root / "new"
        shutil.copytree(setup.ws.path / "install", new / "install", symlinks=True)
        text = (system_file.parent / "thermostat.iface").read_text(encoding="utf-8")
        (system_file.parent / "thermostat_new.iface").write_text(text.replace('version "1.0.0"', 'version "1.0.1"'),
                                                               encoding="utf-8")
        done = setup.iface("system", "replace", str(system_file), "thermostat", "--new",
                           str(system_file.parent / "thermostat_new.iface"), "--package",
                           str(new / "install" / "thermostat"), timeout=240)
        record = json.loads(done.stdout) if done.stdout.strip().startswith("{") else {}
        assert done.returncode == 0 and record.get("result") == "replaced", done.stdout[-3000:] + done.stderr
        replaced = _until(setup, system_file, "the replacement active",
                          lambda code, s: code == 0 and s["thermostat"]["node"] == "/thermostat_2")
        launched.watch()
        set_point, _ = at_once(lambda: _saved(setup, system_file, "thermostat")["set_point"],
                               lambda: _state(setup, "/thermostat_2", "active"))
        assert set_point == 23.5
        assert replaced["sensor"]["pid"] == back["sensor"]["pid"]

        # one SIGINT: the manager takes the system down in reverse order, a snapshot of each, and exits
        interrupted = time.time()
        _interrupted(launched)
        log = launched.log()
        assert 0 <= log.find("thermostat: down") < log.find("sensor: down"), log[-3000:]
        for name in ("sensor", "thermostat"):  # the snapshot of each one's deactivate
            newest = max(p.stat().st_mtime for p in (state / "snapshots" / name).glob("*.json"))
            assert newest >= interrupted, f"{name}: no snapshot after the SIGINT"
    finally:
        launched.stop()
