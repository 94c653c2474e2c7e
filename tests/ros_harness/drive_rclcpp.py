"""Drive the generated C++ (rclcpp) counter through the Python node's checks and a hand-over with a Python counter.

    python drive_rclcpp.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_rclcpp_e2e.py with the ROS runtime's Python. The C++ counter 2.0
(examples/counter_v2.iface, tests/runtime/data/counter_v2_node.cpp) runs from its executable, the
Python counter 1.0 (examples/counter.iface, tests/runtime/data/counter_node.py) from its entry
point, each from its own workspace, each process stopped by its own handle. The checks are
drive_nodes.py's (lifecycle, parameters, QoS, /diagnostics while a callback blocks, control, Σ), then
`iface-lsp handover` from the Python node to a C++ one, and a state saved in C++ restored in Python.
Every wait is bounded; each step is written to RESULT.json as it ends.
"""

from __future__ import annotations

import argparse
import itertools
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout: tests.ros_harness

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402

from tests.ros_harness.probe import Component, Probe, Protocol, Report, check, incompatible, run  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("config", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--logs", type=Path, required=True)
    a = ap.parse_args()
    cfg = json.loads(a.config.read_text())
    a.logs.mkdir(parents=True, exist_ok=True)
    report = Report(a.out)
    from counter_msgs.msg import Count
    from counter_msgs.srv import Reset
    from iface_msgs.srv import ComponentControl

    probe = Probe()
    proto = Protocol(probe, "counter_msgs")
    cpp = [cfg["cpp_executable"]]
    started: list[Component] = []

    def start(argv: list[str], name: str, env: dict[str, str]) -> Component:
        p = Component(name, a.logs, argv, env=env)
        started.append(p)
        return p

    def up(node: str) -> None:
        probe.wait_ready(node, 30)

    def status(node: str) -> Any:
        return proto.control(node, ComponentControl.Request.STATUS, 5.0)

    def count_of(node: str) -> int:
        return int(proto.save(node)["values"]["count"])

    try:
        node = "counter_cpp"
        first = start(cpp, node, cfg["env_cpp"])

        def started_ok() -> str:
            up(node)
            line = probe.wait_until(lambda: next((x for x in first.log().splitlines() if "parameter file:" in x),
                                                 None), 10, "the parameter file line in the log")
            check(line.rstrip().endswith("share/counter/config/counter.params.yaml"), line)
            values = probe.params(node, ["rate_hz", "publish_parity"])
            check(values == {"rate_hz": 10.0, "publish_parity": True}, f"parameters {values}")
            return f"{Path(cfg['cpp_executable']).name}; {line.split('parameter file:')[1].strip()}; {values}"

        if not report.step("start: the executable with the installed parameter file", started_ok):
            return 1

        def lifecycle() -> str:
            check(probe.lifecycle_state(node) == "unconfigured", "not unconfigured at start")
            moved = [probe.transition(node, "configure"), probe.transition(node, "activate")]
            check(moved == ["unconfigured -> inactive", "inactive -> active"], str(moved))
            probe.wait_services(node, ("/counter/reset", f"/{node}/save_state", f"/{node}/restore_state",
                                       f"/{node}/control"))
            return ", ".join(moved)

        report.step("lifecycle: configure and activate through the standard services", lifecycle)

        def descriptors() -> str:
            rate = probe.describe(node, ["rate_hz"])["rate_hz"]
            check(rate.floating_point_range and rate.floating_point_range[0].from_value == 1.0
                  and rate.floating_point_range[0].to_value == 100.0, f"range {rate.floating_point_range}")
            check(rate.description == "Ticks per second.", f"description {rate.description!r}")
            check("unit: Hz" in rate.additional_constraints, f"constraints {rate.additional_constraints!r}")
            return f"rate_hz {rate.description!r} 1..100 ({rate.additional_constraints})"

        def refused() -> str:
            reasons = []
            for value in (500.0, 0.5):
                ok, reason = probe.set_param(node, "rate_hz", value)
                check(not ok and reason, f"rate_hz={value} was accepted")
                reasons.append(f"rate_hz={value}: {reason}")
            check(probe.params(node, ["rate_hz"]) == {"rate_hz": 10.0}, "rate_hz changed")
            return "; ".join(reasons)

        def applied() -> str:
            for name, value in (("rate_hz", 20.0), ("publish_parity", False)):
                ok, reason = probe.set_param(node, name, value)
                check(ok, f"{name}={value} refused: {reason}")
            values = probe.params(node, ["rate_hz", "publish_parity"])
            check(values == {"rate_hz": 20.0, "publish_parity": False}, f"values {values}")
            return str(values)

        report.step("parameters: descriptors with description, unit and range", descriptors)
        report.step("parameters: out-of-range values refused with a reason", refused)
        report.step("parameters: in-range values applied", applied)

        counts: list[int] = []

        def qos_and_topic() -> str:
            probe.subscribe(Count, "/count", lambda m: counts.append(m.value), QoSProfile(
                depth=1000, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE))
            pub = probe.endpoint_qos("/count", node, publisher=True)
            check(pub.reliability == ReliabilityPolicy.RELIABLE, f"/count reliability {pub.reliability}")
            check(pub.durability == DurabilityPolicy.VOLATILE, f"/count durability {pub.durability}")
            probe.wait_until(lambda: len(counts) >= 5, 15, "five counts")
            gaps = [(x, y) for x, y in itertools.pairwise(counts) if y != x + 1]
            check(not gaps, f"counts not consecutive: {gaps[:3]}")
            return f"/count reliable, volatile; {len(counts)} counts {counts[0]}..{counts[-1]}"

        report.step("qos: /count carries the declared QoS, counts published while active", qos_and_topic)

        def busy() -> str:
            diag = probe.diagnostics_of(f"/{node}")
            probe.wait_until(lambda: diag, 5, "/diagnostics")
            start_t = time.monotonic()
            reset = probe.call_async(Reset, "/counter/reset", Reset.Request())
            time.sleep(0.4)
            answer = status(node)
            answered = time.monotonic() - start_t
            check(answer.in_flight == 1, f"control saw {answer.in_flight} work transaction(s) in flight")
            done = probe.wait(reset, 15, "Reset")
            end = time.monotonic()
            check(done.done, "reset not done")
            during = [x for t, x in diag if start_t < t < end]
            check(len(during) >= 2, f"{len(during)} /diagnostics in {end - start_t:.1f} s at 1 Hz")
            in_flight = [{kv.key: kv.value for kv in x.values}.get("in_flight") for x in during]
            check("1" in in_flight, f"in_flight values {in_flight}")
            return (f"{len(during)} DiagnosticArray in {end - start_t:.1f} s of a blocking reset; ~/control answered "
                    f"after {answered:.1f} s with in_flight=1")

        report.step("diagnostics: published and control answered while a long callback runs", busy)

        def pause() -> str:
            reset = probe.call_async(Reset, "/counter/reset", Reset.Request())
            time.sleep(0.4)
            paused = proto.control(node, ComponentControl.Request.PAUSE)
            check(paused.success and paused.paused and paused.in_flight == 0, f"pause {paused.message}")
            check("after 1 work transaction" in paused.message, f"PAUSE did not wait for the reset: {paused.message}")
            probe.wait(reset, 10, "Reset")
            before = count_of(node)
            time.sleep(0.6)
            check(count_of(node) == before, "counted while paused")
            proto.control(node, ComponentControl.Request.RESUME)
            probe.wait_until(lambda: count_of(node) > before + 2, 10, "counting after RESUME")
            return f"{paused.message}; no count while paused, counting after resume"

        report.step("control: pause after the current transaction, resume", pause)

        saved: dict[str, Any] = {}
        second = "counter_cpp_b"

        def hand_over() -> str:
            proto.control(node, ComponentControl.Request.PAUSE)
            doc = proto.save(node)
            saved.update(doc)
            check(doc["schema"] == {"count": "int64"} and doc["format"] == "iface-state/1", str(doc))
            start(cpp, second, cfg["env_cpp"])
            up(second)
            probe.transition(second, "configure")
            answer = proto.restore(second, doc)
            check(answer.success and list(answer.restored) == ["count"], answer.message)
            check(proto.save(second)["values"] == doc["values"], "values differ after restore")
            probe.transition(second, "activate")
            probe.transition(node, "deactivate")
            proto.control(node, ComponentControl.Request.RESUME)
            before = doc["values"]["count"]
            probe.wait_until(lambda: count_of(second) > before + 2, 10, f"{second} counting on")
            check(count_of(node) == before, "the first instance still counts")
            return f"count {before} carried; {second} at {count_of(second)}; {answer.message}"

        report.step("state: saved from one instance, restored into a second, the counter continues", hand_over)

        def refused_restore() -> str:
            check(saved, "no saved state")
            answer = proto.restore(second, incompatible(saved, "count"))
            check(not answer.success and "'count'" in answer.message, f"{answer.message!r}")
            bad = proto.restore(second, "{")
            check(not bad.success and "not JSON" in bad.message, f"{bad.message!r}")
            wide = json.loads(json.dumps(saved))
            wide["values"]["count"] = 2 ** 63
            too_big = proto.restore(second, wide)
            check(not too_big.success and "does not fit int64" in too_big.message, f"{too_big.message!r}")
            return f"{answer.message} | {bad.message} | {too_big.message}"

        report.step("state: a restore from an incompatible interface is refused with a reason", refused_restore)

        def cleanup() -> str:
            check(probe.lifecycle_state(node) == "inactive", f"{node} is not inactive after the hand-over")
            before = count_of(node)
            time.sleep(0.5)
            check(count_of(node) == before, "the inactive node counted")
            moved = probe.transition(node, "cleanup")
            check(moved == "inactive -> unconfigured", moved)
            probe.wait_until(lambda: "/counter/reset" not in probe.services_of(node), 10,
                             "/counter/reset withdrawn from the node")
            check(f"/{node}/save_state" in probe.services_of(node), "the protocol services went with the members")
            return f"count stayed {before} while inactive; {moved}; /counter/reset withdrawn, the protocol kept"

        report.step("lifecycle: inactive does no work, cleanup withdraws the members", cleanup)

        def shutdown_cpp() -> str:
            out = []
            for p in [x for x in started if x.name in (node, second)]:
                probe.transition(p.name, "shutdown")
                code = p.wait_exit(15)
                check(code == 0, f"{p.name} exit status {code}")
                out.append(f"{p.name} exited {code}")
            return ", ".join(out)

        report.step("lifecycle: shutdown ends the process", shutdown_cpp)

        # ---- across languages: a Python counter 1.0 hands over to a C++ counter 2.0 ----------------------
        old_name, new_name = "counter", "counter_new"
        counts.clear()
        old = start([cfg["ros_python"], "-m", "counter", "--activate"], old_name, cfg["env_py"])
        start(cpp, new_name, cfg["env_cpp"])
        result: dict[str, Any] = {}

        def same_document() -> str:
            up(old_name)
            up(new_name)
            probe.wait_until(lambda: len(counts) >= 5, 30, "counts from the Python counter")
            proto.control(old_name, ComponentControl.Request.PAUSE)
            text = proto.save_raw(old_name).state
            probe.transition(new_name, "configure")
            answer = proto.restore(new_name, text)
            check(answer.success, answer.message)
            cpp_text = proto.save_raw(new_name).state
            proto.control(old_name, ComponentControl.Request.RESUME)
            mine, theirs = json.loads(cpp_text), json.loads(text)
            expected = text.replace(json.dumps(theirs["version"]), json.dumps(mine["version"])).replace(
                json.dumps(theirs["interface_hash"]), json.dumps(mine["interface_hash"])).replace(
                '"schedule":' + json.dumps(theirs["schedule"], separators=(",", ":"), sort_keys=True),
                '"schedule":' + json.dumps(mine["schedule"], separators=(",", ":"), sort_keys=True))
            check(cpp_text == expected, f"C++ {cpp_text} vs Python {text}")
            probe.transition(new_name, "cleanup")
            return f"Python saved {text}; the C++ node wrote the same bytes (but its version and hash)"

        report.step("state: the C++ node reads and writes the Python node's state document", same_document)

        def handover() -> str:
            base = [cfg["python"], "-m", "iface", "handover", old_name, new_name, "--old", cfg["old_iface"], "--new",
                    cfg["new_iface"], "--timeout", "10", "--trust-store", cfg["trust_store"], "--new-package"]
            # NEW's install tree with its executable changed after signing: refused before anything is touched
            cmd = [*base, cfg["tampered_package"]]
            refused = subprocess.run(cmd, env=cfg["env_cpp"], capture_output=True, text=True, timeout=180, check=False)
            (a.logs / "handover-refused.log").write_text(f"$ {' '.join(cmd)}\n{refused.stdout}\n{refused.stderr}\n")
            check(refused.returncode == 1, f"tampered package: exit {refused.returncode}: {refused.stderr[-1500:]}")
            check(f"{cfg['tampered_file']}: changed since it was signed" in refused.stderr, refused.stderr[-1500:])
            check(status(old_name).lifecycle_state == 3, "the refused hand-over touched the Python node")
            cmd = [*base, cfg["new_package"]]
            done = subprocess.run(cmd, env=cfg["env_cpp"], capture_output=True, text=True, timeout=180, check=False)
            (a.logs / "handover.log").write_text(f"$ {' '.join(cmd)}\n{done.stdout}\n{done.stderr}\n")
            check(done.returncode == 0, f"exit {done.returncode}: {done.stderr[-1500:]}")
            result.update(json.loads(done.stdout))
            steps = [s["step"] for s in result["steps"]]
            check("trust" in steps, f"no trust step: {steps}")
            return f"{result['result']}: {steps} (a tampered executable refused first)"

        def carried() -> str:
            before, after = result["state_before"], result["state_after"]
            check(after["count"] >= before["count"] > 0, f"count before {before['count']}, after {after['count']}")
            target = before["count"] + 10
            probe.wait_until(lambda: counts and counts[-1] >= target, 30, f"the C++ node counting past {target}")
            check(status(old_name).lifecycle_state == 2, "the Python node is not inactive")
            check(status(new_name).lifecycle_state == 3, "the C++ node is not active")
            gaps = [(x, y) for x, y in itertools.pairwise(counts) if y != x + 1]
            check(not gaps, f"counts not consecutive across the hand-over: {gaps[:5]}")
            return (f"count {before['count']} from Python, {after['count']} in C++, now {counts[-1]}; "
                    f"{len(counts)} counts, none lost or repeated; Python inactive, C++ active")

        if report.step("handover: iface-lsp handover from the Python counter 1.0 to the C++ counter 2.0", handover):
            report.step("handover: the count continues in C++, none lost, the Python node deactivated", carried)

        def back() -> str:
            doc = proto.save(new_name)
            answer = proto.restore(old_name, doc)
            check(answer.success, answer.message)
            check(count_of(old_name) == doc["values"]["count"], "the Python node did not take the count")
            return f"{answer.message}"

        report.step("state: saved from the C++ node, restored into the Python node", back)
        old.stop()
    finally:
        for p in started:
            p.stop()
        probe.close()
    return 0 if all(s["ok"] for s in report.steps.values()) else 1


if __name__ == "__main__":
    run(main)
