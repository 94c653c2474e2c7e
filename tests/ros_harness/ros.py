"""Finding the ROS 2 runtime, building generated packages with it, and its environment for processes.

The runtime is the venv that ``../shared/ros2-runtime/setup.sh VENV`` makes: ``IFACE_ROS2_VENV``,
else ``~/.cache/ros2-runtime`` when it exists. Without it the ROS tests skip, saying why.
Builds use ``ros2-runtime/build.sh`` (``IFACE_ROS2_SHARED``, else ``../shared`` beside the
clone) and fall back to the venv's colcon with the same arguments.

``build`` takes every package from the test cache (``workspaces.py``, ``cache.py``): each is built
once per content on this machine, in a workspace of its own on those of the packages it depends on.
"""

from __future__ import annotations

import fcntl
import os
import random
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import IO

ROOT = Path(__file__).resolve().parents[2]
#: The test data of the runtime tests: interfaces and the user code put into generated packages.
DATA = ROOT / "tests" / "runtime" / "data"
#: This folder: the drivers (``drive_*.py``) run with the ROS runtime's Python.
HARNESS = Path(__file__).parent
DEFAULT_VENV = Path.home() / ".cache" / "ros2-runtime"
LOOPBACK = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST", "ROS_LOCALHOST_ONLY": "1"}
NOT_LOOPBACK = ("ROS_STATIC_PEERS", "ROS_DISCOVERY_SERVER", "FASTRTPS_DEFAULT_PROFILES_FILE",
                "FASTDDS_DEFAULT_PROFILES_FILE", "ROS2_EASY_MODE")


def runtime_venv() -> tuple[Path | None, str]:
    """The runtime venv, or None and why it is not there."""
    given = os.environ.get("IFACE_ROS2_VENV")
    venv = Path(given) if given else DEFAULT_VENV
    if not (venv / "ros2-env.sh").is_file():
        where = f"IFACE_ROS2_VENV={given}" if given else f"{DEFAULT_VENV} (the default; set IFACE_ROS2_VENV)"
        return None, (f"no ROS 2 runtime at {where}: install it with `bash ../shared/ros2-runtime/setup.sh VENV` "
                      "(.ci/run does)")
    return venv, ""


def shared_dir() -> Path | None:
    """The folder that holds ros2-runtime/ and ros2-build/, if any."""
    for candidate in (os.environ.get("IFACE_ROS2_SHARED"), ROOT.parent / "shared"):
        if candidate and (Path(candidate) / "ros2-runtime" / "build.sh").is_file():
            return Path(candidate)
    return None


DOMAIN_LOCKS = Path(tempfile.gettempdir()) / "iface-ros-domains"
_held: dict[int, IO[str]] = {}


def free_domain() -> int:
    """A ROS_DOMAIN_ID that no other test run on this machine holds, kept until this process ends.

    Two test runs side by side start nodes of the same names; a shared domain would mix them up.
    Each run takes a new domain per scenario while one is free (1..101 stay clear of the ephemeral
    ports), then reuses its own oldest one.
    """
    DOMAIN_LOCKS.mkdir(exist_ok=True)
    free = [d for d in range(1, 102) if d not in _held]
    random.SystemRandom().shuffle(free)
    for domain in free:
        handle = open(DOMAIN_LOCKS / f"{domain}.lock", "a")  # noqa: SIM115 - held until the process ends
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            continue
        _held[domain] = handle
        return domain
    oldest = next(iter(_held), random.SystemRandom().randint(1, 101))
    if oldest in _held:
        _held[oldest] = _held.pop(oldest)
    return oldest


def environment(venv: Path, workspace: Path | None = None, log_dir: Path | None = None) -> dict[str, str]:
    """The environment of ``ros2-env.sh`` (and the workspace's setup), confined to loopback, in a domain of its own."""
    script = f'set +u; . "{venv}/ros2-env.sh" >/dev/null'
    if workspace is not None:
        script += f' && . "{workspace}/install/setup.bash" >/dev/null'
    base = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "ROS_DOMAIN_ID")}
    dump = subprocess.run(["bash", "-c", script + " && env -0"], capture_output=True, timeout=60, check=True,
                          env=base).stdout
    env = dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)
    env.update(LOOPBACK)
    # This checkout's iface first: a worktree's tests must not run another checkout's installed copy.
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT / "server"), env.get("PYTHONPATH", "")) if p)
    for key in NOT_LOOPBACK:
        env.pop(key, None)
    env["ROS_DOMAIN_ID"] = str(free_domain())
    if log_dir is not None:
        env["ROS_LOG_DIR"] = str(log_dir)
    return env


def generate(iface: Path, out: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    """``iface-lsp generate IFACE --target rclpy --out OUT`` (the real CLI)."""
    return subprocess.run([sys.executable, "-m", "iface", "generate", str(iface), "--target", "rclpy", "--out",
                           str(out), "-q", *extra], capture_output=True, text=True, timeout=120, check=False)


def build(venv: Path, generated: Path, workspace: Path, *, underlays: Sequence[Path] = (),
          cpp: bool = False) -> tuple[bool, str, float]:
    """Build every package under ``generated`` and make ``workspace`` their workspace: (ok, why not, seconds).

    Each package comes from the test cache, built there once per content (``workspaces.py``):
    ``workspace/install/setup.bash`` sources them, ``workspace/install/PKG`` is each package (read-only).
    ``underlays``: workspaces made by ``build`` that the packages may depend on; ``cpp``: build the
    C++ packages against rclcpp.
    """
    from .workspaces import build as build_cached

    return build_cached(venv, generated, workspace, underlays=underlays, cpp=cpp)


def sourced(env: dict[str, str], workspaces: Sequence[Path], script: str = "setup.bash") -> dict[str, str]:
    """``env`` with each workspace's ``install/SCRIPT`` sourced on top, in order."""
    if not workspaces:
        return env
    script = "set +u; " + " && ".join(f'. "{ws}/install/{script}" >/dev/null' for ws in workspaces)
    dump = subprocess.run(["bash", "-c", script + " && env -0"], capture_output=True, timeout=60, check=True,
                          env=env).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


def run_bounded(cmd: list[str], env: dict[str, str], timeout: float, log: Path) -> int | None:
    """Run ``cmd`` in a session of its own, output to ``log``; on timeout stop it (and what it started)."""
    with open(log, "w") as out:
        proc = subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            return proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, 15)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, 9)
                proc.wait(timeout=15)
            return None
