"""Building generated C++ (rclcpp) packages with the ROS 2 runtime's rclcpp, for the container tests and benches.

rclcpp has no wheel: ``../shared/ros2-runtime/build-cpp.sh VENV`` builds it into ``VENV/cpp`` and writes
``cpp-env.sh``. ``rclcpp_env`` is the environment of ``ros2-env.sh`` and ``cpp-env.sh`` (None without
them); ``build_cpp`` runs colcon on a folder of generated packages as docs/targets.md says, every package
built there (a workspace of its own, as a user's: the container loads its libraries from it, and the trust
tests sign and change its install folder, which the test cache's read-only entries must never see).
"""

from __future__ import annotations

import shutil
import subprocess
import time
from pathlib import Path

from .workspaces import cpp_environment


def rclcpp_env(venv: Path) -> dict[str, str] | None:
    """The environment of ros2-env.sh and cpp-env.sh (rclcpp built by build-cpp.sh); None without rclcpp."""
    return cpp_environment(venv)


def missing_tools(env: dict[str, str]) -> list[str]:
    """The build tools C++ needs that are not on PATH."""
    return [tool for tool in ("cmake", "c++", "make") if shutil.which(tool, path=env.get("PATH")) is None]


def overlay(env: dict[str, str], ws: Path, script: str = "local_setup.bash") -> dict[str, str]:
    """``env`` with the workspace ``ws`` sourced on top (its install/local_setup.bash; setup.bash: with its underlays)."""
    text = f'set +u; . "{ws}/install/{script}" >/dev/null && env -0'
    dump = subprocess.run(["bash", "-c", text], capture_output=True, timeout=60, check=True, env=env).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


def build_cpp(venv: Path, env: dict[str, str], generated: Path, ws: Path) -> tuple[bool, str, float]:
    """colcon build of every package under ``generated`` into ``ws``: (ok, last lines, seconds)."""
    start = time.monotonic()
    shutil.copytree(generated, ws / "src")
    cmd = ["colcon", "--log-base", "log", "build", "--base-paths", "src", "--build-base", "build",
           "--install-base", "install", "--event-handlers", "console_direct-", "--cmake-args",
           f"-DPython3_EXECUTABLE={venv}/bin/python", "-DBUILD_TESTING=OFF",
           f"-DCMAKE_EXE_LINKER_FLAGS={env.get('ROS2_RUNTIME_CXX_LDFLAGS', '')}",
           f"-DCMAKE_SHARED_LINKER_FLAGS={env.get('ROS2_RUNTIME_CXX_SHARED_LDFLAGS', '')}"]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=2400, env=env, cwd=ws, check=False)
    (ws / "colcon.log").write_text(done.stdout + done.stderr)
    tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-30:])
    return done.returncode == 0, tail, time.monotonic() - start


def keep_only(gen: Path, *keep: str) -> None:
    """Leave only the packages ``keep`` in ``gen``: the rest comes from a workspace built before."""
    for package in gen.iterdir():
        if package.is_dir() and package.name not in keep:
            shutil.rmtree(package)


def ticker_workspaces(venv: Path, env: dict[str, str], root: Path) -> tuple[dict[str, Path], str]:
    """The workspaces of the container tests and bench/container_bench.py, built under ``root`` (reused when built
    there before): ``ws`` holds iface_msgs, iface_runtime_cpp, ticker 1.0, its ticker_msgs and the tally
    (tests/runtime/data, with their user files); ``ws_v1_1`` ticker 1.1 alone on top of it (its ticker_msgs is
    1.0's: NEW can share OLD's container). On failure: no workspaces, why."""
    from .ros import DATA, generate

    out = {"ws": root / "ws", "ws_v1_1": root / "ws_v1_1"}
    plan = {"ws": (("ticker", "ticker"), ("tally", "tally")), "ws_v1_1": (("ticker_v1_1", "ticker"),)}
    for key, components in plan.items():
        ws = out[key]
        if all((ws / "install" / package).is_dir() for _, package in components):
            continue
        gen = root / f"gen_{key}"
        shutil.rmtree(gen, ignore_errors=True)
        for iface, package in components:
            done = generate(DATA / f"{iface}.iface", gen, "--target", "rclcpp")
            if done.returncode != 0:
                return {}, f"generate {iface}: {done.stderr}"
            shutil.copyfile(DATA / f"{package}_node.cpp", gen / package / "src" / "node.cpp")
        build_env = env
        if key == "ws_v1_1":
            keep_only(gen, "ticker")
            build_env = overlay(env, out["ws"], "setup.bash")
        shutil.rmtree(ws, ignore_errors=True)
        ws.mkdir(parents=True)
        ok, tail, _ = build_cpp(venv, build_env, gen, ws)
        if not ok:
            return {}, f"{key} did not build (log {ws}/colcon.log):\n{tail}"
    return out, ""
