"""A timer cancelled between the executor's wait and its call (ros2/rclpy#1485), on every release.

The generated rclpy node cancels a work timer when it is activated after a restore (``_continue_schedule``),
from an executor thread, while the main thread spins. Jazzy's rclpy (7.1.6) then raised "timer is canceled"
in the thread that took the timer: the timer stayed marked as taken, its mutually exclusive callback group
busy for good, and ``spin_once`` re-raised it and ended the node (seen once in the manager scenario, Jazzy:
an instance restarted after kill -9 ended 0.3 s after its activation). ``ComponentExecutor`` skips such a
timer (one that ``is_canceled()``), as later rclpy releases do. The script below makes the race every time:
its executor cancels the timer right after the wait returned it as ready. An error of a timer that is not
cancelled is still raised, whatever its text.
"""

from __future__ import annotations

import subprocess
import textwrap
from pathlib import Path
from typing import Any

from iface.nodes.shared import RUNTIMES

from ..ros_harness.ros import environment

PER_RELEASE = True

SCRIPT = textwrap.dedent("""
    import time
    import rclpy
    from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
    from iface_runtime_py.runtime import ComponentExecutor

    class Racing(ComponentExecutor):
        # cancels a victim right after the wait found it ready: the race, every time
        victims = ()
        races = 0

        def wait_for_ready_callbacks(self, *args, **kwargs):
            handler, entity, node = super().wait_for_ready_callbacks(*args, **kwargs)
            if any(entity is v for v in self.victims) and not entity.is_canceled():
                entity.cancel()
                Racing.races += 1
            return handler, entity, node

    rclpy.init()
    node = rclpy.create_node("timer_race")
    group = MutuallyExclusiveCallbackGroup()
    victim_calls, other_calls = [], []
    executor = Racing(num_threads=2)
    executor.victims = [node.create_timer(0.01, lambda: victim_calls.append(1), callback_group=group)
                        for _ in range(5)]
    node.create_timer(0.01, lambda: other_calls.append(1), callback_group=group)
    executor.add_node(node)
    end = time.monotonic() + 30
    after = None
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.1)
        if Racing.races == 5 and after is None:
            after = len(other_calls)
        if after is not None and len(other_calls) >= after + 10:
            break
    print(f"races {Racing.races}, victims called {len(victim_calls)}, the other timer after the races "
          f"{len(other_calls) - (after or 0)}", flush=True)

    # an error of a timer that is not cancelled is the caller's, whatever its text says
    from rclpy.executors import Executor
    from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
    live = node.create_timer(10.0, lambda: None)
    taken = Executor._take_timer
    def failing(self, tmr):
        raise _rclpy.RCLError("timer is canceled, says a made-up error")
    Executor._take_timer = failing
    try:
        executor._take_timer(live)
        print("a live timer's error: swallowed", flush=True)
    except _rclpy.RCLError:
        print("a live timer's error: raised", flush=True)
    finally:
        Executor._take_timer = taken
    executor.shutdown(timeout_sec=2.0)
    node.destroy_node()
    rclpy.try_shutdown()
""")


def test_a_timer_cancelled_after_the_wait_is_skipped_and_its_group_goes_on(ros_workspace: Any, tmp_path: Path) -> None:
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    source = RUNTIMES / "iface_runtime_py"  # this checkout's runtime, before the installed one
    env["PYTHONPATH"] = f"{source}:{env['PYTHONPATH']}"
    done = subprocess.run([str(ros_workspace.venv / "bin" / "python"), "-c", SCRIPT], env=env, capture_output=True,
                          text=True, timeout=120, check=False)
    out = done.stdout + done.stderr
    assert done.returncode == 0, out[-3000:]
    assert "races 5, victims called 0," in out and "Traceback" not in out, out[-3000:]
    assert "a live timer's error: raised" in out, out[-3000:]
    after = int(out.rsplit("the other timer after the races ", 1)[1].split()[0])
    assert after >= 10, out[-3000:]  # the group is not left busy
