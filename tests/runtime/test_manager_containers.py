"""End to end: `iface-lsp manager` runs a system with a component container beside a process of its own.

The system: a Python room sensor (examples/, built in the session's workspace), then ticker 1.0 (1 kHz,
its rate from a parameters file) and the tally, both C++ (tests/runtime/data), in the container ``box``.
The C++ workspaces are tests/ros_harness/cpp.py's ``ticker_workspaces`` (from the test cache, the component
packages copies of this module's own), each C++ install prefix signed by a key of the trust store; a copy of ticker 1.1's whose library changed after it
was signed is the untrusted NEW. drive_manager_containers.py runs the scenario (each test below is one of
its steps): up in order; the untrusted library refused before the container loads it; the container killed
with SIGKILL and both instances active again with their snapshots in its standby (the tally says
``standby = "true"``: the manager keeps a spare container process), each restart counted; ticker 1.0
replaced by 1.1 inside the container, the count carried and none lost; then by 2.0, which has
another ticker_msgs and so goes into a second container, with the reason in the record; the manager
killed and a new one taking the system back (the previous containers stopped, every instance loaded again
with its snapshot, NEW in its second container); down in reverse order with nothing
left running. C++ components are Kilted only; without rclcpp built in the runtime these tests skip, saying
so.
"""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path
from typing import Any

import pytest

from ..ros_harness.cpp import missing_tools, overlay, rclcpp_env, ticker_workspaces
from ..ros_harness.ros import DATA, HARNESS, ROOT, environment, run_bounded
from .test_containers import sign_prefixes

DRIVER = HARNESS / "drive_manager_containers.py"
STEPS = [
    "up: the Python instance, then both C++ instances in the container, in order",
    "untrusted: a changed library is refused before the container loads it",
    "kill -9 of the container: both instances active again with their snapshots, in its standby",
    "replace inside the container at 1 kHz: the count carried, none lost",
    "replace by a NEW that cannot share the process: a second container, the reason recorded",
    "kill -9 of the manager: a new one loads every instance again, NEW in its own container",
    "down: reverse order, the container stopped, nothing left running",
]
SYSTEM = """/** The container tests' system: a Python sensor, and two C++ components in one container. */
system plant version "1.0.0"
include "room_sensor.iface"
include "ticker.iface"
include "tally.iface"

instance sensor : room_sensor
instance ticker : ticker (container = "box", parameters = "ticker.params.yaml", after = "sensor")
instance tally : tally (container = "box", after = "ticker", standby = "true")
"""


@pytest.fixture(scope="module")
def run(ros_workspace: Any, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    ros_venv = ros_workspace.venv
    env = rclcpp_env(ros_venv)
    if env is None:
        pytest.skip(f"rclcpp is not built in {ros_venv}/cpp: run `bash ../shared/ros2-runtime/build-cpp.sh "
                    f"{ros_venv}` (scripts/install-ros.sh does)")
    if missing_tools(env):
        pytest.skip(f"no {', '.join(missing_tools(env))} on PATH to build C++")
    root = tmp_path_factory.mktemp("manager_containers")
    ws, why = ticker_workspaces(ros_venv, root)
    assert not why, why
    ws_v2 = ws["ws_v2"]
    store, tampered = sign_prefixes([ws["ws"] / "install" / "ticker", ws["ws"] / "install" / "tally",
                                     ws_v2 / "install" / "ticker", ws["ws_v1_1"] / "install" / "ticker"], root)
    sysdir = root / "system"
    sysdir.mkdir()
    shutil.copy(ROOT / "examples" / "room_sensor.iface", sysdir)
    for name in ("ticker", "tally", "ticker_v1_1", "ticker_v2"):
        shutil.copy(DATA / f"{name}.iface", sysdir)
    (sysdir / "ticker.params.yaml").write_text("/**:\n  ros__parameters:\n    rate_hz: 1000.0\n", encoding="utf-8")
    (sysdir / "plant.iface").write_text(SYSTEM, encoding="utf-8")
    # the C++ workspace on top of the Python one: one iface_msgs, the one the container links
    run_env = overlay(environment(ros_venv, ros_workspace.path, root / "ros-log"), ws["ws"], "setup.bash")
    config = {"python": sys.executable, "system": str(sysdir / "plant.iface"), "state": str(root / "state"),
              "store": str(store), "tampered": str(tampered), "new_iface": str(sysdir / "ticker_v1_1.iface"),
              "package_v1_1": str(ws["ws_v1_1"] / "install" / "ticker"),
              "v2_iface": str(sysdir / "ticker_v2.iface"), "package_v2": str(ws_v2 / "install" / "ticker"), "own": str(root), "env": run_env}
    (root / "config.json").write_text(json.dumps(config))
    out, log = root / "result.json", root / "driver.log"
    code = run_bounded([str(ros_venv / "bin" / "python"), str(DRIVER), str(root / "config.json"), "--out", str(out),
                        "--logs", str(root / "logs")], run_env, 600, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "logs")}
    return steps


@pytest.mark.parametrize("step", STEPS)
def test_manager_with_a_container(run: dict[str, Any], step: str) -> None:
    """A system with two C++ instances in one container and a Python one, run by the manager (docs/system.md,
    Containers)."""
    info = run["_run"]
    if step not in run:
        tail = Path(info["log"]).read_text(errors="replace")[-3000:] if Path(info["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {info['code']}; logs in {info['logs']}):\n{tail}")
    assert run[step]["ok"], f"{step}: {run[step]['detail']} (logs in {info['logs']})"
