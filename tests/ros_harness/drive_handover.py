"""Drive a hand-over between two running counter components and report each step (run in a ROS 2 environment).

    python drive_handover.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_handover.py with the ROS runtime's Python. OLD (examples/counter.iface)
and NEW (examples/counter_v2.iface) run from their entry points, each from its own workspace, each
process stopped by its own handle; `iface-lsp handover` is run as a user would. Every wait is bounded.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout: tests.ros_harness
import itertools

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

from tests.ros_harness.probe import Component, Probe, Report, check, run  # noqa: E402

OLD, NEW = "counter", "counter_new"


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("config", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--logs", type=Path, required=True)
    a = ap.parse_args()
    cfg = json.loads(a.config.read_text())
    a.logs.mkdir(parents=True, exist_ok=True)
    report = Report(a.out)
    from counter_msgs.msg import Count, Parity
    from iface_msgs.srv import ComponentControl, Describe

    probe = Probe()
    counts: list[int] = []
    parities: list[Any] = []
    qos = QoSProfile(reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST, depth=1000)
    probe.subscribe(Count, "/count", lambda m: counts.append(m.value), qos)
    probe.subscribe(Parity, "/parity", parities.append, 10)
    old = Component(OLD, a.logs, [cfg["ros_python"], "-m", "counter", "--activate"], env=cfg["env_old"])
    new = Component(NEW, a.logs, [cfg["ros_python"], "-m", "counter"], env=cfg["env_new"])

    def status(node: str) -> Any:
        request = ComponentControl.Request(command=ComponentControl.Request.STATUS, timeout_sec=5.0)
        return probe.call(ComponentControl, f"/{node}/control", request, timeout=30)

    def handover(*extra: str, new_node: str = NEW, timeout: float = 10.0) -> tuple[int, dict[str, Any], str]:
        cmd = [cfg["python"], "-m", "iface", "handover", OLD, new_node, "--old", cfg["old_iface"],
               "--new", extra[0] if extra else cfg["new_iface"], "--timeout", str(timeout), *extra[1:]]
        done = subprocess.run(cmd, env=cfg["env_new"], capture_output=True, text=True, timeout=180, check=False)
        (a.logs / "handover.log").open("a").write(f"$ {' '.join(cmd)}\n{done.stdout}\n{done.stderr}\n")
        try:
            record = json.loads(done.stdout)
        except ValueError:
            record = {}
        return done.returncode, record, done.stderr

    def untouched() -> str:
        """OLD is active, not paused, and still counting."""
        s = status(OLD)
        check(s.lifecycle_state == 3, f"OLD is in lifecycle state {s.lifecycle_state}, not active")
        check(not s.paused, "OLD was left paused")
        seen = counts[-1] if counts else 0
        probe.wait_until(lambda: counts and counts[-1] > seen + 2, 30, "OLD counting on")
        return f"OLD active, not paused, counting ({seen} → {counts[-1]})"

    def refused(extra: tuple[str, ...], reason: str, **kw: Any) -> str:
        code, record, err = handover(*extra, **kw)
        check(code == 1, f"exit {code}, not 1: {err[-500:]}")
        check(record.get("result") == "refused", f"result {record.get('result')}")
        text = json.dumps(record) + err
        check(reason in text, f"the refusal does not say {reason!r}: {text[-800:]}")
        return f"refused ({reason}); " + untouched()

    try:
        report.step("start: OLD active and counting, NEW started", lambda: (
            probe.wait_until(lambda: len(counts) >= 10, 60, "10 counts from OLD"),
            check(status(NEW).lifecycle_state == 1, "NEW is not unconfigured"),
            f"OLD counted to {counts[-1]}")[-1])
        def one_protocol() -> str:
            types = {}
            for node in (OLD, NEW):
                name = f"/{node}/save_state"
                types[node] = probe.wait_until(lambda name=name: next(
                    (t for n, t in probe.node.get_service_names_and_types() if n == name), None), 30, name)
            check(types[OLD] == types[NEW] == ["iface_msgs/srv/SaveState"], f"save_state types {types}")
            answer = probe.call(Describe, f"/{NEW}/describe", Describe.Request(), timeout=30, idempotent=True)
            described = json.loads(answer.interface_json)
            check(answer.runtime == "rclpy" and answer.protocol_version == "1" and answer.component == "counter"
                  and answer.version == "2.0.0" and answer.node_name == f"/{NEW}", str(answer))
            check(described.get("name") == "counter" and answer.interface_json.startswith("{"), answer.interface_json)
            control = status(OLD)
            check(control.protocol_version == "1" and control.pid > 0, f"control {control}")
            return (f"both ~/save_state are {types[OLD][0]}; {NEW} describes {answer.component} {answer.version} "
                    f"({answer.runtime} {answer.runtime_version}, protocol {answer.protocol_version}), "
                    f"{len(answer.interface_json)} bytes of interface")

        report.step("protocol: one SaveState type for both components, ~/describe answers", one_protocol)
        report.step("refused: a provided service removed", lambda: refused((cfg["no_service_iface"],), "may not replace"))
        report.step("refused: a state variable retyped", lambda: refused((cfg["retyped_iface"],), "may not replace"))
        report.step("refused: NEW's interface hash is not the approved one",
                    lambda: refused((cfg["other_hash_iface"],), "not the one compat approved"))
        report.step("refused: NEW unsigned where a trust store is configured",
                    lambda: refused((cfg["new_iface"], "--trust-store", cfg["store"], "--new-package",
                                     cfg["unsigned_package"]), "is not signed"))
        report.step("refused: NEW signed by a key the trust store does not hold",
                    lambda: refused((cfg["new_iface"], "--trust-store", cfg["store"], "--new-package",
                                     cfg["foreign_package"]), "does not hold"))
        report.step("refused: NEW does not answer within the timeout",
                    lambda: refused((), "does not answer", new_node="counter_nobody", timeout=3.0))

        result: dict[str, Any] = {}

        def take_over() -> str:
            code, record, err = handover(cfg["new_iface"], "--trust-store", cfg["store"], "--new-package",
                                         cfg["package"])
            check(code == 0, f"exit {code}: {err[-1500:]}")
            result.update(record)
            names = [s["step"] for s in record["steps"]]
            check(names.index("prepare") < names.index("pause OLD"), f"not prepared before OLD paused: {names}")
            match = next((s["detail"] for s in record["steps"] if s["step"] == "match"), "")
            check(names.index("prepare") < names.index("match") < names.index("pause OLD")
                  and "/count" in match and "matched as OLD's are" in match,
                  f"NEW's publishers not matched before OLD paused: {match!r} in {names}")
            check(names.index("deactivate OLD") < names.index("activate NEW"), f"both active at once: {names}")
            critical = record.get("critical_section_ms")
            check(isinstance(critical, (int, float)) and critical > 0, f"critical section {critical!r}")
            saved = next(s["detail"] for s in record["steps"] if s["step"] == "save OLD")
            check(saved == "saved with the pause" and record.get("pause_ms", 0) > 0,
                  f"OLD's answer to the pause did not carry its state: {saved!r}, pause {record.get('pause_ms')!r} ms")
            return f"{record['result']}: {names}; critical section {critical} ms"

        def carried() -> str:
            before, after = result["state_before"], result["state_after"]
            check(isinstance(before, dict) and isinstance(after, dict), f"state before/after: {before}, {after}")
            check(after["count"] >= before["count"] > 0, f"count before {before['count']}, after {after['count']}")
            target = before["count"] + 20
            probe.wait_until(lambda: counts and counts[-1] >= target, 30, f"NEW counting past {target}")
            return f"count {before['count']} saved from OLD, {after['count']} in NEW, now {counts[-1]}"

        def switched() -> str:
            check(status(OLD).lifecycle_state == 2, "OLD is not inactive")
            check(status(NEW).lifecycle_state == 3, "NEW is not active")
            return "OLD inactive, NEW active"

        def gapless() -> str:
            gaps = [(x, y) for x, y in itertools.pairwise(counts) if y != x + 1]
            check(not gaps, f"counts not consecutive across the hand-over: {gaps[:5]}")
            check(counts[0] < result["state_before"]["count"] < counts[-1], "the hand-over is not inside the run")
            return f"{len(counts)} counts {counts[0]}..{counts[-1]}, none lost or repeated"

        def new_topic() -> str:
            probe.wait_until(lambda: parities, 20, "a /parity message from NEW")
            return f"{len(parities)} /parity messages"

        if report.step("handover: trusted, compatible NEW takes over", take_over):
            report.step("handover: every state value carried, the counter continues in NEW", carried)
            report.step("handover: OLD deactivated, NEW active", switched)
            report.step("handover: no message lost on the reliable topic NEW took over", gapless)
            report.step("handover: NEW's extra topic is published", new_topic)
            report.step("handover: the JSON shows the state before and after", lambda: (
                check("count" in result["state_before"] and "count" in result["state_after"], str(result)),
                json.dumps({"before": result["state_before"], "after": result["state_after"]}))[-1])
    finally:
        old.stop()
        new.stop()
        probe.close()
    return 0


if __name__ == "__main__":
    run(main)
