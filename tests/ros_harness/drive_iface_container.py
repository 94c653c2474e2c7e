"""iface_container end to end: two C++ components in one process, and a hand-over inside it at 1 kHz.

    python drive_iface_container.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_containers.py with the ROS runtime's Python, in the environment of the
workspace that holds iface_msgs, iface_runtime_cpp, ticker 1.0 and the tally (tests/runtime/data).
One ``iface_container`` (``-r __node:=box``) loads ticker 1.0 (1 kHz) and the tally, active, with
intra-process communication, through ``iface.operate.in_container`` (the calls the component manager
makes); a ticker whose signed library was changed is refused before the container is asked to load it;
ticker 1.1 (its own install prefix, 1.0's interface package) is loaded beside 1.0, configured, and the
container's ``~/handover`` switches them; the count goes on, none lost or repeated, at this process's
subscriber (over DDS) and at the tally (in the process). Every wait is bounded; each process is stopped by
its own handle; each step is written to RESULT.json as it ends.
"""

from __future__ import annotations

import argparse
import itertools
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the checkout: tests.ros_harness
sys.path.insert(0, str(ROOT / "server"))  # iface.operate: the calls the manager makes

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from iface.live.link import Link
from iface.nodes import protocol
from iface.operate.containers import ContainerError, component_in, mapped_files, sharing_problem
from iface.operate.in_container import ContainerCalls
from tests.ros_harness.probe import Component, Probe, Protocol, Report, check, run

CONTAINER = "box"


def gaps(values: list[int]) -> list[tuple[int, int]]:
    """Pairs of successive counts that are not one apart (a count lost or repeated)."""
    return [(a, b) for a, b in itertools.pairwise(values) if b != a + 1]


#: snapshots of the tally taken in a row while /tick runs (each paused its work gate: a count arriving then was lost)
SAVES = 100


#: Callback groups of an iface component: its work, action, client, Δ and control groups and rclcpp's default one.
GROUPS = 6


def threads_named(pid: int) -> dict[str, int]:
    """How many threads of process ``pid`` bear each name."""
    names: dict[str, int] = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            name = (task / "comm").read_text().strip()
        except OSError:
            continue  # ended meanwhile
        names[name] = names.get(name, 0) + 1
    return names


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("config", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--logs", type=Path, required=True)
    a = ap.parse_args()
    cfg = json.loads(a.config.read_text())
    a.logs.mkdir(parents=True, exist_ok=True)
    report = Report(a.out)
    from ticker_msgs.msg import Tick

    probe = Probe()
    link = Link(probe.node)
    box = ContainerCalls(link, CONTAINER)
    env = cfg["env"]
    ticks: list[tuple[int, float]] = []  # (count, publish time in ms)
    qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
    probe.fast_subscription(Tick, "/tick", lambda m, info: ticks.append(
        (m.value, info["source_timestamp"] / 1e6)), qos)
    store = Path(cfg["store"])
    v1_0 = component_in(Path(cfg["ws"]) / "install" / "ticker", "ticker", "ticker::Ticker")
    v1_1 = component_in(Path(cfg["ws_v1_1"]) / "install" / "ticker", "ticker", "ticker::Ticker")
    tampered = component_in(Path(cfg["tampered"]), "ticker", "ticker::Ticker")
    tally = component_in(Path(cfg["ws"]) / "install" / "tally", "tally", "tally::Tally")
    loaded: dict[str, int] = {}
    started: list[Component] = []
    try:
        exe = Path(cfg["ws"]) / "install" / "iface_runtime_cpp" / "lib" / "iface_runtime_cpp" / "iface_container"
        container = Component(CONTAINER, a.logs, [str(exe)], env=env)
        started.append(container)

        def up() -> str:
            probe.wait_until(lambda: f"/{CONTAINER}/_container/load_node" in probe.services_of(CONTAINER), 30,
                             f"/{CONTAINER}/_container/load_node")
            for name, component, files in (("ticker", v1_0, (Path(cfg["rate_1khz"]),)), ("tally", tally, ())):
                got = box.load(component, name, params_files=files, activate=True, trust_store=store)
                loaded[name] = got.unique_id
            check(box.nodes() == {"/ticker": loaded["ticker"], "/tally": loaded["tally"]}, str(box.nodes()))
            protocol_of = Protocol(probe)
            states = {n: protocol_of.control(n, protocol.STATUS).lifecycle_state for n in ("ticker", "tally")}
            check(states == {"ticker": 3, "tally": 3}, f"lifecycle states {states}")
            probe.wait_until(lambda: len(ticks) >= 500, 30, "500 ticks from ticker 1.0")
            named = threads_named(container.proc.pid)
            check(named.get("ticker", 0) >= GROUPS and named.get("tally", 0) >= GROUPS,
                  f"each callback group of each node on a thread of its own, named as the node: {named}")
            log = container.log()
            check("[ticker]: intra-process communication: publisher /tick" in log, "ticker 1.0 not intra-process")
            check("[tally]: intra-process communication: subscription /tick" in log, "the tally not intra-process")
            return (f"ticker 1.0 ({v1_0.library}) and the tally loaded into {exe.name} (pid {container.proc.pid}), "
                    f"trusted, active, /tick intra-process; {len(ticks)} ticks so far")

        if not report.step("container: ticker 1.0 and the tally loaded into iface_container, active", up):
            return 1

        def refused() -> str:
            before = box.nodes()
            try:
                box.load(tampered, "ticker_tampered", trust_store=store)
            except ContainerError as e:
                said = str(e)
            else:
                raise AssertionError("a ticker whose library changed after it was signed was loaded")
            check("changed since it was signed" in said and "not loaded" in said, said)
            check(box.nodes() == before, f"the container's nodes changed: {box.nodes()}")
            maps = mapped_files(container.proc.pid)
            check(str(tampered.library) not in maps and str(tampered.library.resolve()) not in maps,
                  f"the container mapped {tampered.library}")
            check("ticker_tampered" not in container.log(), "the container heard of ticker_tampered")
            return f"refused before any request: {said[:300]}; the container never mapped {tampered.library.name}"

        report.step("container: an untrusted library is refused before it is loaded", refused)

        def snapshots() -> str:
            calls = Protocol(probe)
            first = calls.save("tally")["values"]
            for _ in range(SAVES - 1):
                calls.save("tally")
            last = calls.save("tally")["values"]
            status = calls.control("tally", protocol.STATUS)
            check(last["received"] - first["received"] >= 100, f"the tally received {last['received']} (the ticker "
                  f"stopped?)")
            check(last["missed"] == first["missed"], f"the tally missed {last['missed'] - first['missed']} counts "
                  f"across {SAVES} snapshots")
            return (f"{SAVES} snapshots of the tally while /tick ran at 1 kHz: {last['received'] - first['received']} "
                    f"counts received between the first and the last, none missed; {status.transactions} transactions")

        report.step(f"container: {SAVES} snapshots of the tally at 1 kHz lose no message", snapshots)

        def beside() -> str:
            problem = sharing_problem(v1_1.library, container.proc.pid, env, cfg["env_v1_1"])
            check(problem is None, f"ticker 1.1 cannot share the container: {problem}")
            got = box.load(v1_1, "ticker_next", params_files=(Path(cfg["rate_1khz"]),), configure=True,
                           trust_store=store)
            loaded["ticker_next"] = got.unique_id
            status = Protocol(probe).control("ticker_next", protocol.STATUS)
            check((status.version, status.lifecycle_state) == ("1.1.0", 2), f"ticker_next: {status}")
            maps = mapped_files(container.proc.pid)
            check(str(v1_1.library) in maps or str(v1_1.library.resolve()) in maps,
                  f"{v1_1.library} is not mapped in the container")
            return f"ticker 1.1 ({v1_1.library}) can share the process; loaded and configured as /ticker_next"

        if not report.step("container: ticker 1.1 loaded beside 1.0 (it can share the process)", beside):
            return 1

        def switch() -> str:
            # NEW's publisher matched by this process's subscription before the switch, as the manager waits for
            probe.wait_until(lambda: len(Protocol(probe).control("ticker_next", protocol.STATUS).publisher_matched)
                             and min(Protocol(probe).control("ticker_next", protocol.STATUS).publisher_matched) >= 2,
                             10, "ticker 1.1's /tick matched by the probe and the tally")
            since = len(ticks)
            done = box.hand_over("/ticker", "/ticker_next", 10.0)
            check(done.success, f"~/handover: {done.message}")
            carried = int(done.state["values"]["count"])
            probe.wait_until(lambda: ticks and ticks[-1][0] >= carried + 500, 10, f"counts past {carried + 500}")
            values = [v for v, _ in ticks]
            check(not gaps(values), f"counts lost or repeated at the subscriber: {gaps(values)[:5]}")
            check(values[since] <= carried, f"the first count after the request, {values[since]}, is past {carried}")
            at = dict(ticks)
            silence = at[carried + 1] - at[carried]
            steps = r"\(saved [\d.]+, restored [\d.]+, first tick set [\d.]+, active [\d.]+ ms\)"
            check(re.search(steps, done.message), f"no steps of the critical section in {done.message!r}")
            # OLD is deactivated (and the switch logged) after NEW's first tick, so that nothing of OLD runs beside it;
            # the runtime waits for that tick for two periods and 10 ms at most from when NEW's schedule was set (a
            # machine loaded past its cores has delayed the tick by 80 ms): before the tick only once that wait ran out
            log = container.log()
            logged = re.search(r"\[INFO\] \[([\d.]+)\] \[ticker\]: handed over: NEW /ticker_next", log)
            check(logged is not None, f"OLD did not log the switch: {log[-2000:]}")
            assert logged is not None
            logged_ms = float(logged.group(1)) * 1000
            if logged_ms < at[carried + 1]:
                plan = re.search(r"\[ticker_next\]: schedule: .* the first tick due at ([\d.]+) \(period ([\d.]+) s, "
                                 r"in (-?[\d.]+) s\)", log)
                check(plan is not None, f"no schedule line of NEW in the container's log: {log[-2000:]}")
                assert plan is not None
                due, period, due_in = (float(plan.group(i)) for i in (1, 2, 3))
                waited_until = (due - due_in + min(1.0, 2 * period + 0.01)) * 1000
                check(logged_ms >= waited_until,
                      f"OLD logged the switch at {logged_ms:.3f} ms, before NEW's first count "
                      f"({at[carried + 1]:.3f} ms) and before its wait for it ran out ({waited_until:.3f} ms)")
            states = {n: Protocol(probe).control(n, protocol.STATUS).lifecycle_state for n in ("ticker", "ticker_next")}
            check(states == {"ticker": 2, "ticker_next": 3}, f"lifecycle states after the switch {states}")
            tallied = Protocol(probe).save("tally")["values"]
            check(tallied["missed"] == 0, f"the tally (intra-process) missed {tallied['missed']}")
            check(tallied["last"] > carried, f"the tally's last count {tallied['last']} is not past {carried}")
            check(container.proc.poll() is None, "the container has exited")
            return (f"{done.message}; count {carried} carried; {len(values)} counts {values[0]}..{values[-1]}, none lost "
                    f"or repeated; /tick {carried} -> {carried + 1}: {silence:.2f} ms apart (publish times); pause "
                    f"{done.pause_ms:.2f} ms, critical section {done.critical_ms:.3f} ms, after a tick of "
                    f"'{done.after_tick}'; the tally: {tallied['received']} received, missed 0")

        if not report.step("container: ~/handover switches ticker 1.0 to 1.1 at 1 kHz, state carried, none lost",
                           switch):
            return 1

        def unload() -> str:
            box.unload(loaded.pop("ticker"))
            check(set(box.nodes()) == {"/tally", "/ticker_next"}, str(box.nodes()))
            mark = len(ticks)
            probe.wait_until(lambda: len(ticks) >= mark + 200, 10, "ticks from ticker 1.1 after the unload")
            values = [v for v, _ in ticks]
            check(not gaps(values), f"counts lost or repeated: {gaps(values)[:5]}")
            check(container.proc.poll() is None, "the container has exited")
            named = threads_named(container.proc.pid)
            check("ticker" not in named and named.get("ticker_next", 0) >= GROUPS,
                  f"ticker 1.0's threads end with its unload, 1.1's run: {named}")
            container.stop()
            return f"ticker 1.0 unloaded, 1.1 goes on ({values[-1]}); the container stopped: {container.proc.returncode}"

        report.step("container: OLD unloaded, NEW goes on", unload)
    finally:
        for p in started:
            p.stop()
        probe.close()
    return 0 if all(s["ok"] for s in report.steps.values()) else 1


if __name__ == "__main__":
    run(main)
