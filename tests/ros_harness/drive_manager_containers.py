"""Drive the component manager through a system with a container and report each step (run in a ROS 2 environment).

    python drive_manager_containers.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_manager_containers.py with the ROS runtime's Python. The system: a Python
room sensor, then ticker 1.0 (1 kHz) and the tally, both C++, in the container ``box``. The manager runs as
a user runs it (``iface-lsp manager``, in a session of its own, stopped by its own handle); the clients are
the real CLI (``iface-lsp system ...``); this driver's node subscribes to /tick, reads the status and the
nodes' states, and asks the container what it holds. Every wait is bounded; each step is written to
RESULT.json as it ends.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))  # the checkout: tests.ros_harness
sys.path.insert(0, str(ROOT / "server"))  # iface.operate: the container's calls

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from iface.live.link import Link
from iface.operate.containers import mapped_files
from iface.operate.in_container import ContainerCalls
from tests.ros_harness.probe import ManagerStatus, Probe, Protocol, Report, StepFailed, check, run
from tests.ros_harness.ros2cli import node_processes
from tests.ros_harness.standby_probe import logged, ready_standby

ORDER = ("sensor", "ticker", "tally")


def gaps(values: list[int]) -> list[tuple[int, int]]:
    """Pairs of successive counts that are not one apart (a count lost or repeated)."""
    return [(a, b) for a, b in itertools.pairwise(values) if b != a + 1]


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

    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    probe = Probe()
    box = ContainerCalls(Link(probe.node), "box")
    ticks: list[int] = []
    qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
    probe.fast_subscription(Tick, "/tick", lambda m: ticks.append(int(m.value)), qos)
    argv = [cfg["python"], "-m", "iface", "manager", cfg["system"], "--state-dir", cfg["state"], "--trust-store",
            cfg["store"], "--max-restarts", "3", "--heartbeat-timeout", "10", "--grace", "2"]
    managers: list[tuple[subprocess.Popen[bytes], Path]] = []

    def start_manager() -> subprocess.Popen[bytes]:
        path = a.logs / f"manager{len(managers) + 1}.log"
        with open(path, "w") as out:
            proc = subprocess.Popen(argv, env=cfg["env"], stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
        managers.append((proc, path))
        return proc

    def manager_log() -> str:
        return managers[-1][1].read_text(errors="replace")

    start_manager()

    status = ManagerStatus(probe)
    settle = status.settle

    def all_active(s: dict[str, Any]) -> bool:
        return set(s) == set(ORDER) and all(i.state == "active" for i in s.values())

    def cli(*args: str, timeout: float = 240) -> tuple[int, str, str]:
        cmd = [cfg["python"], "-m", "iface", "system", *args]
        done = subprocess.run(cmd, env=cfg["env"], capture_output=True, text=True, timeout=timeout, check=False)
        with (a.logs / "cli.log").open("a") as f:
            f.write(f"$ {' '.join(cmd)}\nexit {done.returncode}\n{done.stdout}\n{done.stderr}\n")
        return done.returncode, done.stdout, done.stderr

    def counts_past(value: int, timeout: float, what: str) -> None:
        """Wait until the subscriber has seen a count past ``value``; on a timeout say where it was."""
        since, start = len(ticks), time.monotonic()
        try:
            probe.wait_until(lambda: ticks and ticks[-1] > value, timeout, what)
        except TimeoutError as e:
            raise StepFailed(f"{e}: {len(ticks) - since} counts arrived in {time.monotonic() - start:.1f} s, the last "
                             f"{ticks[-1] if ticks else None} (wanted past {value})") from None

    def counts_after_restart(saved: int, what: str) -> list[int]:
        """Counts of the ticker once it runs again (restarted from its snapshot ``saved``): the counts that arrive
        1 s after it is active (the dead process's last ones are in by then), 100 of them."""
        time.sleep(1.0)
        since = len(ticks)
        probe.wait_until(lambda: len(ticks) >= since + 100, 30, f"100 counts from {what}")
        fresh = ticks[since:]
        check(fresh[0] > saved, f"{what} counts from {fresh[0]}: not past its snapshot's {saved} (restarted from "
              "nothing?)")
        check(not gaps(fresh), f"counts lost or repeated: {gaps(fresh)[:5]}")
        return fresh

    def replace(new_iface: str, package: str) -> tuple[int, dict[str, Any]]:
        # --timeout also bounds the wait for NEW's publishers to be matched by every subscriber: with three test
        # workers on two cores, a NEW in a second container was matched after 4.6 and 7.8 s (a bound, not a measure)
        code, out, err = cli("replace", cfg["system"], "ticker", "--new", new_iface, "--package", package,
                             "--timeout", "30")
        try:
            return code, json.loads(out)
        except ValueError:
            raise AssertionError(f"not one JSON record (exit {code}): {out[-500:]} {err[-500:]}") from None

    try:
        def up() -> str:
            s = settle(all_active, 180, "every instance active")
            log = manager_log()
            order = [log.find(f"{n}: active") for n in ORDER]
            check(-1 not in order and order == sorted(order), f"not brought up in order: {order}")
            check(log.find("container box: started pid") < order[1], "the container started after its instance")
            check(s["ticker"].container == "box" and s["tally"].container == "box" and s["sensor"].container == "",
                  f"containers {[(n, i.container) for n, i in s.items()]}")
            check(s["ticker"].pid == s["tally"].pid != s["sensor"].pid, "the container's pid is not both instances'")
            code, out, err = cli("status", cfg["system"], "--format", "json")
            check(code == 0, f"status exit {code}: {err}")
            data = {i["name"]: i for i in json.loads(out)["instances"]}
            check([data[n]["container"] for n in ORDER] == [None, "box", "box"], f"json: {data}")
            nodes = box.nodes()
            check(set(nodes) == {"/ticker", "/tally"}, f"the container holds {nodes}")
            probe.wait_until(lambda: len(ticks) >= 500, 30, "500 ticks from the ticker in the container")
            return (f"up in order (log offsets {order}); box pid {s['ticker'].pid} holds {sorted(nodes)}; sensor pid "
                    f"{s['sensor'].pid}; {len(ticks)} ticks")

        if not report.step("up: the Python instance, then both C++ instances in the container, in order", up):
            return 1

        def untrusted() -> str:
            pid = status()["ticker"].pid
            before = box.nodes()
            code, record = replace(cfg["new_iface"], cfg["tampered"])
            check(code == 1 and record["result"] == "refused", f"exit {code}, result {record['result']}")
            said = " ".join(s["detail"] for s in record["steps"] if not s["ok"])
            check("changed since it was signed" in said, said)
            check(box.nodes() == before, f"the container's nodes changed: {box.nodes()}")
            library = Path(cfg["tampered"]) / "lib" / "libticker_component.so"
            mapped = mapped_files(pid)
            check(str(library) not in mapped and str(library.resolve()) not in mapped, f"the container mapped {library}")
            s = status()
            check(all_active(s) and s["ticker"].node == "/ticker", f"{s['ticker'].node} {s['ticker'].state}")
            return f"refused before NEW was loaded: {said[:300]}; the container never mapped {library.name}"

        report.step("untrusted: a changed library is refused before the container loads it", untrusted)

        def kill_container() -> str:
            code, out, err = cli("snapshot", cfg["system"])
            check(code == 0, f"snapshot exit {code}: {err}")
            snap = {n: json.loads(Path(f).read_text())["values"] for n, f in
                    zip(("sensor", "ticker", "tally"), sorted(json.loads(out)["files"], key=lambda f: ORDER.index(
                        Path(f).parent.name)), strict=True)}
            s = status()
            pid, restarts = s["ticker"].pid, (s["ticker"].restarts, s["tally"].restarts, s["sensor"].restarts)
            spare = ready_standby("box", cfg["own"])  # the tally says standby: its container keeps one
            check(logged(manager_log, f"container box: started standby pid {spare}"), "the standby is not the manager's")
            check(logged(manager_log, f"container box: standby pid {spare} discovered"),
                  f"the manager did not see standby {spare} in its graph")
            counts_past(snap["ticker"]["count"] + 300, 10, "300 ticks more")
            mark = len(ticks)
            os.kill(pid, signal.SIGKILL)
            killed = time.monotonic()
            back = settle(lambda x: all_active(x) and x["ticker"].pid not in (0, pid)
                          and x["ticker"].restarts > restarts[0] and x["tally"].restarts > restarts[1],
                          90, "both instances active again in a new container, each restart counted")
            took = time.monotonic() - killed
            check(back["sensor"].restarts == restarts[2] and back["sensor"].pid == s["sensor"].pid,
                  "the Python instance was touched")
            check(back["ticker"].pid == back["tally"].pid, "not one container again")
            check(back["ticker"].pid == spare and f"container box: standby pid {spare} told to start" in manager_log(),
                  f"the container came back as pid {back['ticker'].pid}, not its standby {spare}")
            for n in ("ticker", "tally"):
                check(any("container box" in f and "ended" in f for f in back[n].findings),
                      f"{n}: no finding names the container: {list(back[n].findings)}")
            last = ticks[mark - 1]
            fresh = counts_after_restart(snap["ticker"]["count"], "the restarted ticker")
            lines = manager_log().splitlines()
            for n in ("ticker", "tally"):
                said = [x for x in lines if f"{n}: active in container box (pid {back[n].pid}," in x]
                check(said and "snapshot" in said[-1] and "restored" in said[-1],
                      f"{n}: the manager did not say it was loaded again with its snapshot: {said[-1:]}")
            tally = Protocol(probe).save("tally")["values"]
            check(tally["received"] >= snap["tally"]["received"], f"the tally restarted from nothing: {tally}")
            return (f"box pid {pid} killed; {took:.2f} s to both active in its standby, pid {back['ticker'].pid} (as seen by status "
                    f"polls); ticker counting again at {fresh[0]} (snapshot {snap['ticker']['count']}, last before the kill "
                    f"{last}); tally received {tally['received']} (snapshot {snap['tally']['received']}); restarts "
                    f"ticker {back['ticker'].restarts}, tally {back['tally'].restarts}, sensor {back['sensor'].restarts}")

        if not report.step("kill -9 of the container: both instances active again with their snapshots, in its standby",
                           kill_container):
            return 1

        def in_container() -> str:
            s = status()
            pid = s["ticker"].pid
            probe.wait_until(lambda: len(ticks) > 200, 10, "ticks")
            missed_before = Protocol(probe).save("tally")["values"]["missed"]
            mark = len(ticks)
            code, record = replace(cfg["new_iface"], cfg["package_v1_1"])
            check(code == 0 and record["result"] == "replaced", f"exit {code}: {json.dumps(record)[:1500]}")
            steps = {x["step"]: x["detail"] for x in record["steps"]}
            check("share" in steps and "switch in container" in steps, f"steps {list(steps)}")
            carried = int(record["state_before"]["count"])
            check(int(record["state_after"]["count"]) >= carried, f"state after {record['state_after']}")
            counts_past(carried + 499, 15, f"counts past {carried + 500}")
            window = ticks[mark:]
            check(not gaps(window), f"counts lost or repeated across the replacement: {gaps(window)[:5]}")
            check(carried in window and carried + 1 in window, f"{carried} -> {carried + 1} not seen")
            after = status()
            check(after["ticker"].node == "/ticker_2" and after["ticker"].container == "box"
                  and after["ticker"].pid == pid and after["ticker"].state == "active", f"status {after['ticker']}")
            check(set(box.nodes()) == {"/ticker_2", "/tally"}, f"the container holds {box.nodes()}")
            status_1_1 = Protocol(probe).control("ticker_2", 0)
            check(status_1_1.version == "1.1.0", f"ticker_2 runs {status_1_1.version}")
            missed = Protocol(probe).save("tally")["values"]["missed"]
            check(missed == missed_before, f"the tally (in the process) missed {missed - missed_before} counts")
            return (f"{steps['switch in container'][:200]}; count {carried} carried; {len(window)} counts "
                    f"{window[0]}..{window[-1]} none lost or repeated at the subscriber, none missed at the tally; "
                    "/ticker unloaded, /ticker_2 (1.1.0) in box")

        if not report.step("replace inside the container at 1 kHz: the count carried, none lost", in_container):
            return 1

        def second() -> str:
            s = status()
            box_pid = s["tally"].pid
            mark = len(ticks)
            code, record = replace(cfg["v2_iface"], cfg["package_v2"])
            check(code == 0 and record["result"] == "replaced", f"exit {code}: {json.dumps(record)[:1500]}")
            steps = {x["step"]: x["detail"] for x in record["steps"]}
            why = steps.get("second container", "")
            check("another ticker_msgs (an interface package)" in why and "box_3" in why, f"steps {steps}")
            check("switch in container" not in steps and "activate NEW" in steps, f"steps {list(steps)}")
            carried = int(record["state_before"]["count"])
            counts_past(carried + 499, 15, f"counts past {carried + 500}")
            window = ticks[mark:]
            check(not gaps(window), f"counts lost or repeated across the replacement: {gaps(window)[:5]}")
            after = status()
            t = after["ticker"]
            check(t.node == "/ticker_3" and t.container == "box_3" and t.state == "active"
                  and t.pid not in (0, box_pid), f"status {t}")
            check(after["tally"].container == "box" and after["tally"].pid == box_pid, f"tally {after['tally']}")
            check(set(box.nodes()) == {"/tally"}, f"box holds {box.nodes()}")
            check(set(ContainerCalls(Link(probe.node), "box_3").nodes()) == {"/ticker_3"}, "box_3 does not hold NEW")
            tally = Protocol(probe).save("tally")["values"]
            return (f"{why[:400]}; count {carried} carried, {len(window)} counts none lost or repeated at the "
                    f"subscriber; /ticker_3 (2.0.0) in box_3 (pid {t.pid}), the tally in box (pid {box_pid}, "
                    f"{tally['missed']} missed since its start, over DDS now)")

        if not report.step("replace by a NEW that cannot share the process: a second container, the reason recorded",
                           second):
            return 1

        def manager_killed() -> str:
            code, out, err = cli("snapshot", cfg["system"])
            check(code == 0, f"snapshot exit {code}: {err}")
            saved = json.loads(Path(next(f for f in json.loads(out)["files"] if Path(f).parent.name == "ticker"))
                               .read_text())["values"]["count"]
            s = status()
            before = {n: i.pid for n, i in s.items()}
            counts_past(saved + 300, 10, "300 ticks past the snapshot")
            os.kill(managers[-1][0].pid, signal.SIGKILL)
            managers[-1][0].wait(timeout=30)
            start_manager()
            after = settle(lambda x: all_active(x) and x["ticker"].pid not in (0, before["ticker"])
                           and x["tally"].pid not in (0, before["tally"]), 120, "a new manager: every instance active")
            t = after["ticker"]
            check(t.node == "/ticker_3" and t.container == "box_3" and after["tally"].container == "box",
                  f"ticker {t.node} in {t.container}, tally in {after['tally'].container}")
            check(after["sensor"].pid == before["sensor"], "the Python instance was not adopted")
            gone = [p for p in (before["ticker"], before["tally"]) if Path(f"/proc/{p}").exists()
                    and "Z" not in Path(f"/proc/{p}/stat").read_text().rsplit(")", 1)[1].split()[:1]]
            check(not gone, f"the previous manager's containers still run: {gone}")
            fresh = counts_after_restart(saved, "the ticker loaded again")
            log = manager_log()
            check("ticker: active in container box_3" in log and "snapshot" in log, "no restore of the ticker logged")
            check("a previous manager's pid" in log, "the new manager did not say it stopped the previous containers")
            return (f"the manager killed; a new one stopped the previous containers (pids {before['ticker']}, "
                    f"{before['tally']}), adopted the sensor (pid {before['sensor']}), loaded /ticker_3 into box_3 "
                    f"(pid {t.pid}) and the tally into box (pid {after['tally'].pid}); ticker counting again at {fresh[0]} "
                    f"(snapshot {saved})")

        report.step("kill -9 of the manager: a new one loads every instance again, NEW in its own container",
                    manager_killed)

        def down() -> str:
            manager = managers[-1][0]
            manager.send_signal(signal.SIGTERM)
            code = manager.wait(timeout=120)
            check(code == 0, f"the manager exited {code}")
            log = manager_log()
            at = [log.find(f"{n}: down") for n in ("tally", "ticker", "sensor")]
            check(-1 not in at and at == sorted(at), f"not down in reverse order: {at}")
            check(log.find("container box: stopped") > at[1], "the container stopped before its instances were down")
            left = {n: node_processes(n, cfg["own"]) for n in ("box", "box_3", "sensor", "ticker", "tally")}
            check(not any(left.values()), f"still running: {left}")
            return f"down in reverse order (log offsets {at}), the container stopped; manager exit 0; nothing left"

        report.step("down: reverse order, the container stopped, nothing left running", down)
    finally:
        for manager, _ in managers:
            if manager.poll() is None:
                os.killpg(manager.pid, signal.SIGKILL)
                manager.wait(timeout=30)
        for node in ("box", "box_3", "sensor", "ticker", "tally"):
            for pid in node_processes(node, cfg["own"]):
                os.kill(pid, signal.SIGKILL)
        probe.close()
    return 0 if all(s["ok"] for s in report.steps.values()) else 1


if __name__ == "__main__":
    run(main)
