"""Finding the ROS 2 runtime, building generated packages with it, and its environment for processes.

The runtime is the venv that ``../shared/ros2-runtime/setup.sh [--distro RELEASE] VENV`` makes, one per
ROS 2 release (``RELEASES``): Kilted in ``IFACE_ROS2_VENV`` (else ``~/.cache/ros2-runtime``), Jazzy in
``IFACE_ROS2_VENV_JAZZY`` (else ``~/.cache/ros2-runtime-jazzy``). ``IFACE_ROS_DISTRO`` (``kilted``,
``jazzy`` or ``all``, the default) says which releases the tests run on. Without a release's venv its
tests skip, saying why.
Builds use ``ros2-runtime/build.sh`` (``IFACE_ROS2_SHARED``, else ``../shared`` beside the
clone) and fall back to the venv's colcon with the same arguments.

The packages every component shares (``iface_msgs``, ``iface_runtime_py``: ``SHARED_PACKAGES``) and
every interface package are built once per test process and content, each in a workspace of its own
that the component workspaces are built on (colcon's underlays: sourcing a component workspace
sources them too), so that the scenarios do not compile the same type supports again.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import IO

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
    if log_dir is not None:
        env["ROS_LOG_DIR"] = str(log_dir)
    return env


def generate(iface: Path, out: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    """``iface-lsp generate IFACE --target rclpy --out OUT`` (the real CLI)."""
    return subprocess.run([sys.executable, "-m", "iface", "generate", str(iface), "--target", "rclpy", "--out",
                           str(out), "-q", *extra], capture_output=True, text=True, timeout=120, check=False)


#: Packages ``generate`` writes beside every component; with every interface package, built once per process.
SHARED_PACKAGES = ("iface_msgs", "iface_runtime_py")
#: Workspaces of packages built before in this process, by the digest of their files and their dependencies'.
_reused: dict[str, Path] = {}
_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_DEPEND = re.compile(r"<(?:depend|build_depend|exec_depend|build_export_depend)>\s*([^<\s]+)\s*</")


def _digest(folder: Path) -> str:
    h = hashlib.sha256()
    for path in sorted(folder.rglob("*")):
        if path.is_file():
            h.update(path.relative_to(folder).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def _packages(generated: Path) -> dict[str, tuple[Path, set[str]]]:
    """Each package directly under ``generated``: its folder and what it depends on."""
    found: dict[str, tuple[Path, set[str]]] = {}
    for xml in sorted(generated.glob("*/package.xml")):
        text = xml.read_text(encoding="utf-8")
        name = _NAME.search(text)
        if name:
            found[name.group(1)] = (xml.parent, set(_DEPEND.findall(text)))
    return found


def _reusable(folder: Path, name: str) -> bool:
    """The shared packages and interface packages: the same files give the same build, whoever asks."""
    cmake = folder / "CMakeLists.txt"
    return name in SHARED_PACKAGES or (cmake.is_file() and "rosidl_generate_interfaces" in cmake.read_text("utf-8"))


def reused_underlays(venv: Path, generated: Path, near: Path) -> tuple[list[Path], set[str], str]:
    """The workspaces that hold the reusable packages of ``generated`` (built now when new), the names they cover.

    Each reusable package is built alone, on the workspaces of the generated packages it depends on,
    once per process and content: the protocol's type supports and a component's interface package
    are compiled once however many scenarios use them. On failure: no workspaces, why.
    """
    packages = _packages(generated)
    reusable = {n for n, (folder, _) in packages.items() if _reusable(folder, n)}
    changed = True
    while changed:  # a package on a generated dependency that is built with the component is built there too
        changed = False
        for name in sorted(reusable):
            if any(d in packages and d not in reusable for d in packages[name][1]):
                reusable.discard(name)
                changed = True
    if reusable == set(packages):  # the component workspace needs a package of its own
        return [], set(), ""
    keys: dict[str, str] = {}
    underlays: list[Path] = []
    pending = sorted(reusable)
    while pending:
        name = next(n for n in pending if all(d not in reusable or d in keys for d in packages[n][1]))
        pending.remove(name)
        folder, depends = packages[name]
        inner = sorted(d for d in depends if d in reusable)
        # the venv too: the same files built against another release are another build
        key = hashlib.sha256((str(venv) + _digest(folder) + "".join(keys[d] for d in inner)).encode()).hexdigest()
        keys[name] = key
        if key not in _reused:
            root = near.parent / f"iface-{name}-{key[:12]}"
            shutil.rmtree(root, ignore_errors=True)
            shutil.copytree(folder, root / "gen" / name)
            (root / "ws").mkdir()
            ok, tail, _ = _build(venv, root / "gen", root / "ws", [_reused[keys[d]] for d in inner])
            if not ok:
                return [], set(), f"{name}: {tail}"
            _reused[key] = root / "ws"
        underlays.append(_reused[key])
    return underlays, reusable, ""


def build(venv: Path, generated: Path, workspace: Path) -> tuple[bool, str, float]:
    """Build every package under ``generated`` into ``workspace``: (ok, last lines, seconds).

    The reusable packages among them (``reused_underlays``) come from workspaces built before, which
    ``workspace`` is built on (colcon's underlays: its ``install/setup.bash`` sources them too).
    """
    start = time.monotonic()
    underlays, taken, why = reused_underlays(venv, generated, workspace)
    if why:
        return False, why, time.monotonic() - start
    if taken:
        generated = own_packages(generated, workspace, taken)
    ok, tail, _ = _build(venv, generated, workspace, underlays)
    return ok, tail, time.monotonic() - start


def own_packages(generated: Path, workspace: Path, taken: set[str]) -> Path:
    """A copy of ``generated`` without the packages ``taken`` (those come from underlays), beside ``workspace``."""
    own = workspace / "gen-own"
    shutil.rmtree(own, ignore_errors=True)
    folders = {folder.name for name, (folder, _) in _packages(generated).items() if name in taken}
    shutil.copytree(generated, own, ignore=lambda folder, names: [n for n in names if Path(folder) == generated
                                                                 and n in folders])
    return own


def sourced(env: dict[str, str], workspaces: list[Path]) -> dict[str, str]:
    """``env`` with each workspace's ``install/setup.bash`` sourced on top, in order."""
    if not workspaces:
        return env
    script = "set +u; " + " && ".join(f'. "{ws}/install/setup.bash" >/dev/null' for ws in workspaces)
    dump = subprocess.run(["bash", "-c", script + " && env -0"], capture_output=True, timeout=60, check=True,
                          env=env).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


def _build(venv: Path, generated: Path, workspace: Path, underlays: list[Path]) -> tuple[bool, str, float]:
    start = time.monotonic()
    shared = shared_dir()
    env = sourced(environment(venv), underlays)
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
