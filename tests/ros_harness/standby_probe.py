"""A component's standby (``--standby``) as the manager uses it, looked at from the ROS graph (run in a ROS 2 environment).

    python standby_probe.py NODE -- EXECUTABLE [ARGS...]

Starts ``EXECUTABLE --standby --ros-args -r __node:=NODE``, and prints one line per finding: ready (a handler for
SIGUSR1), its hidden node seen and the component's not, the component's node there after SIGUSR1 and the hidden
one gone, a second SIGUSR1 ending nothing, SIGTERM ending it with exit 0; then a second standby whose parent is
killed (right after it is ready, its parent named by ``IFACE_STANDBY_PARENT`` as the manager names itself) ends by
itself. Every wait is bounded; every process is stopped by its own handle.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout, when run as a script
from tests.ros_harness.ros2cli import node_processes, proc_start


def catches(pid: int, signum: int) -> bool:
    """Whether ``pid`` has a handler for ``signum`` (``SigCgt``): the manager's test that a standby is ready
    (``iface.operate.processes.catches``, which this file cannot import: it runs in the ROS environment, which has
    none of iface's dependencies)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    mask = next((line.split()[1] for line in text.splitlines() if line.startswith("SigCgt:")), "0")
    return bool(int(mask, 16) >> (signum - 1) & 1)


#: What this probe prints for a standby that keeps its contract.
SAYS = ("ready True", "standby node seen True", "component node before told False", "component node after told True",
        "standby node gone True", "alive after a second SIGUSR1 True", "exit after SIGTERM 0", "orphan ready True",
        "orphan ended with its parent True")


def findings(venv: Path, env: dict[str, str], node: str, command: list[str], log: Path) -> str:
    """Run this probe on ``command`` in ``venv``'s Python (from a test); its output, asserted to say all of ``SAYS``."""
    from .ros import run_bounded

    code = run_bounded([str(venv / "bin" / "python"), __file__, node, "--", *command], env, 180, log)
    said = log.read_text(errors="replace")
    lines = said.splitlines()
    assert code == 0 and all(line in lines for line in SAYS), said[-3000:]
    return said


def ready_standby(node: str, own: str = "", timeout: float = 60.0, other_than: tuple[int, ...] = ()) -> int:
    """The pid of the one standby of ``node`` (``own``: see ``ros2cli.node_processes``; not one of ``other_than``:
    one that became the node keeps its command line) once it takes its signal, the manager's test of ready;
    TimeoutError after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while True:
        found = [p for p in node_processes(node, own, standby=True) if p not in other_than]
        if len(found) == 1 and catches(found[0], signal.SIGUSR1):
            return found[0]
        if time.monotonic() >= end:
            raise TimeoutError(f"no one standby of {node} ready within {timeout:g} s: {found}")
        time.sleep(0.05)


#: How long a driver waits at most for a log line about what it has just seen happen (a bound, not a figure).
LOG_WAIT = 10.0


def logged(read: Callable[[], str], text: str) -> bool:
    """Whether the log ``read`` returns says ``text`` within ``LOG_WAIT`` seconds (a line comes after what it
    tells of)."""
    return until(lambda: text in read(), LOG_WAIT)


def until(predicate: Callable[[], bool], timeout: float) -> bool:
    end = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() >= end:
            return False
        time.sleep(0.05)
    return True


def main() -> int:
    import rclpy

    node = sys.argv[1]
    command = sys.argv[sys.argv.index("--") + 1:]
    rclpy.init()
    probe = rclpy.create_node("standby_probe")

    def names() -> set[str]:
        return {name for name, _ in probe.get_node_names_and_namespaces()}

    standby = subprocess.Popen([*command, "--standby", "--ros-args", "-r", f"__node:={node}"], start_new_session=True)
    try:
        print("ready", until(lambda: catches(standby.pid, signal.SIGUSR1), 60), flush=True)
        hidden = f"_iface_standby_{standby.pid}"
        print("standby node seen", until(lambda: hidden in names(), 30), flush=True)
        time.sleep(1.0)
        print("component node before told", node in names(), flush=True)
        told = time.monotonic()
        os.kill(standby.pid, signal.SIGUSR1)
        print("component node after told", until(lambda: node in names(), 30), flush=True)
        print(f"told to node in the graph: {time.monotonic() - told:.3f} s", flush=True)
        print("standby node gone", until(lambda: hidden not in names(), 30), flush=True)
        os.kill(standby.pid, signal.SIGUSR1)
        time.sleep(0.5)
        print("alive after a second SIGUSR1", standby.poll() is None, flush=True)
        standby.terminate()
        print("exit after SIGTERM", standby.wait(timeout=20), flush=True)
    finally:
        if standby.poll() is None:
            os.killpg(standby.pid, signal.SIGKILL)
            standby.wait(timeout=10)

    # a standby outlives no manager: its parent killed, it ends by itself
    parent = subprocess.Popen(
        [sys.executable, "-c", ("import os, subprocess, sys, time\n"
                                "os.environ['IFACE_STANDBY_PARENT'] = str(os.getpid())  # as the manager does\n"
                                "child = subprocess.Popen(sys.argv[1:], start_new_session=True)\n"
                                "print(child.pid, flush=True)\ntime.sleep(120)"),
         *command, "--standby", "--ros-args", "-r", f"__node:={node}_orphan"], stdout=subprocess.PIPE, text=True)
    orphan = 0
    try:
        orphan = int(parent.stdout.readline())  # type: ignore[union-attr]
        print("orphan ready", until(lambda: catches(orphan, signal.SIGUSR1), 60), flush=True)
        parent.kill()
        parent.wait(timeout=10)
        print("orphan ended with its parent", until(lambda: proc_start(orphan) is None, 15), flush=True)
    finally:
        if parent.poll() is None:
            parent.kill()
            parent.wait(timeout=10)
        if orphan and proc_start(orphan) is not None:
            os.killpg(orphan, signal.SIGKILL)
    probe.destroy_node()
    rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
