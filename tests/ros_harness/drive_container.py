"""Generated C++ components in one component container, and hand-overs from C++ to C++ and to Python.

    python drive_container.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_rclcpp_e2e.py with the ROS runtime's Python, in the environment of every
workspace it built: iface_msgs and iface_runtime_cpp with the C++ counter 2.0, the C++ counter 1.0 on
top of it (one counter_msgs per process: 2.0's, which holds 1.0's), and every_member. One
component_container_mt loads counter 1.0 and 2.0 by their versioned names (counter@1.0.0,
counter@2.0.0) and every_member by its package, side by side; `iface-lsp handover` replaces 1.0 by
2.0 inside the container; then the C++ counter 1.0's executable hands over to the Python counter 1.0.
Every wait is bounded; each process is stopped by its own handle; each step is written to RESULT.json
as it ends.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout: tests.ros_harness

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402

from tests.ros_harness.probe import Component, Probe, Protocol, Report, check, run  # noqa: E402

CONTAINER = "iface_container"


def prefix_of(package: str, env: dict[str, str]) -> Path:
    """The install prefix of an ament package in ``env``."""
    for prefix in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        if prefix and (Path(prefix) / "share" / "ament_index" / "resource_index" / "packages" / package).is_file():
            return Path(prefix)
    raise FileNotFoundError(f"{package} is not installed (AMENT_PREFIX_PATH)")


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("config", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--logs", type=Path, required=True)
    a = ap.parse_args()
    cfg = json.loads(a.config.read_text())
    a.logs.mkdir(parents=True, exist_ok=True)
    report = Report(a.out)
    from composition_interfaces.srv import ListNodes, LoadNode, UnloadNode
    from counter_msgs.msg import Count
    from counter_msgs.srv import Reset
    from iface_msgs.srv import ComponentControl, Describe

    probe = Probe()
    env = cfg["env"]
    started: list[Component] = []
    counts: list[tuple[float, int]] = []
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
    probe.subscribe(Count, "/count", lambda m: counts.append((time.monotonic(), m.value)), qos)
    base = f"/{CONTAINER}/_container"
    loaded: dict[str, int] = {}

    def start(argv: list[str], name: str, penv: dict[str, str]) -> Component:
        p = Component(name, a.logs, argv, env=penv)
        started.append(p)
        return p

    def status(node: str) -> Any:
        """~/control STATUS, with the types ``node`` serves it with (iface_msgs; a Python node's may differ)."""
        types = probe.wait_until(lambda: dict(probe.node.get_service_names_and_types()).get(f"/{node}/control"),
                                 30, f"/{node}/control in the graph")
        return Protocol(probe, types[0].split("/")[0]).control(node, ComponentControl.Request.STATUS)

    def handover(old: str, new: str, old_iface: str, new_iface: str, log: str) -> dict[str, Any]:
        cmd = [cfg["python"], "-m", "iface", "handover", old, new, "--old", old_iface, "--new", new_iface,
               "--timeout", "10"]
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=180, check=False)
        (a.logs / log).write_text(f"$ {' '.join(cmd)}\n{done.stdout}\n{done.stderr}\n")
        check(done.returncode == 0, f"exit {done.returncode}: {done.stdout[-1500:]} {done.stderr[-1500:]}")
        return json.loads(done.stdout)

    def continued(before: int, since: int) -> str:
        """The counts seen since index ``since`` are consecutive and pass ``before`` + 10."""
        target = before + 10
        probe.wait_until(lambda: counts and counts[-1][1] >= target, 30, f"counts past {target}")
        values = [v for _, v in counts[since:]]
        gaps = [(x, y) for x, y in itertools.pairwise(values) if y != x + 1]
        check(not gaps, f"counts not consecutive across the hand-over: {gaps[:5]}")
        return f"{len(values)} counts {values[0]}..{values[-1]}, none lost or repeated"

    try:
        exe = prefix_of("rclcpp_components", env) / "lib" / "rclcpp_components" / "component_container_mt"
        container = start([str(exe)], CONTAINER, env)

        def container_up() -> str:
            for service in ("load_node", "unload_node", "list_nodes"):
                probe.wait_until(lambda s=service: f"{base}/{s}" in probe.services_of(CONTAINER), 30,
                                 f"{base}/{service}")
            return f"{exe.name} (pid {container.proc.pid}) serves {base}/load_node"

        if not report.step("container: component_container_mt starts", container_up):
            return 1

        def load_side_by_side() -> str:
            out = []
            for package, plugin, node in (("counter@1.0.0", "counter::Counter", "counter_one"),
                                          ("counter@2.0.0", "counter::Counter", "counter_two"),
                                          ("every_member", "every_member::EveryMember", "em")):
                request = LoadNode.Request(package_name=package, plugin_name=plugin, node_name=node)
                answer = probe.call(LoadNode, f"{base}/load_node", request, timeout=60)
                check(answer.success, f"load_node {package} {plugin}: {answer.error_message!r}")
                loaded[node] = answer.unique_id
                out.append(f"{package} as {answer.full_node_name}")
            listed = probe.call(ListNodes, f"{base}/list_nodes", ListNodes.Request(), idempotent=True)
            check(sorted(listed.full_node_names) == ["/counter_one", "/counter_two", "/em"],
                  f"list_nodes: {list(listed.full_node_names)}")
            described = {}
            for node in loaded:
                probe.wait_ready(node, 30)
                answer = probe.call(Describe, f"/{node}/describe", Describe.Request(), idempotent=True)
                described[node] = (answer.component, answer.version, answer.runtime)
                check(json.loads(answer.interface_json)["component"]["name"] == answer.component,
                      f"{node}: the interface of ~/describe is not {answer.component}'s")
            check(described == {"counter_one": ("counter", "1.0.0", "rclcpp"),
                                "counter_two": ("counter", "2.0.0", "rclcpp"),
                                "em": ("every_member", "2.1.0", "rclcpp")}, str(described))
            check(container.proc.poll() is None, "the container has exited")
            return f"{'; '.join(out)}; ~/describe: {described}"

        if not report.step("container: counter 1.0 and 2.0 and every_member load side by side", load_side_by_side):
            return 1
        result: dict[str, Any] = {}

        def in_container() -> str:
            moved = [probe.transition("counter_one", "configure"), probe.transition("counter_one", "activate")]
            probe.wait_until(lambda: len(counts) >= 5, 30, "counts from counter 1.0 in the container")
            result.update(handover("counter_one", "counter_two", cfg["old_iface"], cfg["new_iface"],
                                   "handover_container.log"))
            check(result["result"] == "replaced", str(result))
            before = result["state_before"]["count"]
            done = continued(before, next(i for i, (_, v) in enumerate(counts) if v == before))
            check(status("counter_one").lifecycle_state == 2, "counter 1.0 is not inactive")
            check(status("counter_two").lifecycle_state == 3, "counter 2.0 is not active")
            check(container.proc.poll() is None, "the container has exited")
            # NEW continues OLD's schedule: its first tick is due one period (0.1 s) after OLD's last.
            found = re.search(r"\[counter_two\]: schedule: timer 'tick' continues the restored state's 'tick': last tick "
                              r"at ([\d.]+), the first tick due at ([\d.]+) \(period ([\d.]+) s", container.log())
            check(found, "counter 2.0 did not say that it continues counter 1.0's schedule")
            last, due, period = (float(x) for x in found.groups())
            check(period == 0.1 and abs(due - (last + period)) < 1e-5, found.group(0))
            at = {v: when for when, v in counts}
            gap = (at[before + 1] - at[before]) * 1000
            return (f"{moved}; count {before} carried from 1.0 to 2.0 in one process; {done}; 2.0's first tick due "
                    f"{period:g} s after 1.0's last; /count {before} -> {before + 1}: {gap:.0f} ms apart")

        report.step("container: handover from counter 1.0 to 2.0 inside the container", in_container)

        def unload() -> str:
            # counter 2.0's reset holds a work transaction for 2.5 s: the container's executor is inside the
            # node when it is unloaded, and the unload must wait for that callback, not delete the node under it.
            sent = time.monotonic()
            probe.call_async(Reset, "/counter/reset", Reset.Request())
            probe.wait_until(lambda: status("counter_two").in_flight == 1, 10, "a reset running in counter 2.0")
            answer = probe.call(UnloadNode, f"{base}/unload_node", UnloadNode.Request(unique_id=loaded["counter_two"]),
                                timeout=30)
            waited = time.monotonic() - sent
            check(answer.success, f"unload counter_two: {answer.error_message!r}")
            check(waited >= 2.4, f"the unload answered {waited:.2f} s after the reset was sent, before its 2.5-s "
                                 "callback could end: the node was deleted under a running callback")
            check(container.proc.poll() is None, "the container exited unloading a node inside a callback")
            loaded.pop("counter_two")
            for node, unique_id in list(loaded.items()):
                answer = probe.call(UnloadNode, f"{base}/unload_node", UnloadNode.Request(unique_id=unique_id),
                                    timeout=30)
                check(answer.success, f"unload {node}: {answer.error_message!r}")
                loaded.pop(node)
            listed = probe.call(ListNodes, f"{base}/list_nodes", ListNodes.Request(), idempotent=True)
            check(not listed.unique_ids, f"list_nodes after unload: {list(listed.full_node_names)}")
            check(container.proc.poll() is None, "the container has exited")
            container.stop()
            return (f"counter 2.0 unloaded inside its reset (answered {waited:.1f} s after it: the callback ended "
                    f"first), then the rest; the container stopped with {container.proc.returncode}")

        report.step("container: the components unload, the container keeps running", unload)

        def cpp_to_python() -> str:
            counts.clear()
            start([cfg["cpp_v1"], "--activate"], "counter_c", cfg["env_v1"])
            start([cfg["ros_python"], "-m", "counter"], "counter_p", cfg["env_py"])
            for node in ("counter_c", "counter_p"):
                probe.wait_ready(node, 30)
            probe.wait_until(lambda: len(counts) >= 5, 30, "counts from the C++ counter 1.0")
            got = handover("counter_c", "counter_p", cfg["old_iface"], cfg["old_iface"], "handover_cpp_py.log")
            check(got["result"] == "replaced", str(got))
            before = got["state_before"]["count"]
            done = continued(before, next(i for i, (_, v) in enumerate(counts) if v == before))
            check(status("counter_c").lifecycle_state == 2, "the C++ node is not inactive")
            check(status("counter_p").lifecycle_state == 3, "the Python node is not active")
            return f"count {before} carried from C++ to Python; {done}"

        report.step("handover: the C++ counter 1.0 to the Python counter 1.0", cpp_to_python)
    finally:
        for p in started:
            p.stop()
        probe.close()
    return 0 if all(s["ok"] for s in report.steps.values()) else 1


if __name__ == "__main__":
    run(main)
