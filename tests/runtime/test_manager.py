"""End to end: `iface-lsp manager` keeps a system up, keeps its state and replaces parts; `iface-lsp system` asks it.

The system (a room sensor with a standby, a thermostat after it, a spare sensor) is generated from examples/ with
the tests' user modules (tests/runtime/data/*_node.py: each dies on activate when a flag file
names its node), built in the session's one workspace (conftest.py), and run on loopback.
NEW for the replacements is a signed copy of the thermostat's install folder (an equivalent
interface: a fix of its code), an unsigned copy, an incompatible interface, and two other
implementations built each in a workspace of its own and signed: thermostat_pro (another
component, package and executable; the interface package thermostat_msgs, as the thermostat's)
and thermostat_eco (with its own interface package, thermostat_eco_msgs). drive_manager.py runs
the scenario in order (every wait bounded, every process stopped by its own handle). Skipped,
saying why, without the runtime.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from iface.operate.trust import keygen, sign

from ..ros_harness.ros import HARNESS, ROOT, build, environment, run_bounded
from ..ros_harness.systems import generate_pro

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

DRIVER = HARNESS / "drive_manager.py"
STEPS = [
    "up: every instance active in order, status with its hash (json, html)",
    "snapshot: on request, and per the instance's period",
    "kill -9 of an instance: active again with its last snapshot, restart counted",
    "kill -9 of the manager: a new one manages every instance again, none started twice",
    "replace refused by compat: nothing changes",
    "replace refused by trust: nothing changes",
    "replace rolled back when NEW crashes on activate: OLD active with its state",
    "replace accepted: NEW active with OLD's state",
    "replace by another implementation: NEW's package and executable run, with OLD's state",
    "kill -9 of NEW: the manager restarts NEW (not OLD) with its state",
    "kill -9 of the manager: a new one adopts NEW",
    "replace by another implementation with an interface package of another name",
    "kill -9 of an instance with a standby: its standby is the instance, with its state; another follows",
    "a crash loop stops at the intensity limit and is reported",
    "SIGTERM: down in reverse order, exit 0",
    "a manager started again runs NEW, with its state",
]
SYSTEM = """/** The manager tests' system. */
system test_room version "1.0.0"
include "room_sensor.iface"
include "thermostat.iface"

instance sensor : room_sensor (standby = "true")
instance thermostat : thermostat (restart = "on-failure", snapshot = "1s", after = "sensor")
instance spare : room_sensor
"""


def _other(ros_venv: Path, sysdir: Path, root: Path, key: Path, component: str, interface_package: str
           ) -> dict[str, str]:
    """Another implementation of the thermostat, built in a workspace of its own and signed: what the driver needs."""
    gen, ws = root / f"gen_{component}", root / f"ws_{component}"
    iface = generate_pro(sysdir, gen, component, interface_package)
    ws.mkdir()
    ok, tail, _ = build(ros_venv, gen, ws)
    assert ok, f"{component} did not build:\n{tail}"
    signed = root / f"signed_{component}" / "install"
    shutil.copytree(ws / "install", signed)  # a copy: the cached packages are read-only
    package = signed / component
    sign(package, key)
    return {"iface": str(iface), "package": str(package), "component": component, "hash": _hash(iface),
            "exe": str(package / "lib" / component / component)}


def _hash(path: Path) -> str:
    done = subprocess.run([sys.executable, "-m", "iface", "hash", str(path)], capture_output=True, text=True,
                          timeout=60, check=True)
    return done.stdout.strip()


@pytest.fixture(scope="module")
def run(ros_workspace: Any, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    ros_venv, ws = ros_workspace.venv, ros_workspace.path
    root = tmp_path_factory.mktemp("manager")
    sysdir = root / "system"
    sysdir.mkdir()
    for name in ("room_sensor", "thermostat"):
        shutil.copy(ROOT / "examples" / f"{name}.iface", sysdir)
    (sysdir / "test_room.iface").write_text(SYSTEM, encoding="utf-8")
    text = (sysdir / "thermostat.iface").read_text(encoding="utf-8")
    new_text = text.replace('version "1.0.0"', 'version "1.0.1"').replace(
        "/** Times the heater was switched. */", "/** Times the heater was switched (1.0.1: once per change). */")
    bad_text = text.replace("    i64 switches\n", "    string switches\n")
    assert new_text != text and bad_text != text
    (sysdir / "thermostat_new.iface").write_text(new_text, encoding="utf-8")
    (sysdir / "thermostat_bad.iface").write_text(bad_text, encoding="utf-8")
    for side in ("signed", "unsigned"):
        shutil.copytree(ws / "install", root / side / "install")  # copies: the cached packages are read-only
    store = root / "store"
    store.mkdir()
    pub, _ = keygen(root / "trusted.key")
    shutil.copy(pub, store / "trusted.pub")
    sign(root / "signed" / "install" / "thermostat", root / "trusted.key")
    pro = _other(ros_venv, sysdir, root, root / "trusted.key", "thermostat_pro", "thermostat_msgs")
    eco = _other(ros_venv, sysdir, root, root / "trusted.key", "thermostat_eco", "thermostat_eco_msgs")
    flags = root / "flags"
    flags.mkdir()
    env = environment(ros_venv, ws, root / "ros-log")
    env["IFACE_TEST_FLAGS"] = str(flags)
    config = {"python": sys.executable, "system": str(sysdir / "test_room.iface"), "state": str(root / "state"),
              "store": str(store), "package": str(root / "signed" / "install" / "thermostat"),
              "unsigned": str(root / "unsigned" / "install" / "thermostat"),
              "new_iface": str(sysdir / "thermostat_new.iface"), "bad_iface": str(sysdir / "thermostat_bad.iface"),
              "hashes": {"sensor": _hash(sysdir / "room_sensor.iface"), "spare": _hash(sysdir / "room_sensor.iface"),
                         "thermostat": _hash(sysdir / "thermostat.iface")},
              "pro": pro, "eco": eco, "own": str(root), "env": env}
    (root / "config.json").write_text(json.dumps(config))
    out, log = root / "result.json", root / "driver.log"
    code = run_bounded([str(ros_venv / "bin" / "python"), str(DRIVER), str(root / "config.json"), "--out", str(out),
                        "--logs", str(root / "logs")], env, 1200, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "logs")}
    return steps


@pytest.mark.parametrize("step", STEPS)
def test_manager(run: dict[str, Any], step: str) -> None:
    info = run["_run"]
    if step not in run:
        tail = Path(info["log"]).read_text(errors="replace")[-3000:] if Path(info["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {info['code']}; logs in {info['logs']}):\n{tail}")
    assert run[step]["ok"], f"{step}: {run[step]['detail']} (logs in {info['logs']})"


def test_without_ros_the_clients_say_so_and_exit_2(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(ROOT / "server")
    system = ROOT / "examples" / "living_room.iface"
    for args in (["manager", str(system)], ["system", "status", str(system)],
                 ["system", "snapshot", str(system)]):
        done = subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True, timeout=60,
                              env=env, check=False)
        try:
            import iface_msgs  # noqa: F401
        except ImportError:
            assert done.returncode == 2, (args, done.stderr)
            assert done.stderr.count("\n") == 1 and "cannot be imported" in done.stderr, done.stderr
        else:  # pragma: no cover - ROS sourced in the test environment itself
            pytest.skip("iface_msgs is importable here")


def test_usage_errors_exit_2_in_one_line(tmp_path: Path) -> None:
    bad = tmp_path / "bad.iface"
    bad.write_text("system broken version \"1\"\ninstance x : nothing\n", encoding="utf-8")
    system = ROOT / "examples" / "living_room.iface"
    cases = [
        (["system", "status", str(bad)], "bad.iface:"),
        (["system", "replace", str(system), "thermostat", "--new", str(tmp_path / "none.iface"), "--package",
          str(tmp_path)], "no such file"),
        (["system", "replace", str(system), "thermostat", "--new", str(bad), "--package", str(tmp_path), "--timeout",
          "0"], "--timeout must be more than 0"),
        (["manager", str(system), "--max-restarts", "0"], "--max-restarts must be at least 1"),
    ]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "server")}
    for args, expected in cases:
        done = subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True, timeout=60,
                              env=env, check=False)
        assert done.returncode == 2, (args, done.stdout, done.stderr)
        assert expected in done.stderr and "Traceback" not in done.stderr, done.stderr
