"""The drivers' probe in place of a deadlocked participant (``Probe.revived``), on every release.

Fast DDS's deadlock (``iface.live.deadlock``, eProsima/Fast-DDS#6502) cannot be made on demand, so the
script below has ``dds_deadlock.stuck`` report it once. A call that gets no answer then looks, finds it, and
asks again on a new participant; that participant answers calls, its subscriptions are made again and get
what is published after; the deadlocked one is kept (never destroyed) and the driver ends through
``probe.run`` with its own exit code, at once. A probe that finds nothing does not open a new participant.
"""

from __future__ import annotations

import subprocess
import textwrap
from pathlib import Path

from ..ros_harness.ros import ROOT, environment

PER_RELEASE = True

SCRIPT = textwrap.dedent("""
    import sys, time
    sys.path.insert(0, sys.argv[1])
    import rclpy
    from rcl_interfaces.srv import GetParameters
    from std_msgs.msg import String
    from iface.live import deadlock as dds_deadlock
    from tests.ros_harness import probe as P

    def main():
        p = P.Probe()
        got = []
        p.subscribe(String, "/revival", got.append, 10)
        talker_context = rclpy.Context()
        rclpy.init(context=talker_context)
        talker = rclpy.create_node("talker", context=talker_context)
        pub = talker.create_publisher(String, "/revival", 10)

        def heard():
            pub.publish(String(data="x"))
            return got

        try:
            p.wait_until(heard, 20, "a message before")
            assert p.revivals == 0, "revived with nothing stuck"
            old = p.node
            dds_deadlock.stuck = lambda pid, settle=1.0, ignore=frozenset(): (
                [] if 1 in ignore else [dds_deadlock.Stuck(pid, 1, "dds.ev.0", 0)])
            try:
                p.call(GetParameters, "/nobody/get_parameters", GetParameters.Request(), timeout=1.0)
            except (TimeoutError, P.StepFailed) as e:
                print("no answer:", e)
            else:
                raise AssertionError("answered by nobody")
            assert p.revivals == 1 and p.node is not old and p.context is not old.context, "not revived"
            assert len(P.ABANDONED) == 1 and P.ABANDONED[0][1] is old, "the old participant not kept"
            answer = p.call(GetParameters, "/iface_probe/get_parameters",
                            GetParameters.Request(names=["use_sim_time"]), timeout=20, idempotent=True)
            assert len(answer.values) == 1, answer
            got.clear()
            p.wait_until(heard, 20, "a message on the new participant's subscription")
            assert p.revivals == 1
            print("revived", flush=True)
        finally:
            talker.destroy_node()
            rclpy.try_shutdown(context=talker_context)
        return 7

    P.run(main)
""")


def test_a_probe_whose_participant_is_deadlocked_goes_on_with_a_new_one(ros_venv: Path, tmp_path: Path) -> None:
    env = environment(ros_venv, log_dir=tmp_path / "ros-log")
    done = subprocess.run([str(ros_venv / "bin" / "python"), "-c", SCRIPT, str(ROOT)], env=env, capture_output=True,
                          text=True, timeout=120, check=False)
    out = done.stdout + done.stderr
    assert done.returncode == 7, out  # the driver's own code, through os._exit
    assert "a new participant takes its place" in out and "revived" in out, out
    assert "no answer: " in out, out
