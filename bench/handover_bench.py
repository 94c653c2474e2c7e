"""Benchmark: how long a topic goes silent across ``iface-lsp handover``, at 10 Hz and 100 Hz.

Run: ``python bench/handover_bench.py [--handovers 20] [--rates 10 100]`` — builds examples/counter.iface
(rclpy, with the tests' user module: a work timer publishes the count on ``/count`` at ``rate_hz``)
with the ROS 2 runtime of ``../shared/ros2-runtime`` (``IFACE_ROS2_VENV``, default
``~/.cache/ros2-runtime``), starts two instances on loopback, one active, and hands over between them
back and forth. For each rate it prints the median and p95 of

- the silence on ``/count`` across the switch: from OLD's last count (the one in the state it saved
  at the pause) to NEW's first (one period when no tick is lost);
- the longest gap between two counts while the command ran (the switch's or one from the load the
  command itself puts on the machine: start-up, compat, discovery);
- the critical section (OLD paused, its state restored into NEW, OLD deactivated, NEW activated, as
  ``handover`` reports it), and the median of the pause before it (OLD's current work and, when a
  work timer is due within 0.1 s, its next tick ending);
- the whole command (``python -m iface handover``: start-up, compat, preparation, switch);

and how many counts were lost or repeated (0 expected). Python → Python by default; with
``--new-runtime rclcpp`` the second instance is the C++ counter (examples/counter.iface with
tests/runtime/data/counter_node.cpp, built with iface_runtime_cpp on top of the Python workspace), so
the hand-overs alternate Python → C++ and C++ → Python.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "server"))

COUNTER = ROOT / "examples" / "counter.iface"
USER = ROOT / "tests" / "runtime" / "data" / "counter_node.py"
USER_CPP = ROOT / "tests" / "runtime" / "data" / "counter_node.cpp"


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, int(round(q * len(ordered) + 0.5)) - 1))]


def measure(rate: float, handovers: int, python: str, logs: Path, cpp: str | None = None) -> dict[str, Any]:
    """In the ROS environment: start two counters and hand over ``handovers`` times; the figures."""
    import rclpy
    from counter_msgs.msg import Count
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

    rclpy.init()
    node = rclpy.create_node("handover_bench_probe")
    arrivals: list[tuple[float, int]] = []
    qos = QoSProfile(reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST, depth=1000)
    node.create_subscription(Count, "/count", lambda m: arrivals.append((time.monotonic(), m.value)), qos)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinning = threading.Thread(target=executor.spin, daemon=True)
    spinning.start()
    names = ("counter_a", "counter_b")
    procs = []
    for i, name in enumerate(names):
        start_cmd = [cpp] if cpp and i == 1 else [python, "-m", "counter"]
        cmd = [*start_cmd, *(["--activate"] if i == 0 else []), "--ros-args", "-r", f"__node:={name}",
               "-p", f"rate_hz:={rate}"]
        procs.append(subprocess.Popen(cmd, stdout=open(logs / f"{name}-{rate:g}.log", "w"),  # noqa: SIM115
                                      stderr=subprocess.STDOUT, start_new_session=True))
    silences: list[float] = []
    critical: list[float] = []
    pauses: list[float] = []
    longest: list[float] = []
    bursts: list[int] = []
    offsets: list[float] = []
    whole: list[float] = []
    refused = 0
    try:
        end = time.monotonic() + 60
        while len(arrivals) < 20 and time.monotonic() < end:
            time.sleep(0.05)
        if len(arrivals) < 20:
            raise SystemExit(f"no counts from {names[0]} within 60 s (logs in {logs})")
        for i in range(handovers):
            old, new = names[i % 2], names[(i + 1) % 2]
            time.sleep(1.0)
            start = time.monotonic()
            done = subprocess.run([python, "-m", "iface", "handover", old, new, "--old", str(COUNTER), "--new",
                                   str(COUNTER), "--timeout", "20"], capture_output=True, text=True, timeout=120,
                                  check=False)
            stop = time.monotonic()
            with open(logs / f"handover-{rate:g}.log", "a") as f:
                f.write(f"--- {old} -> {new}: exit {done.returncode}\n{done.stdout}\n{done.stderr}\n")
            if done.returncode != 0:
                refused += 1
                continue
            record = json.loads(done.stdout)
            time.sleep(0.5 + 2.0 / rate)
            times = [t for t, _ in arrivals]
            gaps = [b - a for a, b in zip(times, times[1:]) if b >= start and a <= stop + 0.5]
            longest.append(max(gaps) * 1000 if gaps else float("nan"))
            if gaps:  # counts that came in a burst after the longest gap: the probe, not OLD, had stalled
                end_of_gap = next(b for a, b in zip(times, times[1:]) if b - a == max(gaps))
                bursts.append(sum(1 for t in times if end_of_gap <= t < end_of_gap + 0.002))
                offsets.append((end_of_gap - max(gaps) - start) * 1000)
            # OLD's last count is the one in the state it saved at the pause; NEW publishes the next one
            last_old = (record.get("state_before") or {}).get("count")
            at = {v: t for t, v in arrivals}
            switch = at[last_old + 1] - at[last_old] if last_old in at and last_old + 1 in at else max(gaps)
            silences.append(switch * 1000)
            critical.append(float(record["critical_section_ms"]))
            pauses.append(float(record["pause_ms"]))
            whole.append((stop - start) * 1000)
        values = [v for _, v in arrivals]
        lost = sum(max(0, b - a - 1) for a, b in zip(values, values[1:]))
        repeated = sum(1 for a, b in zip(values, values[1:]) if b <= a)
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait(timeout=10)
        executor.shutdown(timeout_sec=2.0)
        node.destroy_node()
        rclpy.try_shutdown()
    return {"rate": rate, "silence_ms": silences, "critical_ms": critical, "pause_ms": pauses, "longest_gap_ms": longest, "burst_after_longest": bursts,
            "longest_from_ms": offsets, "command_ms": whole,
            "refused": refused, "lost": lost, "repeated": repeated, "counts": len(arrivals)}


def overlay(env: dict[str, str], ws: Path, first: Path | None = None) -> dict[str, str]:
    """``env`` with the script ``first`` (if given), then the workspace ``ws``, sourced on top."""
    before = f'. "{first}" >/dev/null && ' if first is not None else ""
    script = f'set +u; {before}. "{ws}/install/local_setup.bash" >/dev/null && env -0'
    dump = subprocess.run(["bash", "-c", script], capture_output=True, timeout=60, check=True, env=env).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


def build_cpp_counter(venv: Path, root: Path) -> tuple[str | None, str]:
    """The C++ counter 1.0 and iface_runtime_cpp, built on the Python workspace (counter_msgs, iface_msgs):
    the executable's path, or None and why."""
    from tests.ros_harness.ros import environment, generate

    gen = root / "gen_cpp"
    done = generate(COUNTER, gen, "--target", "rclcpp")
    if done.returncode != 0:
        return None, done.stderr
    for package in gen.iterdir():
        if package.name not in ("counter", "iface_runtime_cpp"):
            shutil.rmtree(package)
    shutil.copyfile(USER_CPP, gen / "counter" / "src" / "node.cpp")
    ws = root / "ws_cpp"
    shutil.copytree(gen, ws / "src")
    script = (f'set +u; . "{venv}/cpp/cpp-env.sh" >/dev/null && colcon --log-base log build --base-paths src '
              '--build-base build --install-base install --cmake-args -DBUILD_TESTING=OFF '
              '"-DCMAKE_EXE_LINKER_FLAGS=$ROS2_RUNTIME_CXX_LDFLAGS" '
              '"-DCMAKE_SHARED_LINKER_FLAGS=$ROS2_RUNTIME_CXX_SHARED_LDFLAGS"')
    start = time.monotonic()
    done = subprocess.run(["bash", "-c", script], env=environment(venv, root / "ws"), cwd=ws, capture_output=True,
                          text=True, timeout=3600, check=False)
    if done.returncode != 0:
        return None, done.stdout[-1500:] + done.stderr[-1500:]
    print(f"built iface_runtime_cpp + the C++ counter in {time.monotonic() - start:.0f} s")
    return str(ws / "install" / "counter" / "lib" / "counter" / "counter"), ""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--handovers", type=int, default=20)
    ap.add_argument("--rates", type=float, nargs="+", default=[10.0, 100.0])
    ap.add_argument("--measure", type=float, help=argparse.SUPPRESS)
    ap.add_argument("--python", help=argparse.SUPPRESS)
    ap.add_argument("--logs", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--keep", type=Path, help="build into this folder, or reuse the counter built there before")
    ap.add_argument("--new-runtime", choices=("rclpy", "rclcpp"), default="rclpy",
                    help="the second instance's runtime: rclcpp alternates Python -> C++ and C++ -> Python")
    ap.add_argument("--cpp", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.measure is not None:
        print(json.dumps(measure(args.measure, args.handovers, args.python, args.logs, args.cpp)), flush=True)
        os._exit(0)  # rclpy's threads may abort the interpreter's own teardown ("terminate called…")
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT / "server"), os.environ.get("PYTHONPATH")) if p)
    from tests.ros_harness.ros import build, environment, generate, runtime_venv  # generate runs this checkout's iface

    venv, why = runtime_venv()
    if venv is None:
        print(f"handover_bench: {why}", file=sys.stderr)
        return 2
    root = args.keep.resolve() if args.keep else Path(tempfile.mkdtemp(prefix="handover-bench-"))
    gen, ws, logs = root / "gen", root / "ws", root / "logs"
    if not (ws / "install" / "counter").is_dir():
        ws.mkdir(parents=True, exist_ok=True)
        done = generate(COUNTER, gen)
        if done.returncode != 0:
            print(done.stderr, file=sys.stderr)
            return 3
        shutil.copyfile(USER, gen / "counter" / "counter" / "node.py")
        ok, tail, seconds = build(venv, gen, ws)
        if not ok:
            print(f"handover_bench: the counter did not build:\n{tail}", file=sys.stderr)
            return 3
        print(f"built counter + iface_msgs + iface_runtime_py in {seconds:.0f} s")
    logs.mkdir(exist_ok=True)
    print(f"logs in {logs}")
    cpp: str | None = None
    if args.new_runtime == "rclcpp":
        cpp = str(root / "ws_cpp" / "install" / "counter" / "lib" / "counter" / "counter")
        if not Path(cpp).is_file():
            cpp, why = build_cpp_counter(venv, root)
            if cpp is None:
                print(f"handover_bench: the C++ counter did not build: {why}", file=sys.stderr)
                return 3
    print(f"{'rate':>6} {'n':>3} {'silence median':>15} {'p95':>8} {'longest gap median':>19} {'p95':>8} "
          f"{'critical median':>16} {'p95':>8} {'pause median':>13} {'command median':>15} {'p95':>8} {'lost':>5} "
          f"{'repeated':>8}")
    for rate in args.rates:
        env = environment(venv, ws, root / "ros-log")
        env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")])
        if cpp is not None:
            # the rclcpp install first: ws_cpp's local_setup.bash does not chain it (librclcpp_action)
            env = overlay(env, root / "ws_cpp", venv / "cpp" / "cpp-env.sh")
        run = subprocess.run([sys.executable, __file__, "--measure", str(rate), "--handovers", str(args.handovers),
                              "--python", sys.executable, "--logs", str(logs),
                              *(["--cpp", cpp] if cpp else [])], env=env, capture_output=True,
                             text=True, timeout=600 + 60 * args.handovers, check=False)
        if run.returncode != 0 or not run.stdout.strip():
            print(f"handover_bench: {rate:g} Hz failed: {run.stderr[-1500:]}", file=sys.stderr)
            return 3
        r = json.loads(run.stdout.strip().splitlines()[-1])
        (logs / f"figures-{rate:g}.json").write_text(json.dumps(r, indent=1))
        s, c, w = r["silence_ms"], r["critical_ms"], r["command_ms"]
        if not s:
            print(f"{rate:>5g}Hz: every hand-over refused (see {logs})")
            continue
        g = r["longest_gap_ms"]
        print(f"{rate:>4g}Hz {len(s):>3} {statistics.median(s):>12.1f} ms {percentile(s, 0.95):>5.1f} ms "
              f"{statistics.median(g):>16.1f} ms {percentile(g, 0.95):>5.1f} ms "
              f"{statistics.median(c):>13.1f} ms {percentile(c, 0.95):>5.1f} ms "
              f"{statistics.median(r['pause_ms']):>10.1f} ms {statistics.median(w):>12.0f} ms "
              f"{percentile(w, 0.95):>5.0f} ms {r['lost']:>5} {r['repeated']:>8}"
              + (f"  ({r['refused']} refused)" if r["refused"] else ""))
    if not args.keep:
        shutil.rmtree(root, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
