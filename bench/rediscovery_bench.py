"""Rediscovery after a crash, without iface: what bounds a restart that has no standby (docs/system.md).

    python bench/rediscovery_bench.py [--runs 8] [--distro kilted|jazzy] [--gap SECONDS] [--other-port]

Two plain rclpy processes, no iface code: a client node A stays up; a server process B (a node with one
service) is started, answers A, and is ended, ``--runs`` times; the next B starts ``--gap`` seconds (default
0.05) after the last one ended. For each start it prints how long after B's node was made A got its first
answer (A asks every 50 ms) and when B first saw A in its graph, once when each B is ended by ``kill -9`` and
once by SIGINT (a clean exit, which says goodbye to its peers). The difference between the two is the time DDS
takes to take in a participant that follows one that vanished without a goodbye: a restart after a crash
cannot be faster than it unless the next process is up before the crash (``standby = "true"``).

``--other-port``: each B gets a participant id of its own (10 and 11 in turn, through a Fast DDS profile), so
that it never takes the ports of the B just killed, as it does by default (the lowest free participant id).
"""

from __future__ import annotations

import argparse
import json
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

SERVER = """\
import sys, time, rclpy
from lifecycle_msgs.srv import GetState
rclpy.init()
node = rclpy.create_node("rediscovery_b")
node.create_service(GetState, "/rediscovery_b/get_state", lambda req, resp: resp)
made = time.time()
print(f"UP {made:.6f}", flush=True)
try:
    while "rediscovery_a" not in node.get_node_names() and time.time() - made < 15:
        rclpy.spin_once(node, timeout_sec=0.005)
    print(f"SAW {time.time() - made:.6f}", flush=True)
    rclpy.spin(node)
except KeyboardInterrupt:
    node.destroy_node()
    rclpy.try_shutdown()
"""


PROFILE = """<?xml version="1.0" encoding="UTF-8"?>
<profiles xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <participant profile_name="rediscovery_b" is_default_profile="true">
    <rtps><participantID>{id}</participantID></rtps>
  </participant>
</profiles>
"""


def server_env(server: Path, start: int | None) -> dict[str, str]:
    """B's environment: with ``start``, a Fast DDS profile that gives it participant id 10 or 11 in turn."""
    env = dict(os.environ)
    if start is not None:
        profile = server.with_name(f"participant-{10 + start % 2}.xml")
        profile.write_text(PROFILE.format(id=10 + start % 2), encoding="utf-8")
        env["FASTDDS_DEFAULT_PROFILES_FILE"] = env["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(profile)
    return env


def inner(runs: int, server: Path, gap: float, other_port: bool) -> int:
    """In the ROS environment: the runs, one line each, then the summary as JSON on the last line."""
    import rclpy
    from lifecycle_msgs.srv import GetState

    rclpy.init()
    node = rclpy.create_node("rediscovery_a")
    client = node.create_client(GetState, "/rediscovery_b/get_state")
    figures: dict[str, dict[str, list[float]]] = {}
    for how in ("SIGINT", "kill -9"):  # the clean exits first: no crash before them
        answer, saw = [], []
        for i in range(runs + 1):  # the first start follows the other kind of end: not counted
            proc = subprocess.Popen([sys.executable, str(server)], stdout=subprocess.PIPE, text=True,
                                    env=server_env(server, i if other_port else None))
            try:
                made = float(proc.stdout.readline().split()[1])
                got = None
                while got is None and time.time() - made < 15:
                    future = client.call_async(GetState.Request())
                    until = time.time() + 0.05
                    while time.time() < until and not future.done():
                        rclpy.spin_once(node, timeout_sec=0.01)
                    if future.done():
                        got = time.time() - made
                    else:
                        client.remove_pending_request(future)
                line = proc.stdout.readline().split()
                seen = float(line[1]) if len(line) == 2 else None
            finally:
                proc.send_signal(signal.SIGKILL if how == "kill -9" else signal.SIGINT)
                proc.wait(timeout=10)
            if i and got is not None and seen is not None:
                answer.append(got)
                saw.append(seen)
            print(f"  after {how if i else 'the other kind (not counted)'}: answered {got if got is None else round(got, 3)} s, "
                  f"saw its client {seen if seen is None else round(seen, 3)} s", flush=True)
            time.sleep(gap)
        figures[how] = {"answer": answer, "saw": saw}
    node.destroy_node()
    rclpy.shutdown()
    print(json.dumps(figures), flush=True)
    return 0


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile (nearest rank) of ``values``."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * len(ordered) + 0.5) - 1))]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=8, help="starts after each kind of end (default 8)")
    ap.add_argument("--distro", choices=("kilted", "jazzy"), default="kilted")
    ap.add_argument("--gap", type=float, default=0.05, help="seconds from one B's end to the next B's start")
    ap.add_argument("--other-port", action="store_true", help="never the ports of the B just ended (see above)")
    ap.add_argument("--inner", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.inner is not None:
        return inner(args.runs, args.inner, args.gap, args.other_port)
    sys.path.insert(0, str(ROOT))
    from tests.ros_harness.ros import environment, runtime_venv

    venv, why = runtime_venv(args.distro)
    if venv is None:
        print(f"rediscovery_bench: {why}", file=sys.stderr)
        return 2
    env = environment(venv)
    env["ROS_DOMAIN_ID"] = str(random.randint(1, 100))
    print(f"ROS 2 {args.distro}, domain {env['ROS_DOMAIN_ID']}, the next B {args.gap:g} s after the last one ended"
          f"{', on ports of its own' if args.other_port else ''}; load average before: "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    with tempfile.TemporaryDirectory(prefix="rediscovery-") as tmp:
        server = Path(tmp) / "server.py"
        server.write_text(SERVER, encoding="utf-8")
        argv = [str(venv / "bin" / "python"), __file__, "--runs", str(args.runs), "--gap", str(args.gap),
                *(["--other-port"] if args.other_port else []), "--inner", str(server)]
        done = subprocess.run(argv, env=env, stdout=subprocess.PIPE, text=True, timeout=900, check=False)
    lines = done.stdout.splitlines()
    print("\n".join(lines[:-1]))
    if done.returncode or not lines:
        return done.returncode or 1
    figures = json.loads(lines[-1])
    for how, f in figures.items():
        if not f["answer"]:
            print(f"after {how}: no start answered")
            continue
        print(f"after {how}: first answer median {statistics.median(f['answer']):.3f} s, p95 "
              f"{percentile(f['answer'], 0.95):.3f} s; the new process saw its client: median "
              f"{statistics.median(f['saw']):.3f} s (over {len(f['answer'])} starts)")
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
