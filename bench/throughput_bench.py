"""Benchmark: messages per second through a generated rclpy component against a hand-written lifecycle node.

Run: ``python bench/throughput_bench.py [--messages 5000] [--rounds 3]`` — builds a relay component
(``subscribes Sample on "/in"``, ``publishes Sample on "/out"``; its node.py republishes each message)
with the ROS 2 runtime of ``../shared/ros2-runtime`` (``IFACE_ROS2_VENV``, default
``~/.cache/ros2-runtime``), and a hand-written ``rclpy.lifecycle.Node`` doing the same (a
subscription whose callback publishes on a lifecycle publisher, spun by ``rclpy.spin``). A driver
publishes ``--messages`` messages (reliable, keep all) as fast as the relay takes them and counts
what comes back; each relay is measured ``--rounds`` times, taking turns, and keeps its best round.
Prints messages/s of both and the ratio generated / hand-written (goal ≥ 0.9).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "server"))

RELAY_IFACE = """/** Republishes what it receives. */
component relay version "1.0.0" (maintainer = "bench", maintainer_email = "bench@example.com", license = "MIT")
namespace ros2 relay_msgs
message Sample { u64 seq, float64 value }
subscribes Sample on "/in" (qos.reliability = "reliable", qos.history = "keep_all")
publishes Sample on "/out" (qos.reliability = "reliable", qos.history = "keep_all")
"""
RELAY_USER = '''"""The relay: each message in is published out."""

from relay_msgs.msg import Sample

from .base import RelayBase


class Relay(RelayBase):
    def on_in(self, msg: Sample) -> None:
        self.publish_out(msg)
'''
HAND_WRITTEN = '''"""A hand-written rclpy lifecycle node doing what the generated relay does."""

import sys

import rclpy
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from relay_msgs.msg import Sample

QOS = QoSProfile(reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_ALL)


class HandRelay(LifecycleNode):
    def __init__(self) -> None:
        super().__init__("hand_relay")
        self.pub = None

    def on_configure(self, state):
        self.pub = self.create_lifecycle_publisher(Sample, "/out", QOS)
        self.create_subscription(Sample, "/in", self.on_in, QOS)
        return TransitionCallbackReturn.SUCCESS

    def on_in(self, msg: Sample) -> None:
        self.pub.publish(msg)


def main() -> None:
    rclpy.init(args=sys.argv)
    node = HandRelay()
    node.trigger_configure()
    node.trigger_activate()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
'''


def drive(messages: int) -> float:
    """In the ROS environment: publish ``messages`` on /in, wait for them on /out; messages per second."""
    import threading

    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
    from relay_msgs.msg import Sample

    rclpy.init()
    node = rclpy.create_node("throughput_driver")
    qos = QoSProfile(reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_ALL)
    got = [0]
    done = threading.Event()

    def received(msg: Sample) -> None:
        got[0] += 1
        if msg.seq == messages:
            done.set()
    node.create_subscription(Sample, "/out", received, qos)
    pub = node.create_publisher(Sample, "/in", qos)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    end = time.monotonic() + 60
    while time.monotonic() < end and (pub.get_subscription_count() == 0 or node.count_publishers("/out") == 0):
        time.sleep(0.05)
    probe_end = time.monotonic() + 30
    while got[0] == 0 and time.monotonic() < probe_end:  # the relay is active once a message comes back
        pub.publish(Sample(seq=0, value=0.0))
        time.sleep(0.1)
    time.sleep(0.5)
    got[0] = 0
    start = time.perf_counter()
    for i in range(1, messages + 1):
        pub.publish(Sample(seq=i, value=float(i)))
    finished = done.wait(120)
    seconds = time.perf_counter() - start
    executor.shutdown(timeout_sec=2.0)
    node.destroy_node()
    rclpy.try_shutdown()
    if not finished:
        raise SystemExit(f"only {got[0]} of {messages} messages came back within 120 s")
    return got[0] / seconds


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--messages", type=int, default=5000)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--drive", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--keep", type=Path, help="build into this folder, or reuse the relay built there before")
    args = ap.parse_args()
    if args.drive is not None:
        print(json.dumps(drive(args.drive)), flush=True)
        os._exit(0)  # rclpy's threads may abort the interpreter's own teardown ("terminate called…")
    os.environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT / "server"), os.environ.get("PYTHONPATH")) if p)
    from tests.ros_harness.ros import build, environment, generate, runtime_venv  # generate runs this checkout's iface

    venv, why = runtime_venv()
    if venv is None:
        print(f"throughput_bench: {why}", file=sys.stderr)
        return 2
    root = args.keep.resolve() if args.keep else Path(tempfile.mkdtemp(prefix="throughput-bench-"))
    gen, ws = root / "gen", root / "ws"
    seconds = 0.0
    if not (ws / "install" / "relay").is_dir():
        root.mkdir(parents=True, exist_ok=True)
        (root / "relay.iface").write_text(RELAY_IFACE, encoding="utf-8")
        ws.mkdir()
        done = generate(root / "relay.iface", gen)
        if done.returncode != 0:
            print(done.stderr, file=sys.stderr)
            return 3
        (gen / "relay" / "relay" / "node.py").write_text(RELAY_USER, encoding="utf-8")
        ok, tail, seconds = build(venv, gen, ws)
        if not ok:
            print(f"throughput_bench: the relay did not build:\n{tail}", file=sys.stderr)
            return 3
    (root / "hand_relay.py").write_text(HAND_WRITTEN, encoding="utf-8")
    env = environment(venv, ws, root / "ros-log")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")])
    relays = {"generated": [sys.executable, "-m", "relay", "--activate"],
              "hand-written": [sys.executable, str(root / "hand_relay.py")]}
    best: dict[str, float] = {}
    for _ in range(args.rounds):
        for name, cmd in relays.items():
            proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                    start_new_session=True)
            try:
                run = subprocess.run([sys.executable, __file__, "--drive", str(args.messages)], env=env,
                                     capture_output=True, text=True, timeout=300, check=False)
            finally:
                proc.terminate()
                try:
                    proc.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait(timeout=10)
            if run.returncode != 0 or not run.stdout.strip():
                print(f"throughput_bench: {name}: {run.stderr[-800:]}", file=sys.stderr)
                return 3
            rate = float(run.stdout.strip().splitlines()[-1])
            best[name] = max(best.get(name, 0.0), rate)
    if not args.keep:
        shutil.rmtree(root, ignore_errors=True)
    print(f"built in {seconds:.0f} s; {args.messages} messages, best of {args.rounds} rounds each")
    print(f"generated rclpy component: {best['generated']:8.0f} msg/s")
    print(f"hand-written lifecycle node: {best['hand-written']:6.0f} msg/s")
    print(f"ratio generated / hand-written: {best['generated'] / best['hand-written']:.2f} (goal >= 0.9)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
