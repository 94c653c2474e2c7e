"""Components in one process, measured on loopback (docs/system.md, "Containers: figures"; issue 37's goals):

    python bench/container_bench.py [--runs 20] [--seconds 5] [--kills 20] [--only replace|throughput|kill] [--keep DIR]
                                     [--threads N]

1. the silence on a 1 kHz topic, and on a 100 Hz one, across a replacement inside the container: an
   ``iface_container`` holds ticker 1.0 and the tally (tests/runtime/data); each run loads ticker 1.1
   beside the active ticker (configured, its publisher matched), calls the container's ``~/handover``
   (between two of OLD's ticks, no DDS round trip in the critical section) and unloads OLD, through
   ``iface.operate.in_container`` (the calls the component manager makes). Median and p95 over ``--runs``
   (goals <= 2 / 3 ms at 1 kHz, <= 11 / 12 ms at 100 Hz) from the publish times (``source_timestamp``) of
   OLD's last count and NEW's first; the arrival times too, the longer of NEW's next two periods (a late
   second tick shows there), every other period (the container's own jitter), the counts per second over
   the run (fewer than the rate when the ticker misses periods), the container's critical section and
   pause, and counts lost or repeated (0 expected, at the bench's subscriber over DDS and at the tally in the process);
2. messages per second from the ticker (1 kHz, 50 a tick) to the tally: in one container with intra-process
   communication, in one container without it, and as two processes; the ratios.

3. a container's ``kill -9`` until every instance in it is active again with its state, restarted by the
   component manager (``iface-lsp manager`` running a system of ticker 1.0 and the tally in the container
   ``box``): ``--kills`` times, the container killed with SIGKILL each time; from the kill to the manager's log
   line that says the last of the two is active in the new container (the container restarted, both loaded
   with their last snapshot restored and activated); median, p95, max (goal <= 1 s median), and the same as
   seen by ``/iface_manager/status`` polled every 20 ms; then the same with ``standby = "true"`` on the tally
   (the manager keeps a spare container process, told to start instead of a process started; each kill once
   the manager has discovered the standby (its log says so), as a crash that comes a while after the last one).

Builds the ticker (1.0 and 1.1) and the tally (rclcpp) once, in the test cache (tests/ros_harness/cpp.py
``ticker_workspaces``; ``--keep DIR`` keeps the run's folder), then runs itself in the ROS 2 environment. The
machine's load average is printed with the figures: measure on a quiet machine.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RATES = {"1khz": 1000.0, "100hz": 100.0}
FLOOD = {"rate_hz": 1000.0, "burst": 50}


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * len(ordered) + 0.5) - 1))]


def load() -> str:
    return "load average " + " ".join(Path("/proc/loadavg").read_text().split()[:3])


def build(root: Path) -> tuple[dict[str, Path], dict[str, str], str]:
    """The workspaces of the tickers and the tally (built now unless built there before), their run environment;
    or why not."""
    from tests.ros_harness.cpp import missing_tools, overlay, rclcpp_env, ticker_workspaces
    from tests.ros_harness.ros import environment, runtime_venv

    venv, why = runtime_venv()
    if venv is None:
        return {}, {}, why
    env = rclcpp_env(venv)
    if env is None:
        return {}, {}, f"rclcpp is not built in {venv}/cpp: run bash ../shared/ros2-runtime/build-cpp.sh {venv}"
    if missing_tools(env):
        return {}, {}, f"no {', '.join(missing_tools(env))} to build C++"
    start = time.monotonic()
    ws, why = ticker_workspaces(venv, root)
    if why:
        return {}, {}, why
    print(f"workspaces ready in {time.monotonic() - start:.0f} s ({root})", flush=True)
    return ws, overlay(environment(venv, ws["ws"], root / "ros-log"), ws["ws"], "setup.bash"), ""


def prepare(args: argparse.Namespace) -> int:
    root = args.keep.resolve() if args.keep else Path(tempfile.mkdtemp(prefix="container-bench-"))
    root.mkdir(parents=True, exist_ok=True)
    sys.path[:0] = [str(ROOT), str(ROOT / "server")]
    ws, env, why = build(root)
    if why:
        print(f"container_bench: {why}", file=sys.stderr)
        return 2
    for name, rate in RATES.items():
        (root / f"{name}.yaml").write_text(f"/**:\n  ros__parameters:\n    rate_hz: {rate}\n", encoding="utf-8")
    (root / "flood.yaml").write_text("/**:\n  ros__parameters:\n" + "".join(f"    {k}: {v}\n" for k, v in
                                                                         FLOOD.items()), encoding="utf-8")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), str(ROOT / "server"), env.get("PYTHONPATH", "")])
    cfg = {"root": str(root), "ws": str(ws["ws"]), "ws_v1_1": str(ws["ws_v1_1"]), "runs": args.runs,
           "threads": args.threads,
           "seconds": args.seconds, "kills": args.kills, "only": args.only or ""}
    (root / "config.json").write_text(json.dumps(cfg))
    print(f"{load()} (before); commit {commit()}; logs in {root}", flush=True)
    try:
        done = subprocess.run([sys.executable, __file__, "--inner", str(root / "config.json")], env=env,
                              timeout=3600, check=False)
    finally:
        print(f"{load()} (after)", flush=True)
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    return done.returncode


def commit() -> str:
    """The checkout's commit (with "+changes" when the work tree differs from it)."""
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                          check=False).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True, check=False).stdout.strip()
    return (head or "unknown") + ("+changes" if dirty else "")


class Ticks:
    """Every /tick the bench receives: (count, publish time, arrival time) in ms, taken by a thread of its own
    (``Probe.fast_subscription``): on the probe's rclpy executor a topic at a true 1 kHz took a whole core of the
    bench, and counts came seconds late or not at all."""

    def __init__(self, probe: Any) -> None:
        from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
        from ticker_msgs.msg import Tick

        self.seen: list[tuple[int, float, float]] = []
        qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
        probe.fast_subscription(Tick, "/tick", self._got, qos)

    def _got(self, msg: Any, info: dict[str, int]) -> None:
        self.seen.append((msg.value, info["source_timestamp"] / 1e6, info["received_timestamp"] / 1e6))


def inner(config: Path) -> int:
    from iface.live.link import Link
    from iface.nodes import protocol
    from iface.operate.containers import component_in
    from iface.operate.in_container import ContainerCalls
    from tests.ros_harness.probe import Component, Probe, Protocol

    cfg = json.loads(config.read_text())
    root, runs = Path(cfg["root"]), int(cfg["runs"])
    logs = root / "logs"
    logs.mkdir(exist_ok=True)
    probe = Probe()
    calls = Protocol(probe)
    ticks = Ticks(probe)
    box = ContainerCalls(Link(probe.node), "box")
    ws = Path(cfg["ws"])
    v1_0 = component_in(ws / "install" / "ticker", "ticker", "ticker::Ticker")
    v1_1 = component_in(Path(cfg["ws_v1_1"]) / "install" / "ticker", "ticker", "ticker::Ticker")
    tally = component_in(ws / "install" / "tally", "tally", "tally::Tally")
    container_exe = ws / "install" / "iface_runtime_cpp" / "lib" / "iface_runtime_cpp" / "iface_container"

    def container() -> Component:
        threads = ("-p", f"executor_threads:={cfg['threads']}") if cfg.get("threads") else ()
        c = Component("box", logs, [str(container_exe)], threads)
        probe.wait_until(lambda: "/box/_container/load_node" in probe.services_of("box"), 30, "the container")
        return c

    def matched(node: str, at_least: int) -> None:
        probe.wait_until(lambda: min(calls.control(node, protocol.STATUS).publisher_matched or [0]) >= at_least, 10,
                         f"{node}'s /tick matched by {at_least} subscriptions")

    only = cfg.get("only", "")
    if only == "kill":
        code = kill_figures(cfg, probe)
        probe.close()
        return code
    # ---- 1. silence across a replacement inside the container
    for name, rate in RATES.items():
        if only == "throughput":
            break
        params = (root / f"{name}.yaml",)
        box_proc = container()
        try:
            box.load(v1_0, "ticker_0", params_files=params, activate=True)
            box.load(tally, "tally", activate=True)
            matched("ticker_0", 2)
            time.sleep(1.0)
            silences, arrivals, critical, pauses, after = [], [], [], [], []
            lasts: list[int] = []
            said: list[tuple[float, str]] = []
            first = len(ticks.seen)
            before = calls.save("tally")["values"]
            for run in range(1, runs + 1):
                old, new = f"/ticker_{run - 1}", f"ticker_{run}"
                box.load(v1_1, new, params_files=params, configure=True)
                matched(new, 2)
                done = box.hand_over(old, "/" + new, 10.0)
                if not done.success:
                    print(f"container_bench: ~/handover {old} -> {new}: {done.message}", file=sys.stderr)
                    return 1
                box.unload(box.nodes()[old])
                last = int(done.state["values"]["count"])
                lasts.append(last)
                probe.wait_until(lambda: bool(ticks.seen) and ticks.seen[-1][0] > last + 2,  # noqa: B023 - now
                                 10, "NEW's counts")
                at = {v: (s, r) for v, s, r in ticks.seen}
                silences.append(at[last + 1][0] - at[last][0])
                said.append((silences[-1], done.message))
                after.append(max(at[v + 1][0] - at[v][0] for v in range(last + 1, last + 3)))  # NEW's next two
                arrivals.append(at[last + 1][1] - at[last][1])
                critical.append(done.critical_ms)
                pauses.append(done.pause_ms)
                time.sleep(0.2)
            values = [v for v, _, _ in ticks.seen[first:]]
            switches = set(lasts)
            steady = [(b[1] - a[1]) for a, b in itertools.pairwise(ticks.seen[first:])
                      if b[0] == a[0] + 1 and a[0] not in switches]
            lost = sum(max(0, b - a - 1) for a, b in itertools.pairwise(values))
            repeated = sum(1 for a, b in itertools.pairwise(values) if b <= a)
            tallied = calls.save("tally")["values"]
            span = ticks.seen[first:]
            per_second = (span[-1][0] - span[0][0]) / (span[-1][1] - span[0][1]) * 1000  # counts over publish time
            twice = (tallied["received"] - before["received"]) - (tallied["last"] - before["last"] - tallied["missed"]
                                                                  + before["missed"])
            print(f"{rate:g} Hz: silence across a replacement inside the container (publish times): median "
                  f"{statistics.median(silences):.2f} ms, p95 {percentile(silences, 0.95):.2f} ms, max "
                  f"{max(silences):.2f} over {len(silences)}; arrival times: median {statistics.median(arrivals):.2f} "
                  f"ms, p95 {percentile(arrivals, 0.95):.2f} ms; critical section median "
                  f"{statistics.median(critical):.3f} ms, p95 {percentile(critical, 0.95):.3f} ms; NEW's next two "
                  f"periods, the longer: median {statistics.median(after):.2f} ms, p95 {percentile(after, 0.95):.2f} "
                  f"ms; every other period (publish times): median {statistics.median(steady):.2f} ms, p95 "
                  f"{percentile(steady, 0.95):.2f} ms, p99 {percentile(steady, 0.99):.2f} ms; counts per second over the run "
                  f"{per_second:.0f}; pause median "
                  f"{statistics.median(pauses):.2f} ms; lost {lost}, repeated {repeated} (bench, over DDS), missed "
                  f"{tallied['missed'] - before['missed']}, received twice {twice} (the tally, in the process); {load()}", flush=True)
            for silence, message in sorted(said, reverse=True)[:3]:
                print(f"  a long one: {silence:.2f} ms of silence; the container said: {message}", flush=True)
        finally:
            box_proc.stop()
    if only == "replace":
        probe.close()
        return 0

    # ---- 2. messages per second
    flood = (root / "flood.yaml",)
    rates: dict[str, float] = {}
    for setup in ("one container, intra-process", "one container, over DDS", "two processes"):
        started: list[Component] = []
        try:
            if setup == "two processes":
                for package in ("ticker", "tally"):
                    exe = ws / "install" / package / "lib" / package / package
                    extra = ("--params-file", str(flood[0])) if package == "ticker" else ()
                    started.append(Component(package, logs, [str(exe), "--activate"], ros_args=extra))
                for package in ("ticker", "tally"):
                    probe.wait_until(lambda: calls.control(package, protocol.STATUS).lifecycle_state == 3,  # noqa: B023
                                     30, f"{package} active")
            else:
                started.append(container())
                ipc = setup.endswith("intra-process")
                box.load(v1_0, "ticker", params_files=flood, activate=True, intra_process=ipc)
                box.load(tally, "tally", activate=True, intra_process=ipc)
            time.sleep(2.0)
            r0, t0 = calls.save("tally")["values"], time.monotonic()
            time.sleep(float(cfg["seconds"]))
            r1, t1 = calls.save("tally")["values"], time.monotonic()
            rates[setup] = (r1["received"] - r0["received"]) / (t1 - t0)
            offered = FLOOD["rate_hz"] * FLOOD["burst"]
            print(f"{setup}: {rates[setup]:,.0f} messages/s received by the tally (offered {offered:,.0f}/s), "
                  f"{r1['missed'] - r0['missed']} missed; {load()}", flush=True)
        finally:
            for p in reversed(started):
                p.stop()
    print(f"messages/s, one container with intra-process communication vs two processes: "
          f"{rates['one container, intra-process'] / rates['two processes']:.2f}x; one container over DDS vs two "
          f"processes: {rates['one container, over DDS'] / rates['two processes']:.2f}x", flush=True)
    code = kill_figures(cfg, probe) if not only and int(cfg["kills"]) > 0 else 0
    probe.close()
    return code


KILL_SYSTEM = """system bench_box version "1.0.0"
include "ticker.iface"
include "tally.iface"

instance ticker : ticker (container = "box")
instance tally : tally (container = "box", after = "ticker"{standby})
"""


def _logged_at(log: Path, line: str, after: float) -> float | None:
    """The wall time (ROS log stamp, s) of the first manager log line containing ``line`` stamped after ``after``."""
    for text in log.read_text(errors="replace").splitlines():
        if line in text and text.startswith("[INFO] ["):
            stamp = float(text.split("] [", 1)[1].split("]", 1)[0])
            if stamp > after:
                return stamp
    return None


def kill_figures(cfg: dict[str, Any], probe: Any) -> int:
    """3. Without a standby, then with one."""
    return kill_figure(cfg, probe, standby=False) or kill_figure(cfg, probe, standby=True)


def kill_figure(cfg: dict[str, Any], probe: Any, standby: bool) -> int:
    """The manager runs ticker 1.0 and the tally in ``box`` (with a standby container when ``standby``); the
    container is killed ``kills`` times."""
    import signal

    from iface_msgs.srv import Snapshot, SystemStatus

    from tests.ros_harness.probe import Protocol

    root, kills = Path(cfg["root"]), int(cfg["kills"])
    sysdir = root / "kill"
    shutil.rmtree(sysdir, ignore_errors=True)
    sysdir.mkdir()
    for name in ("ticker", "tally"):
        shutil.copy(ROOT / "tests" / "runtime" / "data" / f"{name}.iface", sysdir)
    (sysdir / "bench_box.iface").write_text(KILL_SYSTEM.format(standby=', standby = "true"' if standby else ""),
                                            encoding="utf-8")
    log = root / "logs" / f"kill-manager{'-standby' if standby else ''}.log"
    with open(log, "w") as out:
        manager = subprocess.Popen([sys.executable, "-m", "iface", "manager", str(sysdir / "bench_box.iface"),
                                    "--state-dir", str(sysdir / "state"), "--max-restarts", str(kills + 5),
                                    "--heartbeat-timeout", "10"], stdout=out, stderr=subprocess.STDOUT,
                                   start_new_session=True)

    def status() -> dict[str, Any]:
        answer = probe.call(SystemStatus, "/iface_manager/status", SystemStatus.Request(), timeout=30,
                            idempotent=True)
        return {i.name: i for i in answer.instances}

    def back(pid: int, timeout: float) -> dict[str, Any]:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            s = status()
            if len(s) == 2 and all(i.state == "active" and i.pid not in (0, pid) for i in s.values()):
                return s
            time.sleep(0.02)
        raise TimeoutError(f"not both active again within {timeout:g} s: {status()}")

    try:
        back(-1, 120)
        logged, seen = [], []
        for _ in range(kills):
            saved = probe.call(Snapshot, "/iface_manager/snapshot", Snapshot.Request(instance=""), timeout=30)
            ticker_file = next(Path(f) for f in saved.files if Path(f).parent.name == "ticker")
            count = json.loads(ticker_file.read_text())["values"]["count"]
            pid = status()["ticker"].pid
            if standby:
                from tests.ros_harness.standby_probe import logged as said, ready_standby

                spare = ready_standby("box", other_than=(pid,))  # a standby told before is the container now
                # as for a crash a while after the last one: the manager has seen the standby's node
                if not said(lambda: log.read_text(encoding="utf-8", errors="replace"),
                              f"container box: standby pid {spare} discovered"):
                    print(f"container_bench: the manager did not see standby {spare} in its graph", file=sys.stderr)
                    return 1
            killed, start = time.time(), time.monotonic()
            os.kill(pid, signal.SIGKILL)
            back(pid, 60)
            seen.append(time.monotonic() - start)
            stamp = None
            end = time.monotonic() + 5
            while stamp is None and time.monotonic() < end:
                stamp = _logged_at(log, "tally: active in container box", killed)
                time.sleep(0.02)
            if stamp is None:
                print("container_bench: the manager did not log the tally active", file=sys.stderr)
                return 1
            logged.append(stamp - killed)
            restored = Protocol(probe).save("ticker")["values"]["count"]
            if restored < count:
                print(f"container_bench: the ticker restarted at {restored}, before its snapshot", file=sys.stderr)
                return 1
            time.sleep(0.5)
        what = "with a standby container" if standby else "without a standby"
        print(f"container kill -9 ({what}) -> ticker and tally active again with their snapshots (the manager's log): median "
              f"{statistics.median(logged):.3f} s, p95 {percentile(logged, 0.95):.3f} s, max {max(logged):.3f} s over "
              f"{len(logged)}; as seen by status polls every 20 ms: median {statistics.median(seen):.3f} s, p95 "
              f"{percentile(seen, 0.95):.3f} s; {load()}", flush=True)
        return 0
    finally:
        if manager.poll() is None:
            manager.send_signal(signal.SIGTERM)
            try:
                manager.wait(timeout=60)
            except subprocess.TimeoutExpired:
                os.killpg(manager.pid, signal.SIGKILL)
                manager.wait(timeout=30)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=5.0, help="how long each throughput is measured")
    ap.add_argument("--kills", type=int, default=20, help="container kills the manager restarts (0: not measured)")
    ap.add_argument("--only", choices=("replace", "throughput", "kill"), help="measure one figure only")
    ap.add_argument("--threads", type=int, help="the container's executor_threads (default: iface_container's, 16)")
    ap.add_argument("--keep", type=Path, help="keep the run's folder (workspace views, logs) here")
    ap.add_argument("--inner", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.inner is not None:
        code = inner(args.inner)
        sys.stdout.flush()
        os._exit(code)  # rclpy's threads may abort the interpreter's own teardown
    return prepare(args)


if __name__ == "__main__":
    sys.exit(main())
