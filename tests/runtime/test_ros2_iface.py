"""``ros2 iface``: iface's ros2cli extension, installed with the package, run by the real ``ros2`` command.

The package is built into a wheel from this checkout and installed with ``pip install --no-deps --target DIR``
(once per content of the sources: a test cache entry);
``DIR`` goes first on the ``PYTHONPATH`` of the ``ros2`` process (the runtime's ``ros2``, with the runtime's
Python), and iface's own requirements (jinja2, pygls…) are found where this Python has them, after the runtime's
packages: what ``pip install .`` into the Python that runs ``ros2`` gives a user. This checkout's ``server/``
is not on that path, so it is the installed copy that runs.

Each verb is compared with the ``iface-lsp`` command it stands for, on loopback: the hand-written nodes of
``data/live/nodes.py`` for import and verify, and a component manager of a two-instance system (the
session's workspace) for status, snapshot and replace. Every wait is bounded; every process started here is
stopped by its own handle.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from importlib import metadata
from pathlib import Path
from typing import Any

import pytest

from ..ros_harness import cache
from ..ros_harness.ros import ROOT, at_once, environment
from .conftest import Workspace
from .test_live import FAULTS, LIVE, STEP, _start, _stop, _wait_line

VERBS = ["import", "replace", "snapshot", "status", "verify"]
SYSTEM = """/** The ros2 iface tests' system. */
system ros2_room version "1.0.0"
include "room_sensor.iface"
include "thermostat.iface"

instance sensor : room_sensor
instance thermostat : thermostat (after = "sensor")
"""


def _requirement_dirs(dist_info: Path) -> list[str]:
    """The folders where this Python finds iface's requirements (read from the installed METADATA)."""
    found: list[str] = []
    for line in (dist_info / "METADATA").read_text(encoding="utf-8").splitlines():
        if not line.startswith("Requires-Dist:") or "extra ==" in line:
            continue
        name = line.split(":", 1)[1].strip().split(";")[0]
        for stop in "<>=!~[ (":
            name = name.split(stop)[0]
        where = str(metadata.distribution(name).locate_file(""))
        if where not in found:
            found.append(where)
    return found


def _install(folder: Path) -> str | None:
    """Build a wheel of this checkout and install it into ``folder/site`` (a test cache entry); None, or why not."""
    src = folder / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    shutil.copytree(ROOT / "server", src / "server",
                    ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build"))
    wheel = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                            "-w", str(folder / "wheel"), str(src)], capture_output=True, text=True, timeout=300,
                           check=False)
    shutil.rmtree(src)
    if wheel.returncode != 0:
        return f"pip wheel: {wheel.stdout}{wheel.stderr}"
    (whl,) = (folder / "wheel").glob("iface-*.whl")
    done = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(folder / "site"),
                           str(whl)], capture_output=True, text=True, timeout=300, check=False)
    return None if done.returncode == 0 else f"pip install: {done.stdout}{done.stderr}"


@pytest.fixture(scope="module")
def installed() -> tuple[Path, list[str]]:
    """iface installed from a wheel of this checkout into a folder of its own; that folder and the requirements'.

    The folder is a test cache entry (ros_harness/cache.py) under the key of the sources, pip and this Python:
    built once per content of ``server/``, not once per run.
    """
    pip = subprocess.run([sys.executable, "-m", "pip", "--version"], capture_output=True, text=True, timeout=60,
                         check=True).stdout.split(" from ")[0]
    sources = [cache.digest_tree(ROOT / "server" / "iface"),
               *(cache.digest_file(ROOT / name) for name in ("pyproject.toml", "README.md"))]
    key = cache.key_of("iface wheel, pip install --target", sys.version, pip, *sources)
    target = cache.entry(key, f"iface installed from a wheel of {ROOT} ({pip}, Python {sys.version.split()[0]})",
                         _install).path / "site"
    (dist_info,) = target.glob("iface-*.dist-info")
    return target, _requirement_dirs(dist_info)


def ros2_env(env: dict[str, str], installed: tuple[Path, list[str]]) -> dict[str, str]:
    """``env`` for the ``ros2`` command: the installed iface first, the runtime's path, iface's requirements last."""
    target, requirements = installed
    own = str(ROOT / "server")
    path = [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p and p != own]
    return {**env, "PYTHONPATH": os.pathsep.join([str(target), *path, *requirements])}


def ros2(env: dict[str, str], *args: str, cwd: Path | None = None,
         extra: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    """The runtime's ``ros2`` command."""
    exe = shutil.which("ros2", path=env["PATH"])
    assert exe is not None, "no ros2 on the runtime's PATH"
    return subprocess.run([exe, *args], env={**env, **(extra or {})}, cwd=cwd, capture_output=True, text=True,
                          timeout=STEP, check=False)


def iface_lsp(env: dict[str, str], *args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """``iface-lsp`` (this checkout's) in the same environment."""
    return subprocess.run([sys.executable, "-m", "iface", *args], env=env, cwd=cwd, capture_output=True, text=True,
                          timeout=STEP, check=False)


@pytest.fixture(scope="module")
def live(ros_workspace: Workspace, installed: tuple[Path, list[str]],
         tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Any]]:
    """The hand-written nodes of data/live/nodes.py in a domain of their own; environments for both commands."""
    root = tmp_path_factory.mktemp("ros2-iface-live")
    env = environment(ros_workspace.venv, ros_workspace.path, root / "ros-log")
    proc = _start([sys.executable, str(LIVE / "nodes.py")], env, root / "nodes.log")
    try:
        _wait_line(root / "nodes.log", "ready", proc, STEP)
        yield {"env": env, "ros2": ros2_env(env, installed), "root": root}
    finally:
        _stop([proc])


def complete(env: dict[str, str], line: str, root: Path) -> list[str]:
    """What argcomplete offers for ``line`` (the cursor at its end), as bash asks ``ros2``."""
    out = root / "completion.out"
    done = ros2(env, extra={"_ARGCOMPLETE": "1", "_ARGCOMPLETE_IFS": "\n", "COMP_LINE": line,
                            "COMP_POINT": str(len(line)), "_ARGCOMPLETE_STDOUT_FILENAME": str(out)})
    assert done.returncode == 0, done.stderr
    return sorted(w.strip() for w in out.read_text().splitlines() if w.strip())


def test_ros2_lists_iface_and_iface_lists_its_verbs(live: dict[str, Any]) -> None:
    top = ros2(live["ros2"], "--help")
    assert top.returncode == 0, top.stderr
    assert any(line.split()[:1] == ["iface"] for line in top.stdout.splitlines()), top.stdout
    group = ros2(live["ros2"], "iface", "--help")
    assert group.returncode == 0, group.stderr
    listed = [line.split()[0] for line in group.stdout.split("Commands:", 1)[1].splitlines()
              if line.startswith("  ") and not line.strip().startswith("Call")]
    assert listed == VERBS, group.stdout
    for verb in VERBS:
        usage = ros2(live["ros2"], "iface", verb, "--help")
        assert usage.returncode == 0 and f"usage: ros2 iface {verb}" in usage.stdout, usage.stdout + usage.stderr
        assert "--spin-time" in usage.stdout and "--debug" in usage.stdout
        assert ("--no-daemon" in usage.stdout) == (verb in ("import", "verify")), usage.stdout
    alone = ros2(live["ros2"], "iface")  # as `ros2 lifecycle`: the group's help, exit 0
    assert alone.returncode == 0 and "verify" in alone.stdout, alone.stdout + alone.stderr


def test_ros2_iface_verify_finds_the_planted_faults_as_iface_lsp_verify_does(live: dict[str, Any]) -> None:
    """Issue 36: the same output and exit code, text and json; --spin-time is --timeout; no daemon started."""
    folder = live["root"] / "faults"
    folder.mkdir()
    for name, text in FAULTS.items():
        (folder / name).write_text(text, encoding="utf-8")
    files = ["talker.iface", "listener.iface", "ghost.iface"]
    daemon = ros2(live["ros2"], "daemon", "status").stdout
    # each run waits out the missing node's grace period: the four at once
    runs = at_once(*(call for fmt in ("text", "json") for call in (
        lambda fmt=fmt: ros2(live["ros2"], "iface", "verify", *files, "--format", fmt, "--spin-time", "60",
                             "--no-daemon", cwd=folder),
        lambda fmt=fmt: iface_lsp(live["env"], "verify", *files, "--format", fmt, "--timeout", "60", cwd=folder))))
    for ours, theirs in (runs[:2], runs[2:]):
        assert (ours.returncode, theirs.returncode) == (1, 1), ours.stderr + theirs.stderr
        assert ours.stdout == theirs.stdout, (ours.stdout, theirs.stdout)
        assert ours.stderr == theirs.stderr == ""
    codes = sorted(f["code"] for f in json.loads(ours.stdout)["findings"])
    assert codes == ["live-endpoint-undeclared", "live-node-missing", "live-param-out-of-range",
                     "live-qos-incompatible", "live-type-mismatch", "live-type-mismatch"], ours.stdout
    if "not running" in daemon:  # iface neither asks nor starts the ROS 2 daemon
        assert "not running" in ros2(live["ros2"], "daemon", "status").stdout


def test_ros2_iface_verify_usage_errors_say_so_in_one_line_and_exit_2(live: dict[str, Any]) -> None:
    cases = [(["verify", "none.iface"], "ros2 iface verify: none.iface: no such file"),
             (["verify", str(ROOT / "examples" / "counter.iface"), "--spin-time", "0"],
              "ros2 iface verify: --timeout must be more than 0 seconds"),
             (["import"], "ros2 iface import: name the nodes to import (NODE...), or --all")]
    for args, line in cases:
        done = ros2(live["ros2"], "iface", *args, cwd=live["root"])
        assert done.returncode == 2 and done.stderr == line + "\n", (args, done.stdout, done.stderr)
    parse = ros2(live["ros2"], "iface", "verify", "--format", "yaml", "x.iface")
    assert parse.returncode == 2 and "invalid choice" in parse.stderr


def test_ros2_iface_import_writes_what_iface_lsp_import_from_node_writes(live: dict[str, Any]) -> None:
    nodes = ["/live/talker", "/live/listener", "/live/lifer"]
    ours, theirs = live["root"] / "import-ros2", live["root"] / "import-iface-lsp"
    ours.mkdir()
    theirs.mkdir()
    a, b = at_once(
        lambda: ros2(live["ros2"], "iface", "import", *nodes, "--system", "room", "--out", "out", "--spin-time", "60",
                     "--no-daemon", cwd=ours),
        lambda: iface_lsp(live["env"], "import", "--from", "node", *nodes, "--system", "room", "--out", "out",
                          "--timeout", "60", cwd=theirs))
    assert (a.returncode, b.returncode) == (0, 0), a.stderr + b.stderr
    assert a.stdout == b.stdout and a.stdout.count("wrote out/") == 4, (a.stdout, b.stdout)
    written = sorted(p.name for p in (ours / "out").iterdir())
    assert written == sorted(p.name for p in (theirs / "out").iterdir()) == [
        "lifer.iface", "listener.iface", "room.iface", "talker.iface"]
    for name in written:
        assert (ours / "out" / name).read_bytes() == (theirs / "out" / name).read_bytes(), name
    missing = ros2(live["ros2"], "iface", "import", "/live/nobody", "--spin-time", "2", "--out", "none",
                   cwd=live["root"])
    assert missing.returncode == 1 and "ros2 iface import: /live/nobody: no such node" in missing.stderr


def test_argcomplete_completes_verbs_options_nodes_and_instances(live: dict[str, Any], tmp_path: Path) -> None:
    env = live["ros2"]
    assert complete(env, "ros2 if", tmp_path) == ["iface"]
    assert complete(env, "ros2 iface ", tmp_path) == VERBS
    assert "--spin-time" in complete(env, "ros2 iface verify --", tmp_path)
    assert complete(env, "ros2 iface import --no-daemon --spin-time 5 /live/", tmp_path) == [
        "/live/lifer", "/live/listener", "/live/talker"]
    system = tmp_path / "ros2_room.iface"
    system.write_text(SYSTEM, encoding="utf-8")
    for name in ("room_sensor", "thermostat"):
        shutil.copy(ROOT / "examples" / f"{name}.iface", tmp_path)
    assert complete(env, f"ros2 iface snapshot {system} ", tmp_path) == ["sensor", "thermostat"]
    assert complete(env, f"ros2 iface replace {system} th", tmp_path) == ["thermostat"]


def test_without_a_manager_the_manager_verbs_exit_2_in_one_line(live: dict[str, Any], tmp_path: Path) -> None:
    system = ROOT / "examples" / "living_room.iface"
    cases = (["status", str(system)], ["snapshot", str(system), "sensor"],
             ["replace", str(system), "thermostat", "--new", str(ROOT / "examples" / "thermostat.iface"),
              "--package", str(tmp_path)])
    # each one looks for a manager for its whole spin time: the three at once
    answers = at_once(*(lambda args=args: ros2(live["ros2"], "iface", *args, "--spin-time", "2") for args in cases))
    for args, done in zip(cases, answers, strict=True):
        assert done.returncode == 2, (args, done.stdout, done.stderr)
        assert done.stderr.count("\n") == 1 and done.stderr.startswith(f"ros2 iface {args[0]}: "), done.stderr
        assert "iface-lsp manager" in done.stderr  # how to start one


# ---- with a component manager ---------------------------------------------------------------------------------


def _status(env: dict[str, str], system: Path) -> dict[str, Any] | None:
    done = iface_lsp(env, "system", "status", str(system), "--format", "json", "--manager-timeout", "5")
    return json.loads(done.stdout) if done.returncode in (0, 1) and done.stdout else None


@pytest.fixture(scope="module")
def managed(ros_workspace: Workspace, installed: tuple[Path, list[str]],
            tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Any]]:
    """``iface-lsp manager`` of a sensor and a thermostat (the session's workspace), every instance active."""
    root = tmp_path_factory.mktemp("ros2-iface-manager")
    sysdir = root / "system"
    sysdir.mkdir()
    for name in ("room_sensor", "thermostat"):
        shutil.copy(ROOT / "examples" / f"{name}.iface", sysdir)
    system = sysdir / "ros2_room.iface"
    system.write_text(SYSTEM, encoding="utf-8")
    env = environment(ros_workspace.venv, ros_workspace.path, root / "ros-log")
    state = root / "state"
    log = open(root / "manager.log", "wb")  # noqa: SIM115 - closed below
    manager = subprocess.Popen([sys.executable, "-m", "iface", "manager", str(system), "--state-dir", str(state)],
                               env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        deadline = time.monotonic() + STEP
        status = None
        while time.monotonic() < deadline and manager.poll() is None:
            status = _status(env, system)
            if status and all(i["state"] == "active" for i in status["instances"]):
                break
            time.sleep(0.5)
        else:
            raise AssertionError(f"the manager did not bring the system up: {status}\n"
                                 + (root / "manager.log").read_text(errors="replace")[-3000:])
        yield {"env": env, "ros2": ros2_env(env, installed), "system": system, "root": root,
               "package": ros_workspace.path / "install" / "thermostat"}
    finally:
        _stop_manager(manager, state, root)
        log.close()


def _stop_manager(manager: subprocess.Popen[bytes], state: Path, root: Path) -> None:
    """SIGTERM: the manager takes the instances down in reverse order and exits; whatever is left is killed."""
    if manager.poll() is None:
        manager.send_signal(signal.SIGTERM)
    try:
        manager.wait(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(manager.pid, signal.SIGKILL)
        manager.wait(timeout=15)
    for record in sorted((state / "processes").glob("*.json")) if (state / "processes").is_dir() else []:
        pid = int(json.loads(record.read_text()).get("pid", 0))
        try:  # only a process of this test (its ROS_LOG_DIR is under root)
            if pid and str(root).encode() in Path(f"/proc/{pid}/environ").read_bytes():
                os.killpg(pid, signal.SIGKILL)
        except OSError:
            pass


def test_ros2_iface_status_and_snapshot_answer_as_iface_lsp_system_does(managed: dict[str, Any]) -> None:
    system, sysdir = managed["system"], managed["system"].parent
    for fmt in ("text", "json"):
        ours, theirs = at_once(
            lambda fmt=fmt: ros2(managed["ros2"], "iface", "status", system.name, "--format", fmt, cwd=sysdir),
            lambda fmt=fmt: iface_lsp(managed["env"], "system", "status", system.name, "--format", fmt, cwd=sysdir))
        assert (ours.returncode, theirs.returncode) == (0, 0), ours.stderr + theirs.stderr
        assert ours.stdout == theirs.stdout, (ours.stdout, theirs.stdout)
    saved = ros2(managed["ros2"], "iface", "snapshot", system.name, "--spin-time", "30", cwd=sysdir)
    assert saved.returncode == 0, saved.stdout + saved.stderr
    answer = json.loads(saved.stdout)
    assert answer["success"] and len(answer["files"]) == 2 and all(Path(f).is_file() for f in answer["files"])
    after = json.loads(ros2(managed["ros2"], "iface", "status", system.name, "--format", "json", cwd=sysdir).stdout)
    assert all(i["last_snapshot"] for i in after["instances"]), after


def test_ros2_iface_replace_hands_an_instance_over_through_the_manager(managed: dict[str, Any]) -> None:
    """The thermostat replaced by its own package and interface (equivalent): one JSON record, exit 0."""
    system = managed["system"]
    before = {i["name"]: i for i in _status(managed["env"], system)["instances"]}  # type: ignore[index]
    done = ros2(managed["ros2"], "iface", "replace", str(system), "thermostat", "--new",
                str(system.parent / "thermostat.iface"), "--package", str(managed["package"]), "--spin-time", "30")
    assert done.returncode == 0, done.stdout + done.stderr
    record = json.loads(done.stdout)
    assert record["result"] == "replaced" and record["instance"] == "thermostat", record
    after = {i["name"]: i for i in _status(managed["env"], system)["instances"]}  # type: ignore[index]
    assert after["thermostat"]["state"] == "active" and after["thermostat"]["pid"] != before["thermostat"]["pid"]
    assert after["sensor"]["pid"] == before["sensor"]["pid"]
