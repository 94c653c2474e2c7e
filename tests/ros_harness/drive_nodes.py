"""Drive generated component nodes through a scenario and report each step (run in a ROS 2 environment).

    python drive_nodes.py SCENARIO --out RESULT.json --logs DIR

Started by tests/runtime/test_rclpy_e2e.py with the ROS runtime's Python and the built workspace
sourced. It starts the components from their entry point (``python -m <package>``), each process
with its own handle and stopped by it, talks to them as any ROS 2 tool would (lifecycle services,
parameter services, topics, services, actions, /diagnostics, the component protocol), bounds every
wait, and writes ``{step: {"ok", "detail", "seconds"}}`` to RESULT.json as it goes.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout: tests.ros_harness

from iface.nodes import remap  # noqa: E402 - this checkout's (the environment puts its server/ first)
from tests.ros_harness.probe import Component, Probe, Protocol, Report, check, entry_point, incompatible, run  # noqa: E402

#: Seconds between a publisher seeing its subscriber and publishing: DDS matches the two ends one after the
#: other, and a reliable volatile sample sent before the subscriber has matched the publisher is not delivered.
MATCH_SETTLE = 1.0


def robot_arm(report: Report, logs: Path) -> None:
    from geometry_msgs.msg import Pose  # noqa: F401 - the message package must load
    from robot_arm_msgs.action import FollowTrajectory
    from robot_arm_msgs.msg import JointCommand, JointState, TrajectoryPoint
    from robot_arm_msgs.srv import ArmDiagnostics, JointLimitsServiceGetLimits, MoveToPose

    probe = Probe()
    proto = Protocol(probe, "robot_arm_msgs")
    a = Component("robot_arm", logs, entry_point("robot_arm"))
    b: Component | None = None
    try:
        def start() -> str:
            probe.wait_ready("robot_arm")
            line = probe.wait_until(lambda: next((x for x in a.log().splitlines() if "parameter file:" in x), None),
                                    10, "the parameter file line in the log")
            check(line.rstrip().endswith("share/robot_arm/config/robot_arm.params.yaml"), line)
            values = probe.params("robot_arm", ["rate_hz", "max_speed", "watchdog_ms"])
            check(values == {"rate_hz": 250.0, "max_speed": 1.5, "watchdog_ms": 100}, f"parameters {values}")
            return f"python -m robot_arm; {line.split('parameter file:')[1].strip()}; {values}"

        if not report.step("start: entry point with the generated parameter file", start):
            return

        def configure() -> str:
            check(probe.lifecycle_state("robot_arm") == "unconfigured", "not unconfigured at start")
            moved = probe.transition("robot_arm", "configure")
            check(moved == "unconfigured -> inactive", moved)
            probe.wait_services("robot_arm", ("/arm/move_to_pose", "/arm/joint_limits/get_limits",
                                              "/robot_arm/save_state", "/robot_arm/restore_state",
                                              "/robot_arm/control", "/arm/diagnostics"))
            return moved

        report.step("lifecycle: configure", configure)

        def descriptors() -> str:
            d = probe.describe("robot_arm", ["rate_hz", "watchdog_ms", "max_speed"])
            rate, watchdog = d["rate_hz"], d["watchdog_ms"]
            check(rate.floating_point_range and rate.floating_point_range[0].from_value == 10.0
                  and rate.floating_point_range[0].to_value == 1000.0, f"rate_hz range {rate.floating_point_range}")
            check("Control loop rate" in rate.description, f"description {rate.description!r}")
            check("unit: Hz" in rate.additional_constraints, f"constraints {rate.additional_constraints!r}")
            check(watchdog.integer_range and watchdog.integer_range[0].from_value == 10
                  and watchdog.integer_range[0].to_value == 1000, f"watchdog_ms range {watchdog.integer_range}")
            check(not rate.read_only, "rate_hz is read-only")
            return f"rate_hz 10..1000 Hz ({rate.description!r}), watchdog_ms 10..1000"

        def refused() -> str:
            reasons = []
            for name, value in (("rate_hz", 5000.0), ("watchdog_ms", 5), ("max_speed", 0.0)):
                ok, reason = probe.set_param("robot_arm", name, value)
                check(not ok and reason, f"{name}={value} was accepted")
                reasons.append(f"{name}={value}: {reason}")
            values = probe.params("robot_arm", ["rate_hz", "watchdog_ms", "max_speed"])
            check(values == {"rate_hz": 250.0, "watchdog_ms": 100, "max_speed": 1.5}, f"values changed: {values}")
            return "; ".join(reasons)

        def applied() -> str:
            for name, value in (("rate_hz", 20.0), ("max_speed", 2.0), ("watchdog_ms", 500)):
                ok, reason = probe.set_param("robot_arm", name, value)
                check(ok, f"{name}={value} refused: {reason}")
            values = probe.params("robot_arm", ["rate_hz", "max_speed", "watchdog_ms"])
            check(values == {"rate_hz": 20.0, "max_speed": 2.0, "watchdog_ms": 500}, f"values {values}")
            return f"{values}"

        report.step("parameters: descriptors with description, unit and range", descriptors)
        report.step("parameters: out-of-range values refused with a reason", refused)
        report.step("parameters: in-range values applied", applied)
        report.step("lifecycle: activate", lambda: probe.transition("robot_arm", "activate"))

        def qos() -> str:
            pub = probe.endpoint_qos("/arm/joint_state", "robot_arm", publisher=True)
            check(pub.reliability == ReliabilityPolicy.BEST_EFFORT, f"joint_state reliability {pub.reliability}")
            check(pub.durability == DurabilityPolicy.VOLATILE, f"joint_state durability {pub.durability}")
            sub = probe.endpoint_qos("/arm/joint_command", "robot_arm", publisher=False)
            check(sub.reliability == ReliabilityPolicy.RELIABLE, f"joint_command reliability {sub.reliability}")
            return "joint_state best_effort/volatile, joint_command reliable"

        report.step("qos: topics carry the declared QoS", qos)

        states = probe.collect(JointState, "/arm/joint_state", QoSProfile(depth=10,
                                                                           reliability=ReliabilityPolicy.BEST_EFFORT))
        command_pub = probe.node.create_publisher(JointCommand, "/arm/joint_command", 10)

        def topics() -> str:
            probe.wait_until(lambda: command_pub.get_subscription_count() > 0, 10, "robot_arm subscribing")
            probe.wait_until(lambda: states, 10, "a JointState")
            time.sleep(MATCH_SETTLE)
            before = states[-1].position[0]
            for _ in range(3):
                command_pub.publish(JointCommand(timestamp=1, velocity=[0.1, 0.2, 0.3, 0.4, 0.5, 0.6], enable=True))
                time.sleep(0.1)
            probe.wait_until(lambda: states[-1].position[0] >= before + 3, 30, "three commands counted in JointState")
            last = states[-1]
            check(abs(last.velocity[5] - 0.6) < 1e-6, f"velocity {list(last.velocity)}")
            return f"JointState position[0] {before} -> {last.position[0]}, velocity echoed, mode {last.mode}"

        report.step("topic: JointCommand in, JointState out", topics)

        def services() -> str:
            request = MoveToPose.Request(speed_scale=0.05)
            request.target.frame_id = "base_link"
            moved = probe.call(MoveToPose, "/arm/move_to_pose", request)
            check(moved.success and "base_link" in moved.message, f"MoveToPose: {moved.message!r}")
            limits = probe.call(JointLimitsServiceGetLimits, "/arm/joint_limits/get_limits",
                                JointLimitsServiceGetLimits.Request(joint=2))
            check(limits.result.joint_name == "joint2" and abs(limits.result.max_velocity - 2.0) < 1e-9,
                  f"get_limits: {limits.result}")
            return f"MoveToPose {moved.message!r}; get_limits {limits.result.joint_name}"

        report.step("service: MoveToPose and a Thrift-style function", services)

        def action() -> str:
            client = probe.action_client(FollowTrajectory, "/arm/follow_trajectory")
            check(client.wait_for_server(timeout_sec=10), "no action server")
            goal = FollowTrajectory.Goal(points=[TrajectoryPoint(positions=[0.1 * i] * 6) for i in range(5)])
            feedback: list[Any] = []
            handle = probe.wait(client.send_goal_async(goal, feedback_callback=feedback.append), 10, "send_goal")
            check(handle.accepted, "goal rejected")
            result = probe.wait(handle.get_result_async(), 20, "the result")
            check(result.result.success, "not successful")
            check(len(feedback) >= 1, "no feedback")
            return f"5 points, {len(feedback)} feedback, success"

        report.step("action: FollowTrajectory goal, feedback, result", action)

        def delta_service() -> str:
            answer = probe.call(ArmDiagnostics, "/arm/diagnostics", ArmDiagnostics.Request(level=2))
            check(answer.summary == "active, level 2", f"summary {answer.summary!r}")
            return answer.summary

        report.step("diagnostics: the component's diagnostics service", delta_service)

        def busy() -> str:
            diag = probe.diagnostics_of("/robot_arm")
            probe.wait_until(lambda: diag, 5, "/diagnostics from robot_arm")
            request = MoveToPose.Request(speed_scale=1.0)  # 3 s in the handler
            request.target.frame_id = "tool"
            start = time.monotonic()
            move = probe.call_async(MoveToPose, "/arm/move_to_pose", request)
            time.sleep(0.5)
            status = proto.control("robot_arm", 0)
            status_at = time.monotonic()
            check(status.in_flight == 1, f"in_flight {status.in_flight} during the move")
            pause = proto.control_async("robot_arm", 1, timeout=10.0)
            moved = probe.wait(move, 15, "MoveToPose")
            moved_at = time.monotonic()
            paused = probe.wait(pause, 15, "PAUSE")
            paused_at = time.monotonic()
            check(moved.success, "the move failed")
            check(paused.success and paused.paused, f"pause: {paused.message}")
            check(paused_at >= moved_at - 0.3, "PAUSE answered before the transaction ended")
            during = [s for t, s in diag if start < t < moved_at]
            check(len(during) >= 2, f"{len(during)} /diagnostics messages during the 3 s move")
            return (f"{len(during)} DiagnosticArray during a {moved_at - start:.1f} s callback; STATUS answered "
                    f"after {status_at - start:.1f} s; PAUSE answered {paused_at - start:.1f} s "
                    f"({paused.message})")

        report.step("diagnostics: published and control answered while a long callback runs", busy)

        def refused_while_paused() -> str:
            before = proto.save("robot_arm")["values"]["trajectory_index"]
            command_pub.publish(JointCommand(enable=False))
            time.sleep(0.5)
            after = proto.save("robot_arm")["values"]["trajectory_index"]
            check(before == after, f"work done while paused: {before} -> {after}")
            resumed = proto.control("robot_arm", 2)
            check(resumed.success and not resumed.paused, resumed.message)
            command_pub.publish(JointCommand(enable=False))
            probe.wait_until(lambda: proto.save("robot_arm")["values"]["trajectory_index"] == before + 1, 10,
                             "the command after RESUME")
            return f"index {before} kept while paused; {before + 1} after resume"

        report.step("control: paused refuses work, resume accepts it", refused_while_paused)

        saved: dict[str, Any] = {}

        def hand_over() -> str:
            nonlocal b
            check(proto.control("robot_arm", 1).paused, "not paused")
            doc = proto.save("robot_arm")
            saved.update(doc)
            b = Component("robot_arm_b", logs, entry_point("robot_arm"))
            probe.wait_ready("robot_arm_b")
            probe.transition("robot_arm_b", "configure")
            answer = proto.restore("robot_arm_b", doc)
            check(answer.success, f"restore refused: {answer.message}")
            check(sorted(answer.restored) == sorted(doc["schema"]), f"restored {list(answer.restored)}")
            copied = proto.save("robot_arm_b")
            check(copied["values"] == doc["values"], f"{copied['values']} != {doc['values']}")
            probe.transition("robot_arm_b", "activate")
            probe.transition("robot_arm", "deactivate")
            proto.control("robot_arm", 2)
            index = doc["values"]["trajectory_index"]
            command_pub.publish(JointCommand(enable=True, velocity=[1.0] * 6))
            probe.wait_until(lambda: proto.save("robot_arm_b")["values"]["trajectory_index"] == index + 1, 10,
                             "the counter advancing in robot_arm_b")
            check(proto.save("robot_arm")["values"]["trajectory_index"] == index, "robot_arm still counting")
            return (f"every Σ value carried ({', '.join(sorted(doc['values']))}); trajectory_index {index} in "
                    f"robot_arm continued as {index + 1} in robot_arm_b; {answer.message}")

        report.step("state: saved from one instance, restored into a second, the counter continues", hand_over)

        def refused_restore() -> str:
            check(saved and b is not None, "no saved state")
            before = proto.save("robot_arm_b")["values"]
            answer = proto.restore("robot_arm_b", incompatible(saved, "trajectory_index"))
            check(not answer.success, "an incompatible state was restored")
            check("trajectory_index" in answer.message, f"reason {answer.message!r}")
            extra = json.loads(json.dumps(saved))
            extra["schema"]["gripper_force"] = "float64"
            extra["values"]["gripper_force"] = 1.0
            lost = proto.restore("robot_arm_b", extra)
            check(not lost.success and "gripper_force" in lost.message, f"lost variable: {lost.message!r}")
            check(proto.save("robot_arm_b")["values"] == before, "the state changed after a refused restore")
            return f"{answer.message} | {lost.message}"

        report.step("state: a restore from an incompatible interface is refused with a reason", refused_restore)

        def silent() -> str:
            probe.transition("robot_arm_b", "deactivate")
            time.sleep(0.5)
            states.clear()
            time.sleep(1.5)
            check(not states, f"{len(states)} JointState while inactive")
            return "no JointState for 1.5 s while both are inactive"

        report.step("lifecycle: deactivate silences the publisher", silent)

        def cleanup() -> str:
            probe.transition("robot_arm_b", "cleanup")
            probe.wait_until(lambda: "/arm/move_to_pose" not in probe.services_of("robot_arm_b"), 10,
                             "MoveToPose withdrawn from robot_arm_b")
            check("/robot_arm_b/save_state" in probe.services_of("robot_arm_b"), "save_state gone after cleanup")
            return "members withdrawn, protocol services kept"

        report.step("lifecycle: cleanup withdraws the members", cleanup)

        def shutdown() -> str:
            codes = []
            for comp in (a, b):
                assert comp is not None
                probe.transition(comp.name, "shutdown")
                code = comp.wait_exit(15)
                check(code == 0, f"{comp.name} exit status {code}")
                codes.append(f"{comp.name} exited {code}")
            return ", ".join(codes)

        report.step("lifecycle: shutdown ends the process", shutdown)
    finally:
        for comp in (a, b):
            if comp is not None:
                comp.stop()
        probe.close()


def every_member(report: Report, logs: Path) -> None:
    from every_member_msgs.action import Travel
    from every_member_msgs.msg import Command, Event, Heartbeat, Sample, Waypoint
    from every_member_msgs.srv import Count, Diagnostics, LimitsGetLimit, Work

    probe = Probe()
    proto = Protocol(probe, "every_member_msgs")
    s = Component("every_member", logs, entry_point("every_member"))
    peer_remaps = []  # the action by its five parts too: Jazzy's rcl does not remap action names
    for name in ("/station/command", "/station/sample", "/station/events", "/station/work", "/station/travel",
                 "/station/limits/get_limit", "/station/limits/reset"):
        peer_remaps += remap.arguments(name, name.replace("/station/", "/peer/"), action=name == "/station/travel")
    peer = Component("peer", logs, entry_point("every_member", "--activate"), tuple(peer_remaps))
    s2: Component | None = None
    names = ["gain", "retries", "priority", "enabled", "label", "start_mode", "offsets", "ids", "tags", "serial"]
    try:
        def start() -> str:
            probe.wait_ready("every_member")
            values = probe.params("every_member", names)
            wanted = {"gain": 1.5, "retries": 3, "priority": 5, "enabled": True, "label": "station",
                      "start_mode": 0, "offsets": [0.0, 0.5, 1.0], "ids": [1, 2], "tags": ["a", "b"],
                      "serial": "SN-1"}
            values = {k: list(v) if isinstance(v, (list, tuple)) or hasattr(v, "tolist") else v
                      for k, v in values.items()}
            check(values == wanted, f"parameters {values}")
            return f"{len(values)} parameters from the generated file"

        if not report.step("start: entry point with the generated parameter file", start):
            return

        def descriptors() -> str:
            d = probe.describe("every_member", names)
            check(d["gain"].floating_point_range[0].to_value == 10.0, "gain range")
            check([(r.from_value, r.to_value) for r in d["retries"].integer_range] == [(0, 10)], "retries range")
            check([(r.from_value, r.to_value) for r in d["priority"].integer_range] == [(0, 255)], "priority u8")
            check(d["serial"].read_only, "serial is not read-only")
            check("one of: IDLE (0)" in d["start_mode"].additional_constraints, "start_mode choices")
            check("at most 8 characters" in d["label"].additional_constraints, "label length")
            return "ranges, u8 bounds, enum choices, length, read-only"

        def refused() -> str:
            out = []
            for name, value in (("gain", 11.0), ("retries", -1), ("priority", 300), ("label", "much too long"),
                                ("start_mode", 7), ("offsets", [1.0, 2.0]), ("ids", [1, 2, 3, 4, 5]),
                                ("serial", "SN-2")):
                ok, reason = probe.set_param("every_member", name, value)
                check(not ok and reason, f"{name}={value} accepted")
                out.append(f"{name}: {reason}")
            return "; ".join(out)

        def applied() -> str:
            wanted = {"gain": 2.5, "label": "st2", "start_mode": 2, "offsets": [1.0, 2.0, 3.0], "ids": [7],
                      "enabled": False}
            for name, value in wanted.items():
                ok, reason = probe.set_param("every_member", name, value)
                check(ok, f"{name}={value} refused: {reason}")
            values = probe.params("every_member", list(wanted))
            values = {k: list(v) if hasattr(v, "__len__") and not isinstance(v, str) else v for k, v in values.items()}
            check(values == wanted, f"{values}")
            return f"{values}"

        report.step("parameters: descriptors with description, unit and range", descriptors)
        report.step("parameters: out-of-range values refused with a reason", refused)
        report.step("parameters: in-range values applied", applied)

        def lifecycle() -> str:
            moved = [probe.transition("every_member", "configure"), probe.transition("every_member", "activate")]
            probe.wait_until(lambda: "/peer/count" in probe.services_of("peer"), 20, "the peer")
            return "; ".join(moved)

        report.step("lifecycle: configure and activate", lifecycle)

        def qos() -> str:
            pub = probe.endpoint_qos("/station/sample", "every_member", publisher=True)
            check(pub.reliability == ReliabilityPolicy.RELIABLE, f"reliability {pub.reliability}")
            check(pub.durability == DurabilityPolicy.TRANSIENT_LOCAL, f"durability {pub.durability}")
            check(pub.deadline.nanoseconds == 2_000_000_000, f"deadline {pub.deadline}")
            check(pub.lifespan.nanoseconds == 10_000_000_000, f"lifespan {pub.lifespan}")
            check(pub.liveliness_lease_duration.nanoseconds == 3_000_000_000, f"lease {pub.liveliness_lease_duration}")
            events = probe.endpoint_qos("/station/events", "every_member", publisher=True)
            check(events.reliability == ReliabilityPolicy.BEST_EFFORT, f"events {events.reliability}")
            command = probe.endpoint_qos("/station/command", "every_member", publisher=False)
            check(command.reliability == ReliabilityPolicy.RELIABLE, f"command {command.reliability}")
            return ("sample reliable, transient_local, deadline 2 s, lifespan 10 s, lease 3 s; events best_effort; "
                    "command reliable")

        report.step("qos: topics carry the declared QoS", qos)

        def depth() -> str:
            live = probe.collect(Sample, "/station/sample", QoSProfile(depth=50, reliability=ReliabilityPolicy.RELIABLE))
            probe.wait_until(lambda: len(live) >= 10, 15, "ten samples")
            probe.transition("every_member", "deactivate")
            time.sleep(0.5)
            last = max(m.seq for m in live)
            late: list[Any] = probe.collect(Sample, "/station/sample", QoSProfile(
                depth=100, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                durability=DurabilityPolicy.TRANSIENT_LOCAL))
            probe.wait_until(lambda: len(late) >= 7, 10, "the kept samples")
            time.sleep(1.0)
            seqs = [m.seq for m in late]
            probe.transition("every_member", "activate")
            check(seqs == list(range(last - 6, last + 1)), f"late joiner got {seqs}, last published {last}")
            return f"a late transient_local subscriber got the last 7 samples ({seqs[0]}..{seqs[-1]}): depth 7"

        report.step("qos: depth and durability (a late joiner gets the kept history)", depth)

        events = probe.collect(Event, "/station/events", QoSProfile(depth=100,
                                                                     reliability=ReliabilityPolicy.BEST_EFFORT))
        command_pub = probe.node.create_publisher(Command, "/station/command", 10)
        beat_pub = probe.node.create_publisher(Heartbeat, "/heartbeat", 10)

        def counter(node: str = "every_member") -> int:
            return int(proto.save(node)["values"]["counter"])

        def topics() -> str:
            probe.wait_until(lambda: command_pub.get_subscription_count() > 0, 10, "every_member subscribing")
            probe.wait_until(lambda: beat_pub.get_subscription_count() > 0, 10, "a subscription on heartbeat")
            time.sleep(MATCH_SETTLE)
            before = counter()
            for _ in range(3):
                command_pub.publish(Command(step=2))
                beat_pub.publish(Heartbeat(beat=1))
            probe.wait_until(lambda: counter() == before + 6, 30, "three commands")
            probe.wait_until(lambda: any(e.text == f"counter {before + 6}" for e in events), 30, "the event")
            return f"counter {before} -> {before + 6}; event published; heartbeat on the relative name"

        report.step("topic: subscriptions and publishers", topics)

        def services() -> str:
            count = probe.call(Count, "/every_member/count", Count.Request(add=4))
            limit = probe.call(LimitsGetLimit, "/station/limits/get_limit", LimitsGetLimit.Request(name="abc"))
            check(limit.result == 9, f"get_limit {limit.result}")
            work = probe.call(Work, "/station/work", Work.Request(seconds=0.1))
            check(work.done and work.counter == count.counter, f"work {work}")
            return f"~/count -> {count.counter}; get_limit 9; work done"

        report.step("service: provided services (node-relative, Thrift-style)", services)

        def clients() -> str:
            peer_before = counter("peer")
            events.clear()
            command_pub.publish(Command(step=-3))
            probe.wait_until(lambda: any(e.text == "peer travel visited 2" for e in events), 20,
                             "the peer's travel result")
            check(counter("peer") == peer_before + 3, "the peer's counter did not advance by 3")
            label = proto.save("every_member")["values"]["last_label"]
            check(label == f"peer:{peer_before + 3}", f"last_label {label!r}")
            return f"called /peer/count ({label}) and sent a goal to /peer/travel (visited 2)"

        report.step("client: a service client and an action client reach their servers", clients)

        def action() -> str:
            client = probe.action_client(Travel, "/station/travel")
            check(client.wait_for_server(timeout_sec=10), "no action server")
            goal = Travel.Goal(waypoints=[Waypoint(x=float(i), y=0.0, name=f"w{i}") for i in range(3)])
            feedback: list[Any] = []
            handle = probe.wait(client.send_goal_async(goal, feedback_callback=feedback.append), 10, "send_goal")
            check(handle.accepted, "rejected")
            result = probe.wait(handle.get_result_async(), 20, "result")
            check(result.result.reached and result.result.visited == 3, f"result {result.result}")
            target = proto.save("every_member")["values"]["target"]
            check(target == {"x": 2.0, "y": 0.0, "name": "w2"}, f"target {target}")
            return f"3 waypoints, {len(feedback)} feedback, state.target {target}"

        report.step("action: goal, feedback, result", action)

        def busy() -> str:
            diag = probe.diagnostics_of("/every_member")
            probe.wait_until(lambda: diag, 5, "/diagnostics")
            start = time.monotonic()
            work = probe.call_async(Work, "/station/work", Work.Request(seconds=2.5))
            time.sleep(0.4)
            answer = probe.call(Diagnostics, "/every_member/diagnostics", Diagnostics.Request(level=3), timeout=2)
            answered = time.monotonic() - start
            check(answer.summary == "level 3, busy", f"diagnostics service: {answer.summary!r}")
            done = probe.wait(work, 15, "Work")
            end = time.monotonic()
            during = [x for t, x in diag if start < t < end]
            check(done.done, "work not done")
            check(len(during) >= 6, f"{len(during)} /diagnostics in {end - start:.1f} s at 4 Hz")
            busy_values = [{kv.key: kv.value for kv in x.values}.get("in_flight") for x in during]
            check("1" in busy_values, f"in_flight values {busy_values}")
            return (f"{len(during)} DiagnosticArray in {end - start:.1f} s of a blocking callback (4 Hz); the Δ "
                    f"service answered after {answered:.1f} s with {answer.summary!r}")

        report.step("diagnostics: published and control answered while a long callback runs", busy)

        def pause() -> str:
            work = probe.call_async(Work, "/station/work", Work.Request(seconds=1.5))
            time.sleep(0.3)
            paused = proto.control("every_member", 1)
            check(paused.success and paused.paused and paused.in_flight == 0, f"pause {paused.message}")
            check("after 1 work transaction" in paused.message, f"PAUSE did not wait for Work: {paused.message}")
            check(probe.wait(work, 10, "Work").done, "Work failed")
            before = counter()
            command_pub.publish(Command(step=5))
            time.sleep(0.5)
            check(counter() == before, "a command was handled while paused")
            proto.control("every_member", 2)
            command_pub.publish(Command(step=5))
            probe.wait_until(lambda: counter() == before + 5, 10, "the command after RESUME")
            return f"{paused.message}; command refused while paused, handled after resume"

        report.step("control: pause after the current transaction, resume", pause)

        saved: dict[str, Any] = {}

        def hand_over() -> str:
            nonlocal s2
            proto.control("every_member", 1)
            doc = proto.save("every_member")
            saved.update(doc)
            check(set(doc["values"]) == {"counter", "last_label", "position", "target", "mode", "busy", "history",
                                         "flags"}, f"variables {sorted(doc['values'])}")
            s2 = Component("every_member_b", logs, entry_point("every_member"))
            probe.wait_ready("every_member_b")
            probe.transition("every_member_b", "configure")
            answer = proto.restore("every_member_b", doc)
            check(answer.success, answer.message)
            copied = proto.save("every_member_b")
            check(copied["values"] == doc["values"], f"{copied['values']} != {doc['values']}")
            probe.transition("every_member_b", "activate")
            probe.transition("every_member", "deactivate")
            proto.control("every_member", 2)
            before = doc["values"]["counter"]
            command_pub.publish(Command(step=1))
            probe.wait_until(lambda: counter("every_member_b") == before + 1, 10, "every_member_b counting on")
            check(counter("every_member") == before, "the first instance still counts")
            return f"all 8 Σ values carried {doc['values']}; counter {before} -> {before + 1} in the second"

        report.step("state: saved from one instance, restored into a second, the counter continues", hand_over)

        def refused_restore() -> str:
            check(saved, "no saved state")
            answer = proto.restore("every_member_b", incompatible(saved, "counter"))
            check(not answer.success and "counter" in answer.message, f"{answer.message!r}")
            nested = json.loads(json.dumps(saved))
            nested["types"]["every_member_msgs/Waypoint"]["z"] = "float64"
            other = proto.restore("every_member_b", nested)
            check(not other.success and "Waypoint" in other.message, f"{other.message!r}")
            return f"{answer.message} | {other.message}"

        report.step("state: a restore from an incompatible interface is refused with a reason", refused_restore)

        def shutdown_waits() -> str:
            logged = len(peer.log())
            work = probe.call_async(Work, "/peer/work", Work.Request(seconds=1.5))
            time.sleep(0.4)  # the work transaction runs when the shutdown comes
            start = time.monotonic()
            probe.transition(peer.name, "shutdown")
            took = time.monotonic() - start
            answer = probe.wait(work, 10, "the Work in progress at the shutdown")
            check(answer.done, "the Work in progress at the shutdown was not done")
            code = peer.wait_exit(15)
            check(code == 0, f"peer exit status {code}")
            log = peer.log()[logged:]
            check("members destroyed while" not in log and "ERROR" not in log, log[-2000:])
            return f"the shutdown took {took:.1f} s: the Work in progress ended and was answered first; exit {code}"

        report.step("lifecycle: shutdown waits for the work in progress, then destroys the members", shutdown_waits)

        def shutdown() -> str:
            out = []
            for comp in (s, s2):
                assert comp is not None
                probe.transition(comp.name, "shutdown")
                code = comp.wait_exit(15)
                check(code == 0, f"{comp.name} exit status {code}")
                out.append(f"{comp.name} exited {code}")
            return ", ".join(out)

        report.step("lifecycle: shutdown ends the process", shutdown)
    finally:
        for comp in (s, peer, s2):
            if comp is not None:
                comp.stop()
        probe.close()


SCENARIOS = {"robot_arm": robot_arm, "every_member": every_member}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", choices=sorted(SCENARIOS))
    parser.add_argument("--out", required=True)
    parser.add_argument("--logs", required=True)
    args = parser.parse_args()
    logs = Path(args.logs)
    logs.mkdir(parents=True, exist_ok=True)
    report = Report(Path(args.out))
    print(f"drive_nodes: {args.scenario}, ROS_DOMAIN_ID {os.environ.get('ROS_DOMAIN_ID')}", flush=True)
    SCENARIOS[args.scenario](report, logs)
    return 0 if all(s["ok"] for s in report.steps.values()) else 1


if __name__ == "__main__":
    run(main)
