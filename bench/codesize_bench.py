"""Benchmark: lines of generated code per component, and the C++ component's build time, before and after.

Run: ``python bench/codesize_bench.py [--before DIR] [--build]`` — prints, for a thermostat-sized
component (tests/runtime/data/thermostat.iface: 3 parameters, 3 state variables, a subscription, a
publication, a service, an action, a diagnostics service) and examples/robot_arm.iface, the lines
``generate`` writes per component package (rclpy and rclcpp; the user's file and the interface's JSON
file, data the package installs for ``~/describe``, left out: its lines are the ``json`` column), the
lines of the shared packages written once per output folder, and how long ``generate`` takes in
process (``cold``: the first call of a fresh process, compile and the targets' imports included;
``warm``: a call after it; each the best of 3 processes, the warm one of 10 calls each). ``--before DIR`` runs the same with the iface of another checkout (e.g. ``/work/main``)
beside this one.
``--build`` also times ``colcon build`` of each rclcpp component package on its own (the interface
and shared packages built first, not timed), with the ROS 2 runtime of ``../shared/ros2-runtime``
(``IFACE_ROS2_VENV``, default ``~/.cache/ros2-runtime``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = {"thermostat": ROOT / "tests" / "runtime" / "data" / "thermostat.iface",
         "robot_arm": ROOT / "examples" / "robot_arm.iface"}
USER_FILES = ("node.py", "node.cpp")
SHARED = ("iface_msgs", "iface_runtime_py", "iface_runtime_cpp")


def generate(checkout: Path, iface: Path, target: str, out: Path) -> None:
    """``iface-lsp generate`` of ``checkout``'s iface."""
    env = dict(os.environ, PYTHONPATH=str(checkout / "server"))
    done = subprocess.run([sys.executable, "-m", "iface", "generate", str(iface), "--target", target, "--out",
                           str(out), "-q"], env=env, capture_output=True, text=True, timeout=300, check=False)
    if done.returncode != 0:
        raise SystemExit(f"generate failed ({checkout}, {iface.name}, {target}): {done.stderr[-400:]}")


def lines(folder: Path, skip: tuple[str, ...] = ()) -> int:
    """Lines of every file under ``folder`` but the user's (and those named in ``skip``)."""
    return sum(p.read_bytes().count(b"\n") for p in folder.rglob("*")
               if p.is_file() and p.name not in USER_FILES and p.name not in skip)


#: Run in a fresh process with a checkout's iface: the first generate (compile included), then the best of 10.
_TIMING = """
import sys, time
from iface.emit import generate
from iface.semantics.compile import Workspace
path, target = sys.argv[1:3]
start = time.perf_counter()
generate(Workspace().compile_path(path), target)
cold = time.perf_counter() - start
comp = Workspace().compile_path(path)
warm = []
for _ in range(10):
    start = time.perf_counter()
    generate(comp, target)
    warm.append(time.perf_counter() - start)
print(cold * 1000, min(warm) * 1000)
"""


def generation_ms(checkout: Path, iface: Path, target: str, rounds: int = 3) -> tuple[float, float]:
    """(cold, warm) milliseconds of ``generate`` with ``checkout``'s iface: the best of ``rounds`` fresh processes."""
    env = dict(os.environ, PYTHONPATH=str(checkout / "server"))
    runs = []
    for _ in range(rounds):
        done = subprocess.run([sys.executable, "-c", _TIMING, str(iface), target], env=env, capture_output=True,
                              text=True, timeout=300, check=True)
        cold, warm = done.stdout.split()
        runs.append((float(cold), float(warm)))
    return min(c for c, _ in runs), min(w for _, w in runs)


def component_dir(out: Path, name: str) -> Path:
    """The component package (``<name>``, or ``<name>_node`` where the interface package has the name)."""
    return out / name if (out / name / "package.xml").is_file() and not (out / name / "msg").exists() \
        else out / f"{name}_node"


@dataclass
class Figures:
    """What one checkout generates for one case and target, and how fast."""

    code: int
    json: int
    shared: int
    cold_ms: float
    warm_ms: float
    folder: Path


def measure(checkout: Path, work: Path) -> dict[tuple[str, str], Figures]:
    """(case, target) → the figures."""
    out: dict[tuple[str, str], Figures] = {}
    for case, iface in CASES.items():
        for target in ("rclpy", "rclcpp"):
            folder = work / f"{case}-{target}"
            generate(checkout, iface, target, folder)
            shared = sum(lines(folder / s) for s in SHARED if (folder / s).is_dir())
            package = component_dir(folder, case)
            data = (f"{iface.stem}.json",)
            code = lines(package, data)
            out[(case, target)] = Figures(code, lines(package) - code, shared, *generation_ms(checkout, iface, target),
                                          folder)
    return out


def build_time(folder: Path, component: str, venv: Path) -> float | None:
    """Seconds of ``colcon build --packages-select`` of the component, its dependencies built before."""
    env_sh = venv / "ros2-env.sh"
    cpp_env = venv / "cpp" / "cpp-env.sh"
    if not env_sh.is_file():
        return None
    ws = Path(tempfile.mkdtemp(prefix="codesize-ws-"))
    shutil.copytree(folder, ws / "src")
    source = f"set +u; source {env_sh}" + (f"; source {cpp_env}" if cpp_env.is_file() else "")
    # Shared libraries (the runtime and component libraries) link lttng-ust through the runtime's link folder,
    # executables libpython too (../shared/ros2-runtime/README.md, "Link flags").
    base = "colcon --log-base log build --base-paths src --build-base build --install-base install " \
           "--cmake-args -DBUILD_TESTING=OFF \"-DCMAKE_EXE_LINKER_FLAGS=$ROS2_RUNTIME_CXX_LDFLAGS\" " \
           "\"-DCMAKE_SHARED_LINKER_FLAGS=$ROS2_RUNTIME_CXX_SHARED_LDFLAGS\""
    deps = subprocess.run(["bash", "-c", f"{source}; cd {ws} && {base} --packages-up-to {component} "
                           f"--packages-skip {component}"], capture_output=True, text=True, timeout=3600, check=False)
    if deps.returncode != 0:
        print(f"  (dependencies of {component} did not build: {deps.stdout[-300:]})")
        return None
    start = time.perf_counter()
    done = subprocess.run(["bash", "-c", f"{source}; cd {ws} && {base} --packages-select {component}"],
                          capture_output=True, text=True, timeout=3600, check=False)
    seconds = time.perf_counter() - start
    shutil.rmtree(ws, ignore_errors=True)
    if done.returncode != 0:
        print(f"  ({component} did not build: {done.stdout[-300:]})")
        return None
    return seconds


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, help="another checkout (e.g. /work/main) to compare with")
    ap.add_argument("--build", action="store_true", help="also time colcon build of each rclcpp component")
    ap.add_argument("--cases", nargs="+", choices=sorted(CASES), default=list(CASES),
                    help="the components to build with --build (default: every one)")
    args = ap.parse_args()
    venv = Path(os.environ.get("IFACE_ROS2_VENV", Path.home() / ".cache" / "ros2-runtime"))
    runs = [("after", ROOT)] + ([("before", args.before.resolve())] if args.before else [])
    with tempfile.TemporaryDirectory(prefix="codesize-") as tmp:
        results = {label: measure(checkout, Path(tmp) / label) for label, checkout in runs}
        print(f"{'component':<12} {'target':<7} " + " ".join(
            f"{label + ' lines':>13} {'json':>5} {'shared':>7} {'cold ms':>8} {'warm ms':>8}" for label, _ in runs))
        for case in CASES:
            for target in ("rclpy", "rclcpp"):
                cells = " ".join(f"{f.code:>13} {f.json:>5} {f.shared:>7} {f.cold_ms:>8.1f} {f.warm_ms:>8.1f}"
                                 for f in (results[label][(case, target)] for label, _ in runs))
                print(f"{case:<12} {target:<7} {cells}")
        if args.build:
            for case in args.cases:
                cells = []
                for label, _ in runs:
                    folder = results[label][(case, "rclcpp")].folder
                    seconds = build_time(folder, component_dir(folder, case).name, venv)
                    cells.append(f"{label} {seconds:.1f} s" if seconds is not None else f"{label} -")
                print(f"build {case} (rclcpp, colcon --packages-select): {', '.join(cells)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
