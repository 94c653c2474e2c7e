"""End to end: generated rclpy components built with the ROS 2 runtime and run on loopback.

One scenario per component (tests/ros_harness/drive_nodes.py) starts the nodes from their entry point and
checks each point of the issue as a step; each test below is one step. Every wait is bounded, every
process is stopped by its own handle, traffic stays on loopback in a random ROS_DOMAIN_ID.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from .conftest import Workspace
from ..ros_harness.ros import HARNESS, environment, run_bounded

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

DRIVER = HARNESS / "drive_nodes.py"
COMMON = [
    "start: entry point with the generated parameter file",
    "parameters: descriptors with description, unit and range",
    "parameters: out-of-range values refused with a reason",
    "parameters: in-range values applied",
    "qos: topics carry the declared QoS",
    "diagnostics: published and control answered while a long callback runs",
    "state: saved from one instance, restored into a second, the counter continues",
    "state: a restore from an incompatible interface is refused with a reason",
    "lifecycle: shutdown ends the process",
]
ROBOT_ARM = COMMON + [
    "lifecycle: configure",
    "lifecycle: activate",
    "topic: JointCommand in, JointState out",
    "service: MoveToPose and a Thrift-style function",
    "action: FollowTrajectory goal, feedback, result",
    "diagnostics: the component's diagnostics service",
    "control: paused refuses work, resume accepts it",
    "lifecycle: deactivate silences the publisher",
    "lifecycle: cleanup withdraws the members",
]
EVERY_MEMBER = COMMON + [
    "lifecycle: shutdown waits for the work in progress, then destroys the members",
    "lifecycle: configure and activate",
    "qos: depth and durability (a late joiner gets the kept history)",
    "topic: subscriptions and publishers",
    "service: provided services (node-relative, Thrift-style)",
    "client: a service client and an action client reach their servers",
    "action: goal, feedback, result",
    "control: pause after the current transaction, resume",
]


def _scenario(name: str, ws: Workspace, tmp: Path) -> dict[str, Any]:
    env = environment(ws.venv, ws.path, tmp / "ros-log")
    out = tmp / "result.json"
    log = tmp / "driver.log"
    code = run_bounded([str(ws.venv / "bin" / "python"), str(DRIVER), name, "--out", str(out), "--logs",
                        str(tmp / "logs")], env, 300, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(tmp / "logs")}
    return steps


@pytest.fixture(scope="module")
def robot_arm_run(ros_workspace: Workspace, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return _scenario("robot_arm", ros_workspace, tmp_path_factory.mktemp("robot_arm_run"))


@pytest.fixture(scope="module")
def every_member_run(ros_workspace: Workspace, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return _scenario("every_member", ros_workspace, tmp_path_factory.mktemp("every_member_run"))


def _check(steps: dict[str, Any], step: str) -> None:
    run = steps["_run"]
    if step not in steps:
        tail = Path(run["log"]).read_text(errors="replace")[-3000:] if Path(run["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {run['code']}; logs in {run['logs']}):\n{tail}")
    result = steps[step]
    assert result["ok"], f"{step}: {result['detail']} (logs in {run['logs']})"


@pytest.mark.parametrize("step", ROBOT_ARM)
def test_robot_arm(robot_arm_run: dict[str, Any], step: str) -> None:
    _check(robot_arm_run, step)


@pytest.mark.parametrize("step", EVERY_MEMBER)
def test_every_member(every_member_run: dict[str, Any], step: str) -> None:
    _check(every_member_run, step)
