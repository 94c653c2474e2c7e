"""Finding the ROS 2 runtime, building generated packages with it, and its environment for processes.

The runtime is the venv that ``../shared/ros2-runtime/setup.sh [--distro RELEASE] VENV`` makes, one per
ROS 2 release (``RELEASES``): Kilted in ``IFACE_ROS2_VENV`` (else ``~/.cache/ros2-runtime``), Jazzy in
``IFACE_ROS2_VENV_JAZZY`` (else ``~/.cache/ros2-runtime-jazzy``). ``IFACE_ROS_DISTRO`` (``kilted``,
``jazzy`` or ``all``, the default) says which releases the tests run on. Without a release's venv its
tests skip, saying why.
Builds use ``ros2-runtime/build.sh`` (``IFACE_ROS2_SHARED``, else ``../shared`` beside the
clone) and fall back to the venv's colcon with the same arguments.

``build`` takes every package from the test cache (``workspaces.py``, ``cache.py``): each is built
once per content on this machine, in a workspace of its own on those of the packages it depends on.
"""

from __future__ import annotations

import fcntl
import os
import random
import re
import subprocess
import tempfile
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import IO, TypeVar

T = TypeVar("T")
ROOT = Path(__file__).resolve().parents[2]
#: The test data of the runtime tests: interfaces and the user code put into generated packages.
DATA = ROOT / "tests" / "runtime" / "data"
#: This folder: the drivers (``drive_*.py``) run with the ROS runtime's Python.
HARNESS = Path(__file__).parent
#: The ROS 2 releases the tests run on, the first one the default (the C++ runtime is built for it only).
RELEASES = ("kilted", "jazzy")
#: Where each release's venv is: the variable that names it, and the folder without it.
VENV_VARIABLES = {"kilted": "IFACE_ROS2_VENV", "jazzy": "IFACE_ROS2_VENV_JAZZY"}
DEFAULT_VENVS = {"kilted": Path.home() / ".cache" / "ros2-runtime",
                 "jazzy": Path.home() / ".cache" / "ros2-runtime-jazzy"}
DEFAULT_VENV = DEFAULT_VENVS["kilted"]
#: The switch: which releases the tests run on.
DISTRO_VARIABLE = "IFACE_ROS_DISTRO"
LOOPBACK = {"ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST"}
NOT_LOOPBACK = ("ROS_STATIC_PEERS", "ROS_DISCOVERY_SERVER", "FASTRTPS_DEFAULT_PROFILES_FILE",
                "FASTDDS_DEFAULT_PROFILES_FILE", "ROS2_EASY_MODE")


def selected_releases() -> list[str]:
    """The releases ``IFACE_ROS_DISTRO`` names (``kilted``, ``jazzy``, ``all``; default all); ValueError for others."""
    given = os.environ.get(DISTRO_VARIABLE, "").strip().lower()
    if given in ("", "all"):
        return list(RELEASES)
    chosen = [r.strip() for r in given.split(",") if r.strip()]
    unknown = [r for r in chosen if r not in RELEASES]
    if unknown or not chosen:
        raise ValueError(f"{DISTRO_VARIABLE}={given}: give {', '.join(RELEASES)} or all")
    return [r for r in RELEASES if r in chosen]


def release_of(venv: Path) -> str | None:
    """The release a runtime venv holds (``ROS_DISTRO`` of its ros2-env.sh), None when it is no runtime."""
    try:
        text = (venv / "ros2-env.sh").read_text(encoding="utf-8")
    except OSError:
        return None
    found = re.search(r"ROS_DISTRO=([a-z]+)", text)
    return found.group(1) if found else None


def runtime_venv(release: str = RELEASES[0]) -> tuple[Path | None, str]:
    """The runtime venv of ``release``, or None and why it is not there."""
    variable = VENV_VARIABLES[release]
    given = os.environ.get(variable)
    venv = Path(given) if given else DEFAULT_VENVS[release]
    where = f"{variable}={given}" if given else f"{venv} (the default; set {variable})"
    held = release_of(venv)
    if held is None:
        flag = "" if release == RELEASES[0] else f"--distro {release} "
        return None, (f"no ROS 2 {release.capitalize()} runtime at {where}: install it with `bash "
                      f"scripts/install-ros.sh` (or `bash ../shared/ros2-runtime/setup.sh {flag}VENV`; .ci/run does)")
    if held != release:
        return None, f"{where} holds ROS 2 {held}, not {release}"
    return venv, ""


def shared_dir() -> Path | None:
    """The folder that holds ros2-runtime/ and ros2-build/, if any."""
    for candidate in (os.environ.get("IFACE_ROS2_SHARED"), ROOT.parent / "shared"):
        if candidate and (Path(candidate) / "ros2-runtime" / "build.sh").is_file():
            return Path(candidate)
    return None


DOMAIN_LOCKS = Path(tempfile.gettempdir()) / "iface-ros-domains"
#: The most domains one process holds: a worker that runs many scenarios then reuses its own, and leaves the
#: rest of the 101 to the other workers and runs (a worker that took one per scenario held half of them, two
#: held them all, and a run started then took domains at random: shared).
MAX_HELD = 16
_held: dict[int, IO[str]] = {}


def free_domain() -> int:
    """A ROS_DOMAIN_ID that no other test run on this machine holds, kept until this process ends.

    Two test runs side by side start nodes of the same names; a shared domain would mix them up.
    Each process takes a new domain per scenario while one is free and it holds fewer than
    :data:`MAX_HELD` (1..101 stay clear of the ephemeral ports), then reuses its own oldest one.
    """
    DOMAIN_LOCKS.mkdir(exist_ok=True)
    free = [d for d in range(1, 102) if d not in _held] if len(_held) < MAX_HELD else []
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
    if env.get("ROS_DISTRO") == "jazzy":
        # Jazzy's rcl still reads it, and warns twice at every start (into each ros2 command's output too);
        # ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST alone confines Fast DDS 2.14 (../shared/ros2-runtime, Jazzy)
        env.pop("ROS_LOCALHOST_ONLY", None)
    else:
        env["ROS_LOCALHOST_ONLY"] = "1"  # Kilted's rcl ignores it; set for older tools
    # This checkout's iface first: a worktree's tests must not run another checkout's installed copy.
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT / "server"), env.get("PYTHONPATH", "")) if p)
    for key in NOT_LOOPBACK:
        env.pop(key, None)
    env["ROS_DOMAIN_ID"] = str(free_domain())
    # numpy (imported by every rclpy process) starts OpenBLAS's thread pool, whose threads spin before they
    # sleep: 0.11 CPU-s of each process's 0.70 (2026-11-30, a node's start). No ROS process here does BLAS.
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    if log_dir is not None:
        env["ROS_LOG_DIR"] = str(log_dir)
    return env


def generate(iface: Path, out: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    """``iface-lsp generate IFACE --target rclpy --out OUT`` (``extra``: more options, a later ``--target`` wins),
    in this process (``run_main``): what is tested here is what it writes; its process is tested in tests/core."""
    from tests.conftest import run_main

    return run_main("generate", str(iface), "--target", "rclpy", "--out", str(out), "-q", *extra)


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


def at_once(*calls: Callable[[], T]) -> list[T]:
    """Each call in a thread of its own, all at the same time; their results in the order given.

    For commands that spend their time waiting on the graph (discovery, a grace period for a missing node, a
    spin time): one after another their waits add up, at the same time they overlap. Each call bounds its own
    wait (``subprocess.run(timeout=...)``). Every call ends before this returns; when calls raised, the
    exception of the first of them (in the order given) is raised here.
    """
    with ThreadPoolExecutor(max_workers=len(calls)) as pool:
        futures = [pool.submit(call) for call in calls]
    return [f.result() for f in futures]
