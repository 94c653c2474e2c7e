"""End to end: `iface-lsp handover` replaces a running counter 1.0 by counter 2.0, and refuses what it must.

Both components are generated from examples/counter.iface and examples/counter_v2.iface, built each
into its own workspace with the ROS 2 runtime, and run on loopback; drive_handover.py runs the
scenario (every wait bounded, every process stopped by its own handle). Skipped, saying why, without
the runtime.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from iface.operate.trust import keygen, sign

from ..ros_harness.ros import DATA, HARNESS, ROOT, build, environment, generate, run_bounded

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

DRIVER = HARNESS / "drive_handover.py"
STEPS = [
    "start: OLD active and counting, NEW started",
    "protocol: one SaveState type for both components, ~/describe answers",
    "refused: a provided service removed",
    "refused: a state variable retyped",
    "refused: NEW's interface hash is not the approved one",
    "refused: NEW unsigned where a trust store is configured",
    "refused: NEW signed by a key the trust store does not hold",
    "refused: NEW does not answer within the timeout",
    "handover: trusted, compatible NEW takes over",
    "handover: every state value carried, the counter continues in NEW",
    "handover: OLD deactivated, NEW active",
    "handover: no message lost on the reliable topic NEW took over",
    "handover: NEW's extra topic is published",
    "handover: the JSON shows the state before and after",
]


def _component(venv: Path, iface: Path, user: Path, root: Path, name: str) -> Path:
    gen = root / f"gen_{name}"
    done = generate(iface, gen)
    assert done.returncode == 0, done.stderr
    shutil.copyfile(user, gen / "counter" / "counter" / "node.py")
    ws = root / f"ws_{name}"
    ws.mkdir()
    ok, tail, _ = build(venv, gen, ws)
    assert ok, f"{iface.name} did not build:\n{tail}"
    return ws


@pytest.fixture(scope="module")
def run(ros_venv: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    root = tmp_path_factory.mktemp("handover")
    old_iface, new_iface = ROOT / "examples" / "counter.iface", ROOT / "examples" / "counter_v2.iface"
    ws_old = _component(ros_venv, old_iface, DATA / "counter_node.py", root, "old")
    ws_new = _component(ros_venv, new_iface, DATA / "counter_v2_node.py", root, "new")
    text = new_iface.read_text(encoding="utf-8")
    variants = {
        "no_service_iface": text.replace('provides Reset on "/counter/reset"\n', ""),
        "retyped_iface": text.replace("    i64 count\n", "    string count\n"),
        "other_hash_iface": text.replace("    bool publish_parity = true\n",
                                         "    bool publish_parity = true\n    i32 spare = 0\n"),
    }
    for name, body in variants.items():
        assert body != text, name
        (root / f"{name}.iface").write_text(body, encoding="utf-8")
    package = ws_new / "install" / "counter"
    unsigned = root / "unsigned" / "counter"
    shutil.copytree(package, unsigned)
    store = root / "store"
    store.mkdir()
    pub, _ = keygen(root / "trusted.key")
    shutil.copy(pub, store / "trusted.pub")
    sign(package, root / "trusted.key")
    foreign = root / "foreign" / "counter"
    shutil.copytree(unsigned, foreign)
    keygen(root / "foreign.key")
    sign(foreign, root / "foreign.key")
    env_old = environment(ros_venv, ws_old, root / "ros-log")
    env_new = environment(ros_venv, ws_new, root / "ros-log")
    env_new["ROS_DOMAIN_ID"] = env_old["ROS_DOMAIN_ID"]
    config = {"python": sys.executable, "ros_python": str(ros_venv / "bin" / "python"),
              "old_iface": str(old_iface), "new_iface": str(new_iface), "env_old": env_old, "env_new": env_new,
              "store": str(store), "package": str(package), "unsigned_package": str(unsigned),
              "foreign_package": str(foreign), **{k: str(root / f"{k}.iface") for k in variants}}
    (root / "config.json").write_text(json.dumps(config))
    out, log = root / "result.json", root / "driver.log"
    code = run_bounded([str(ros_venv / "bin" / "python"), str(DRIVER), str(root / "config.json"), "--out", str(out),
                        "--logs", str(root / "logs")], env_new, 600, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "logs")}
    return steps


@pytest.mark.parametrize("step", STEPS)
def test_handover(run: dict[str, Any], step: str) -> None:
    info = run["_run"]
    if step not in run:
        tail = Path(info["log"]).read_text(errors="replace")[-3000:] if Path(info["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {info['code']}; logs in {info['logs']}):\n{tail}")
    assert run[step]["ok"], f"{step}: {run[step]['detail']} (logs in {info['logs']})"


def test_without_rclpy_handover_says_so_in_one_line(tmp_path: Path) -> None:
    env = {k: v for k, v in __import__("os").environ.items() if k != "PYTHONPATH"}
    done = subprocess.run([sys.executable, "-m", "iface", "handover", "/a", "/b", "--old", "x.iface", "--new",
                           "y.iface"], capture_output=True, text=True, timeout=60, env=env, check=False)
    try:
        import rclpy  # noqa: F401
    except ImportError:
        assert done.returncode == 2
        assert done.stderr.count("\n") == 1 and "rclpy cannot be imported" in done.stderr, done.stderr
    else:  # pragma: no cover - rclpy in the test environment itself
        pytest.skip("rclpy is importable here")
