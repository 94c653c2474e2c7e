"""The component manager, measured on loopback (docs/system.md):

    python bench/manager_bench.py [--runs 10] [--replacements 10] [--instances 20] [--idle 30]
                                  [--only crash standby replace idle] [--workspace WS]

1. ``crash``: an instance's crash (``kill -9`` of a Python instance) until it is active again with its state
   (goal: median <= 1.5 s, p95 <= 2.5 s over 10 on a quiet machine), and where the time went: each phase
   from the kill (death noticed, process started, its node up, its services answering, configured,
   restored, active) as the manager's log and the instance's log time them; ``standby``: the same with
   ``standby = "true"`` (its standby told instead of a process started; each kill once the manager has
   discovered the standby (its log says so), as a crash that comes a while after the last one);
2. ``replace``: the silence on a 10 Hz topic across a managed replacement (``/iface_manager/replace``;
   goal p95 <= 250 ms);
3. ``idle``: the manager's CPU with N idle instances, and the instances' own (percent of one core over
   ``--idle`` seconds).

Generates and builds the test system's packages once (tests/runtime; ``--workspace`` reuses a colcon
workspace where they are built), then runs itself in the ROS 2 environment. Prints one line per figure
and the machine's load average before and after.
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]


def prepare(args: argparse.Namespace) -> int:
    sys.path.insert(0, str(ROOT))
    sys.path.insert(0, str(ROOT / "server"))
    from tests.ros_harness.ros import build, environment, runtime_venv
    from tests.ros_harness.systems import generate_system

    venv, why = runtime_venv()
    if venv is None:
        print(f"manager_bench: {why}", file=sys.stderr)
        return 2
    root = Path(tempfile.mkdtemp(prefix="manager-bench-"))
    gen, ws = root / "gen", root / "ws"
    if args.workspace is not None:
        ws = args.workspace.resolve()
    else:
        generate_system(gen)
        ws.mkdir()
        ok, tail, _ = build(venv, gen, ws)
        if not ok:
            print(f"manager_bench: build failed:\n{tail}", file=sys.stderr)
            return 2
    for name in ("room_sensor", "thermostat"):
        shutil.copy(ROOT / "examples" / f"{name}.iface", root)
    (root / "idle.yaml").write_text("/**:\n  ros__parameters:\n    rate_hz: 0.1\n", encoding="utf-8")
    for name, extra in (("pair", ""), ("pair_standby", ', standby = "true"')):
        (root / f"{name}.iface").write_text(
            f'system {name} version "1.0.0"\ninclude "room_sensor.iface"\ninclude "thermostat.iface"\n'
            f'instance sensor : room_sensor\ninstance thermostat : thermostat (snapshot = "0.5s"{extra})\n',
            encoding="utf-8")
    idle = "".join(f'instance idle{i} : room_sensor (parameters = "idle.yaml")\n' for i in range(args.instances))
    (root / "idle.iface").write_text(f'system idle version "1.0.0"\ninclude "room_sensor.iface"\n{idle}',
                                     encoding="utf-8")
    for side in ("a", "b"):
        shutil.copytree(ws / "install", root / side / "install")  # copies: the cached packages are read-only
    env = environment(venv, ws, root / "ros-log")
    cfg = {"root": str(root), "python": sys.executable, "runs": args.runs, "replacements": args.replacements,
           "idle": args.idle, "only": args.only, "env": env}
    (root / "config.json").write_text(json.dumps(cfg))
    done = subprocess.run([str(venv / "bin" / "python"), __file__, "--inner", str(root / "config.json")], env=env,
                          timeout=3600, check=False)
    shutil.rmtree(root, ignore_errors=True)
    return done.returncode


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * len(ordered) + 0.5) - 1))]


#: A line of a ROS log (``[INFO] [1764312345.123456789] [name]: message``).
LOG_LINE = re.compile(r"^\[\w+\] \[(\d+\.\d+)\] \[([^\]]+)\]: (.*)$")
#: The phases of a restart, each by the first line after the kill that says it: (phase, log, pattern).
PHASES = (
    ("death noticed", "manager", re.compile(r"^thermostat: process \d+ ended")),
    ("process started", "manager", re.compile(r"^thermostat: started pid \d+")),
    ("standby told", "manager", re.compile(r"^thermostat: standby pid \d+ told")),
    ("node up", "instance", re.compile(r"parameter file")),
    ("services answer", "manager", re.compile(r"^thermostat: answers")),
    ("configured", "manager", re.compile(r"^thermostat: configured")),
    ("restored", "manager", re.compile(r"^thermostat: restored snapshot")),
    ("active", "manager", re.compile(r"^thermostat: active")),
)


def log_times(path: Path, since: float) -> list[tuple[float, str]]:
    """(wall-clock time, message) of each line of a ROS log written at or after ``since``."""
    out: list[tuple[float, str]] = []
    try:
        text = path.read_text(errors="replace")
    except OSError:
        return out
    for line in text.splitlines():
        match = LOG_LINE.match(line.strip())
        if match and float(match.group(1)) >= since:
            out.append((float(match.group(1)), match.group(3)))
    return out


def phases(logs: dict[str, Path], killed: float) -> dict[str, float]:
    """Seconds from the kill (wall clock) to each phase the logs show."""
    lines = {name: log_times(path, killed) for name, path in logs.items()}
    found = {}
    for phase, log, pattern in PHASES:
        at = next((t for t, message in lines[log] if pattern.search(message)), None)
        if at is not None:
            found[phase] = at - killed
    return found


def start_manager(cfg: dict[str, Any], system: str, state: str, log: Path) -> subprocess.Popen[bytes]:
    argv = [cfg["python"], "-m", "iface", "manager", system, "--state-dir", state, "--max-restarts", "1000",
            "--grace", "1"]
    with open(log, "ab") as out:
        return subprocess.Popen(argv, env=cfg["env"], stdout=out, stderr=subprocess.STDOUT, start_new_session=True)


def stop_manager(proc: subprocess.Popen[bytes]) -> None:
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=120)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=30)


class Bench:
    """The probe's calls the sections share."""

    def __init__(self, cfg: dict[str, Any]) -> None:
        from tests.ros_harness.probe import Probe

        self.cfg = cfg
        self.root = Path(cfg["root"])
        self.probe = Probe()

    def status(self) -> dict[str, Any]:
        from iface_msgs.srv import SystemStatus

        answer = self.probe.call(SystemStatus, "/iface_manager/status", SystemStatus.Request(), timeout=30,
                                 idempotent=True)
        return {i.name: i for i in answer.instances}

    def until(self, predicate: Any, timeout: float) -> dict[str, Any]:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with contextlib.suppress(Exception):  # not answering yet
                s = self.status()
                if predicate(s):
                    return s
            time.sleep(0.02)
        raise TimeoutError("manager status not reached")

    def set_point(self, node: str) -> float:
        from tests.ros_harness.probe import import_interface

        service = f"{node}/save_state"
        types = self.probe.wait_until(lambda: next((t for n, t in self.probe.node.get_service_names_and_types()
                                                    if n == service and t), None), 30, service)
        save_t = import_interface(types[0])
        answer = self.probe.call(save_t, service, save_t.Request(timeout_sec=5.0), timeout=30, idempotent=True)
        return float(json.loads(answer.state)["values"]["set_point"])

    def pair(self, system: str) -> tuple[subprocess.Popen[bytes], dict[str, Path]]:
        """The manager of ``system`` (a sensor, a thermostat with a set point of 21.25 in its snapshot) and its logs."""
        from thermostat_msgs.srv import SetPoint

        log = self.root / f"manager-{system}.log"
        manager = start_manager(self.cfg, str(self.root / f"{system}.iface"), str(self.root / f"state-{system}"), log)
        self.until(lambda s: len(s) == 2 and all(i.state == "active" for i in s.values()), 180)
        self.probe.call(SetPoint, "/thermostat/set_point", SetPoint.Request(celsius=21.25), timeout=30)
        time.sleep(1.2)  # a periodic snapshot (0.5 s) holds the value
        return manager, {"manager": log, "instance": self.root / f"state-{system}" / "logs" / "thermostat.log"}

    def crashes(self, logs: dict[str, Path], label: str, standby: bool) -> bool:
        """``kill -9`` of the thermostat, ``runs`` times, each until it is active again with its state; the
        figures printed. False when a state was not restored."""
        crash: list[float] = []
        timed: dict[str, list[float]] = {phase: [] for phase, _, _ in PHASES}
        for run in range(self.cfg["runs"]):
            old = self.status()["thermostat"]
            if standby:
                from tests.ros_harness.standby_probe import logged, ready_standby

                spare = ready_standby("thermostat", other_than=(old.pid,))  # a standby told before is the instance now
                # as for a crash a while after the last one: the manager has seen the standby's node
                if not logged(lambda: logs["manager"].read_text(encoding="utf-8", errors="replace"),
                              f"thermostat: standby pid {spare} discovered"):
                    print(f"manager_bench: the manager did not see standby {spare} in its graph", file=sys.stderr)
                    return False
            killed, start = time.time(), time.monotonic()
            os.kill(old.pid, signal.SIGKILL)
            self.until(lambda s, old=old: s["thermostat"].state == "active"
                       and s["thermostat"].pid not in (0, old.pid), 60)
            crash.append(time.monotonic() - start)
            if self.set_point(self.status()["thermostat"].node) != 21.25:
                print("manager_bench: the state was not restored", file=sys.stderr)
                return False
            seen = phases(logs, killed)
            for phase, at in seen.items():
                timed[phase].append(at)
            print(f"  {label} {run}: {crash[-1]:.2f} s; " + ", ".join(f"{p} {t:.3f}" for p, t in seen.items()),
                  flush=True)
            time.sleep(1.0)
        if crash:
            print("  phases, median s after the kill: " + ", ".join(
                f"{p} {statistics.median(t):.3f}" for p, t in timed.items() if t), flush=True)
            print(f"{label}: crash -> active with state: median {statistics.median(crash):.2f} s, p95 "
                  f"{percentile(crash, 0.95):.2f} s, max {max(crash):.2f} s over {len(crash)} kill -9 "
                  f"(goal: median <= 1.5 s, p95 <= 2.5 s over 10 on a quiet machine)", flush=True)
        return True

    def replacements(self) -> bool:
        """Managed replacements of the thermostat, each the longest silence on /room/heater; False on a failure."""
        from iface_msgs.srv import Replace
        from thermostat_msgs.msg import Heater

        stamps: list[float] = []
        self.probe.node.create_subscription(Heater, "/room/heater", lambda _m: stamps.append(time.monotonic()), 100)
        gaps = []
        for run in range(self.cfg["replacements"]):
            side = "a" if run % 2 == 0 else "b"
            time.sleep(1.0)
            stamps.clear()
            time.sleep(1.0)
            request = Replace.Request(instance="thermostat", new_iface=str(self.root / "thermostat.iface"),
                                      package=str(self.root / side / "install" / "thermostat"), timeout_sec=10.0)
            asked = time.monotonic()
            answer = self.probe.call(Replace, "/iface_manager/replace", request, timeout=120)
            answered = time.monotonic()
            time.sleep(1.0)
            if not answer.success:
                print(f"manager_bench: replace {run} {answer.result}: {answer.record[-400:]}", file=sys.stderr)
                return False
            heard = list(stamps)
            gap, gap_at = max((b - a, a) for a, b in itertools.pairwise(heard))
            gaps.append(gap)
            record = json.loads(answer.record)
            detail = {st["step"]: st["detail"] for st in record.get("steps", [])}
            print(f"  replace {run}: longest gap {gap * 1000:.0f} ms, from {(gap_at - asked) * 1000:.0f} ms after "
                  f"the request ({(answered - asked) * 1000:.0f} ms to the answer); critical section "
                  f"{record.get('critical_section_ms')} ms, pause {record.get('pause_ms')} ms; "
                  f"{detail.get('start NEW', '')}; {detail.get('match', '')}", flush=True)
        if gaps:
            gaps.sort()
            p95 = gaps[min(len(gaps) - 1, round(0.95 * (len(gaps) - 1)))]
            print(f"silence on /room/heater (10 Hz) across a managed replacement: median "
                  f"{statistics.median(gaps) * 1000:.0f} ms, p95 {p95 * 1000:.0f} ms, max {gaps[-1] * 1000:.0f} ms "
                  f"over {len(gaps)} (goal p95 <= 250 ms)", flush=True)
        return True

    def idle(self) -> None:
        """The manager's CPU and memory with ``instances`` idle instances."""
        manager = start_manager(self.cfg, str(self.root / "idle.iface"), str(self.root / "state-idle"),
                                self.root / "manager-idle.log")
        try:
            s = self.until(lambda s: s and all(i.state == "active" for i in s.values()), 600)
            time.sleep(3)
            tick = os.sysconf("SC_CLK_TCK")

            def cpu(pid: int) -> float:
                fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
                return (int(fields[11]) + int(fields[12])) / tick

            pids = [i.pid for i in s.values()]
            c0, n0, t0 = cpu(manager.pid), [cpu(p) for p in pids], time.monotonic()
            time.sleep(self.cfg["idle"])
            c1, n1, t1 = cpu(manager.pid), [cpu(p) for p in pids], time.monotonic()
            rss = int(Path(f"/proc/{manager.pid}/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
            each = sorted(100 * (b - a) / (t1 - t0) for a, b in zip(n0, n1, strict=True))
            print(f"manager CPU with {len(s)} idle instances: {100 * (c1 - c0) / (t1 - t0):.1f} % of one core over "
                  f"{t1 - t0:.0f} s (RSS {rss:.0f} MB); the instances' own: {sum(each):.1f} % in all, "
                  f"median {statistics.median(each):.2f} % each", flush=True)
        finally:
            stop_manager(manager)


def inner(config: Path) -> int:
    sys.path.insert(0, str(ROOT))
    cfg = json.loads(config.read_text())
    only = cfg["only"]
    bench = Bench(cfg)
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    try:
        for system, label, standby in (("pair", "crash", False), ("pair_standby", "standby", True)):
            wanted = label in only or (system == "pair" and "replace" in only)
            if not wanted:
                continue
            manager, logs = bench.pair(system)
            try:
                if label in only and cfg["runs"] and not bench.crashes(logs, label, standby):
                    return 1
                if system == "pair" and "replace" in only and not bench.replacements():
                    return 1
            finally:
                stop_manager(manager)
        if "idle" in only:
            bench.idle()
    finally:
        bench.probe.close()
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=10, help="kill -9 of the instance (default 10)")
    ap.add_argument("--replacements", type=int, default=10, help="managed replacements (default 10)")
    ap.add_argument("--only", nargs="+", choices=("crash", "standby", "replace", "idle"),
                    default=["crash", "standby", "replace", "idle"], help="the figures to measure (default all)")
    ap.add_argument("--instances", type=int, default=20)
    ap.add_argument("--idle", type=float, default=30.0)
    ap.add_argument("--workspace", type=Path, help="a colcon workspace with room_sensor, thermostat and iface_msgs built")
    ap.add_argument("--inner", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.inner is not None:
        return inner(args.inner)
    return prepare(args)


if __name__ == "__main__":
    sys.exit(main())
