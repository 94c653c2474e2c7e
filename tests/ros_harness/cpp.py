"""The container tests' and benches' C++ (rclcpp) workspaces, and the environment that builds and runs them.

rclcpp has no wheel: ``../shared/ros2-runtime/build-cpp.sh VENV`` builds it into ``VENV/cpp`` and writes
``cpp-env.sh``. ``rclcpp_env`` is the environment of ``ros2-env.sh`` and ``cpp-env.sh`` (None without
them). ``ticker_workspaces`` builds the tickers and the tally through the test cache (``workspaces.py``: each
package once per content on this machine) and gives each test its own copy of the component packages it signs
(the container loads its libraries from there; the trust tests sign and change them, which the cache's
read-only entries must never see).
"""

from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass
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


def keep_only(gen: Path, *keep: str) -> None:
    """Leave only the packages ``keep`` in ``gen``: the rest comes from a workspace built before."""
    for package in gen.iterdir():
        if package.is_dir() and package.name not in keep:
            shutil.rmtree(package)


@dataclass(frozen=True)
class Tickers:
    """One of the workspaces ``ticker_workspaces`` makes."""

    #: (iface file in tests/runtime/data, its package) of each component generated into it
    components: tuple[tuple[str, str], ...]
    #: the generated packages it builds (None: all; the others come from ``ws`` beneath it)
    kept: tuple[str, ...] | None
    #: the packages copied for the test to sign and change
    own: tuple[str, ...]


TICKERS = {
    "ws": Tickers((("ticker", "ticker"), ("tally", "tally")), None, ("ticker", "tally")),
    "ws_v1_1": Tickers((("ticker_v1_1", "ticker"),), ("ticker",), ("ticker",)),
    "ws_v2": Tickers((("ticker_v2", "ticker"),), ("ticker", "ticker_msgs"), ("ticker",)),
}


def ticker_workspaces(venv: Path, root: Path) -> tuple[dict[str, Path], str]:
    """The workspaces of the container tests and bench/container_bench.py, under ``root``: ``ws`` holds iface_msgs,
    iface_runtime_cpp, ticker 1.0, its ticker_msgs and the tally (tests/runtime/data, with their user files);
    ``ws_v1_1`` ticker 1.1 on top of it (its ticker_msgs is 1.0's: NEW can share OLD's container); ``ws_v2``
    ticker 2.0 with a ticker_msgs of its own on top of it (NEW cannot share a container that has 1.0's loaded).
    Each is a view of test cache entries in which the component packages are copies of its own
    (``workspaces.own_copy``), to sign. On failure: no workspaces, why."""
    from .ros import DATA, build, generate
    from .workspaces import own_copy

    cached: dict[str, Path] = {}
    out: dict[str, Path] = {}
    for key, plan in TICKERS.items():
        gen = root / f"gen_{key}"
        shutil.rmtree(gen, ignore_errors=True)
        for iface, package in plan.components:
            done = generate(DATA / f"{iface}.iface", gen, "--target", "rclcpp")
            if done.returncode != 0:
                return {}, f"generate {iface}: {done.stderr}"
            shutil.copyfile(DATA / f"{package}_node.cpp", gen / package / "src" / "node.cpp")
        if plan.kept is not None:
            keep_only(gen, *plan.kept)
        cached[key] = root / f"cache_{key}"
        underlays = [cached["ws"]] if key != "ws" else []
        ok, why, _ = build(venv, gen, cached[key], underlays=underlays, cpp=True)
        if not ok:
            return {}, f"{key}: {why}"
    for key, plan in TICKERS.items():
        out[key] = own_copy(cached[key], plan.own, root / key)
    return out, ""
