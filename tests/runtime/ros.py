"""Finding the ROS 2 runtime, building generated packages with it, and its environment for processes.

The runtime is the venv that ``../shared/ros2-runtime/setup.sh VENV`` makes: ``IFACE_ROS2_VENV``,
else ``/root/.cache/ros2-runtime`` when it exists. Without it the ROS tests skip, saying why.
Builds use ``ros2-runtime/build.sh`` (``IFACE_ROS2_SHARED``, else ``../shared`` beside the
clone, else ``/work/shared``) and fall back to the venv's colcon with the same arguments.

The packages every component shares (``iface_msgs``, ``iface_runtime_py``: ``SHARED_PACKAGES``) are
built once per test process, in a workspace of their own that the component workspaces are built
on (colcon's underlay: sourcing a component workspace sources it too), so that each scenario does
not compile the protocol's type supports again.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import IO

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).parent / "data"
DEFAULT_VENV = Path("/root/.cache/ros2-runtime")
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
    for candidate in (os.environ.get("IFACE_ROS2_SHARED"), ROOT.parent / "shared", "/work/shared"):
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


#: Packages ``generate`` writes beside every component, built once per process (see the module's doc).
SHARED_PACKAGES = ("iface_msgs", "iface_runtime_py")
_shared_built: dict[str, Path] = {}


def _digest(generated: Path, names: list[str]) -> str:
    h = hashlib.sha256()
    for name in names:
        for path in sorted((generated / name).rglob("*")):
            if path.is_file():
                h.update(path.relative_to(generated).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def shared_underlay(venv: Path, generated: Path, near: Path) -> tuple[Path | None, str]:
    """The workspace with the shared packages found in ``generated`` built (once per content); None, why on failure."""
    names = [n for n in SHARED_PACKAGES if (generated / n / "package.xml").is_file()]
    if not names:
        return None, ""
    key = _digest(generated, names)
    if key in _shared_built:
        return _shared_built[key], ""
    src = near.parent / f"iface-shared-{key[:12]}" / "gen"
    shutil.rmtree(src.parent, ignore_errors=True)
    for name in names:
        shutil.copytree(generated / name, src / name)
    ws = src.parent / "ws"
    ws.mkdir()
    ok, tail, _ = _build(venv, src, ws, None)
    if not ok:
        return None, tail
    _shared_built[key] = ws
    return ws, ""


def build(venv: Path, generated: Path, workspace: Path) -> tuple[bool, str, float]:
    """Build every package under ``generated`` into ``workspace``: (ok, last lines, seconds).

    The shared packages among them are built once per process and used as the workspace's underlay.
    """
    start = time.monotonic()
    underlay, why = shared_underlay(venv, generated, workspace)
    if why:
        return False, why, time.monotonic() - start
    if underlay is not None:
        own = workspace / "gen-own"
        shutil.rmtree(own, ignore_errors=True)
        shutil.copytree(generated, own, ignore=lambda folder, names: [n for n in names if Path(folder) == generated
                                                                     and n in SHARED_PACKAGES])
        generated = own
    ok, tail, _ = _build(venv, generated, workspace, underlay)
    return ok, tail, time.monotonic() - start


def _build(venv: Path, generated: Path, workspace: Path, underlay: Path | None) -> tuple[bool, str, float]:
    start = time.monotonic()
    shared = shared_dir()
    env = environment(venv, underlay)
    if shared is not None:
        cmd = ["bash", str(shared / "ros2-runtime" / "build.sh"), str(generated), str(workspace)]
    else:
        src = workspace / "src"
        shutil.rmtree(src, ignore_errors=True)
        shutil.copytree(generated, src)
        cmd = ["colcon", "--log-base", "log", "build", "--base-paths", "src", "--build-base", "build",
               "--install-base", "install", "--event-handlers", "console_direct-", "--cmake-args",
               f"-DPython3_EXECUTABLE={venv}/bin/python", "-DBUILD_TESTING=OFF"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=1200, env=env, cwd=workspace, check=False)
    tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-25:])
    return done.returncode == 0, tail, time.monotonic() - start


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
