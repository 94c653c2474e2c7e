"""End to end: iface_container holds two C++ components and hands over between two of them in its process.

The workspaces (tests/ros_harness/cpp.py ``ticker_workspaces``): iface_msgs, iface_runtime_cpp, ticker 1.0
and the tally; ticker 1.1 alone on top (tests/runtime/data). Both tickers' install prefixes are signed by a
key of the test's trust store; a copy of 1.1's whose library was changed after signing is the untrusted one.
drive_iface_container.py runs the scenario (with this Python: the trust check needs ``cryptography``) through
``iface.operate.in_container``; each test below is one of its steps. Needs rclcpp built in the runtime
(``../shared/ros2-runtime/build-cpp.sh``): without it these tests skip, saying so.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from iface.operate.processes import find_executable

from ..ros_harness.cpp import missing_tools, overlay, rclcpp_env, ticker_workspaces
from ..ros_harness.ros import HARNESS, environment, run_bounded
from ..ros_harness.standby_probe import findings

DRIVER = HARNESS / "drive_iface_container.py"
STEPS = [
    "container: ticker 1.0 and the tally loaded into iface_container, active",
    "container: an untrusted library is refused before it is loaded",
    "container: 100 snapshots of the tally at 1 kHz lose no message",
    "container: ticker 1.1 loaded beside 1.0 (it can share the process)",
    "container: ~/handover switches ticker 1.0 to 1.1 at 1 kHz, state carried, none lost",
    "container: OLD unloaded, NEW goes on",
]


def sign_prefixes(prefixes: list[Path], root: Path) -> tuple[Path, Path]:
    """Sign each install prefix with a new key (``iface-lsp sign``), trusted by a new store; a signed copy of the
    last one whose component library was then changed. The store, the changed copy."""
    key, store = root / "keys" / "me.key", root / "trusted"
    key.parent.mkdir()
    store.mkdir()
    for argv in (["--keygen", str(key)], *([str(p), "--key", str(key)] for p in prefixes)):
        done = subprocess.run([sys.executable, "-m", "iface", "sign", *argv], capture_output=True, text=True,
                              timeout=60, check=False)
        assert done.returncode == 0, done.stderr
    shutil.copy(f"{key}.pub", store)
    tampered = root / "tampered" / "ticker"
    shutil.copytree(prefixes[-1], tampered, symlinks=True)
    with open(tampered / "lib" / "libticker_component.so", "ab") as f:
        f.write(b"\0")
    return store, tampered


@pytest.fixture(scope="module")
def run(ros_venv: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    env = rclcpp_env(ros_venv)
    if env is None:
        pytest.skip(f"rclcpp is not built in {ros_venv}/cpp: run `bash ../shared/ros2-runtime/build-cpp.sh "
                    f"{ros_venv}` (scripts/install-ros.sh does)")
    if missing_tools(env):
        pytest.skip(f"no {', '.join(missing_tools(env))} on PATH to build C++")
    root = tmp_path_factory.mktemp("containers")
    ws, why = ticker_workspaces(ros_venv, root)
    assert not why, why
    store, tampered = sign_prefixes([ws["ws"] / "install" / "ticker", ws["ws"] / "install" / "tally",
                                     ws["ws_v1_1"] / "install" / "ticker"], root)
    run_env = overlay(environment(ros_venv, ws["ws"], root / "ros-log"), ws["ws"], "setup.bash")
    env_v1_1 = overlay(run_env, ws["ws_v1_1"])
    rate = root / "1khz.yaml"
    rate.write_text("/**:\n  ros__parameters:\n    rate_hz: 1000.0\n", encoding="utf-8")
    config = {"env": run_env, "env_v1_1": env_v1_1, "ws": str(ws["ws"]), "ws_v1_1": str(ws["ws_v1_1"]),
              "store": str(store), "tampered": str(tampered), "rate_1khz": str(rate)}
    (root / "config.json").write_text(json.dumps(config))
    out, log = root / "result.json", root / "driver.log"
    code = run_bounded([sys.executable, str(DRIVER), str(root / "config.json"), "--out", str(out), "--logs",
                        str(root / "logs")], run_env, 300, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "logs"), "env": run_env}
    return steps


@pytest.mark.parametrize("step", STEPS)
def test_iface_container(run: dict[str, Any], step: str) -> None:
    """Two C++ instances in one container, an untrusted library refused before it is loaded, and the hand-over
    inside the container from ticker 1.0 to 1.1 at 1 kHz with the count carried and none lost or repeated."""
    info = run["_run"]
    if step not in run:
        tail = Path(info["log"]).read_text(errors="replace")[-3000:] if Path(info["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {info['code']}; logs in {info['logs']}):\n{tail}")
    assert run[step]["ok"], f"{step}: {run[step]['detail']} (logs in {info['logs']})"


def test_a_standby_container_makes_its_node_only_when_told_and_ends_with_its_parent(run: dict[str, Any],
                                                                                    ros_venv: Path) -> None:
    """``iface_container --standby`` (the manager's spare container): no container node until SIGUSR1, then the
    container's (its services, its name from ``__node:=``); a second SIGUSR1 ends nothing; one whose parent ends,
    ends."""
    env = run["_run"]["env"]
    exe = find_executable("iface_runtime_cpp", "iface_container", env)
    findings(ros_venv, env, "box_standby", [exe], Path(run["_run"]["logs"]) / "standby.log")
