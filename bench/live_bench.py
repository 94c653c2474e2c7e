"""Benchmark: live truth (``import --from node``, ``verify``) on a running system of ten rclpy nodes.

Run, with ROS 2 sourced: ``python3 bench/live_bench.py [--nodes 10] [--repeat 5]`` — starts ten nodes
(two publishers, a subscription, a service, a client and three parameters each, std_msgs and
diagnostic_msgs types only) in a process of their own on loopback, in a ROS domain of its own, waits
for discovery, then prints the best and median time of importing one node (graph reads, parameter
service calls, the .iface text) and of verifying the ten-node system against the files imported
from it (the graph reads and the comparison), and the wall time of each as a CLI run (a fresh
process: Python start, discovery, the work). Goal: ≤ 2 s each after discovery.
"""

from __future__ import annotations

import argparse
import os
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "server"))

NODES = '''
import sys, rclpy
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import Float64, Int32, String
from diagnostic_msgs.srv import SelfTest
rclpy.init()
nodes = []
n = int(sys.argv[1])
for i in range(n):
    node = Node(f"bench_{i}", namespace="/bench")
    node.create_publisher(String, f"/bench/t{i}", 10)
    node.create_publisher(Float64, f"/bench/f{i}", 5)
    node.create_subscription(String, f"/bench/t{(i + 1) % n}", lambda m: None, 10)
    node.create_service(SelfTest, f"~/self_test", lambda a, b: b)
    node.create_client(SelfTest, f"/bench/bench_{(i + 1) % n}/self_test")
    node.declare_parameter("rate", 1.5)
    node.declare_parameter("count", i)
    node.declare_parameter("name", f"n{i}")
    nodes.append(node)
ex = MultiThreadedExecutor()
for node in nodes:
    ex.add_node(node)
print("ready", flush=True)
try:
    ex.spin()
except BaseException:
    pass
'''


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    from iface.live.graph import open_graph, ros_missing
    from iface.live.to_iface import node_iface
    from iface.live.verify import declared, read_live, verify
    from iface.semantics.compile import Workspace

    why = ros_missing()
    if why:
        print(f"live_bench: {why}", file=sys.stderr)
        return 2
    os.environ["ROS_DOMAIN_ID"] = str(random.SystemRandom().randint(150, 200))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    tmp = Path(tempfile.mkdtemp(prefix="live_bench-"))
    proc = subprocess.Popen([sys.executable, "-c", NODES, str(args.nodes)], stdout=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        assert proc.stdout is not None and proc.stdout.readline().strip() == "ready"
        names = [f"/bench/bench_{i}" for i in range(args.nodes)]
        with open_graph(30.0) as graph:
            start = time.perf_counter()
            missing = graph.wait_for(names)
            print(f"discovery of {args.nodes} nodes: {time.perf_counter() - start:.2f} s"
                  + (f" (missing: {missing})" if missing else ""))
            one: list[float] = []
            for _ in range(args.repeat):
                start = time.perf_counter()
                node_iface(graph.read_node(names[0]))
                one.append(time.perf_counter() - start)
            files = []
            for n in names:
                imported = node_iface(graph.read_node(n))
                path = tmp / imported.path
                path.write_text(imported.text, encoding="utf-8")
                files.append(path)
            decls = [declared(Workspace().compile_path(str(p))) for p in files]
            ten: list[float] = []
            found = 0
            for _ in range(args.repeat):
                start = time.perf_counter()
                found = len(verify(decls, read_live(graph, decls)))
                ten.append(time.perf_counter() - start)
        print(f"import one node (after discovery): best {min(one):.3f} s, median {statistics.median(one):.3f} s")
        print(f"verify {args.nodes} nodes (after discovery): best {min(ten):.3f} s, median "
              f"{statistics.median(ten):.3f} s, {found} findings")
        for label, cmd in (("import one node", ["import", "--from", "node", names[0], "--out", str(tmp / "cli"),
                                                "-q", "--force"]),
                           (f"verify {args.nodes} nodes", ["verify", *map(str, files)])):
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "iface", *cmd], capture_output=True, text=True,
                                  timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT / "server") + os.pathsep
                                                    + os.environ.get("PYTHONPATH", "")})
            print(f"CLI {label} (fresh process, discovery included): {time.perf_counter() - start:.2f} s, "
                  f"exit {done.returncode}")
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=15)
    return 0


if __name__ == "__main__":
    sys.exit(main())
