"""The tests' ``ros2`` runner (tests/ros_harness/ros2cli.py) against a stand-in ``ros2`` on PATH: no ROS needed.

``transition`` asks ``ros2 lifecycle set`` again while the node is not seen, never after the node answered
(a transition is not idempotent), and counts an answer printed before the command hung at its own exit
(seen once in CI: ``Transitioning successful``, then no exit within 60 s) or died of a signal there (SIGSEGV,
seen once on Kilted). After a hang before any answer it asks the node's state once: taken, or asked once more.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from iface.live import deadlock as dds_deadlock

from ..ros_harness.ros2cli import (
    NOT_SEEN,
    SPIN_TIME,
    TRANSITION_DONE,
    Answer,
    proc_start,
    ros2,
    stop_leftovers,
    transition,
)

#: A stand-in ``ros2``: its behaviour per call comes from SCRIPT (one line per call, the last one repeated),
#: each call counted in CALLS.
STAND_IN = """#!{python}
import os, pathlib, signal, sys, time
folder = pathlib.Path(__file__).parent
calls = folder / "CALLS"
n = int(calls.read_text()) if calls.exists() else 0
calls.write_text(str(n + 1))
with (folder / "ARGV").open("a") as f:
    f.write(" ".join(sys.argv[1:]) + "\\n")
lines = (folder / "SCRIPT").read_text().splitlines()
what = lines[min(n, len(lines) - 1)]
if what == "unseen":
    print("{unseen}", file=sys.stderr)
    sys.exit(1)
if what == "mute":
    time.sleep(600)
if what == "orphan":  # a process of its own holds its output open after it is killed
    import subprocess
    (folder / "ORPHAN").write_text(str(subprocess.Popen(["sleep", "600"]).pid))
    print("partial", flush=True)
    time.sleep(600)
if what == "deadlocked":  # its Fast DDS event thread waits on a mutex the main thread holds (Fast-DDS#6502)
    import ctypes, threading
    libc = ctypes.CDLL(None, use_errno=True)
    mutex = ctypes.create_string_buffer(64)
    libc.pthread_mutex_lock(mutex)
    def event_thread():
        libc.prctl(15, b"dds.ev.0", 0, 0, 0)
        libc.pthread_mutex_lock(mutex)
    threading.Thread(target=event_thread, daemon=True).start()
    time.sleep(600)
if what.startswith("state "):
    print(what[len("state "):])
    sys.exit(0)
print("{done}", flush=True)
if what == "hang":
    time.sleep(600)
if what == "crash":
    os.kill(os.getpid(), signal.SIGSEGV)
"""


def _env(tmp_path: Path, *script: str) -> dict[str, str]:
    folder = tmp_path / "bin"
    folder.mkdir()
    ros2_path = folder / "ros2"
    ros2_path.write_text(STAND_IN.format(python=sys.executable, unseen=NOT_SEEN[0], done=TRANSITION_DONE))
    ros2_path.chmod(0o755)
    (folder / "SCRIPT").write_text("\n".join(script) + "\n")
    return {**os.environ, "PATH": f"{folder}{os.pathsep}{os.environ['PATH']}"}


def _calls(tmp_path: Path) -> int:
    return int((tmp_path / "bin" / "CALLS").read_text())


def test_an_answer_printed_before_a_hang_at_exit_counts_and_is_not_asked_again(tmp_path: Path) -> None:
    answer = transition(_env(tmp_path, "hang"), "/n", "configure", timeout=2, within=20)
    assert answer.code == 0 and TRANSITION_DONE in answer.out and "hung at exit" in answer.err, answer
    assert _calls(tmp_path) == 1


def test_an_answer_printed_before_a_crash_at_exit_counts_and_is_not_asked_again(tmp_path: Path) -> None:
    answer = transition(_env(tmp_path, "crash"), "/n", "configure", timeout=20, within=20)
    assert answer.code == 0 and TRANSITION_DONE in answer.out and "signal 11 at exit" in answer.err, answer
    assert _calls(tmp_path) == 1


def test_a_crash_with_no_answer_is_a_failure(tmp_path: Path) -> None:
    env = _env(tmp_path, "crash")
    (tmp_path / "bin" / "ros2").write_text(f"#!{sys.executable}\nimport os, signal\nos.kill(os.getpid(), signal.SIGSEGV)\n")
    answer = transition(env, "/n", "configure", timeout=20, within=0)
    assert answer.code == -11, answer


def test_a_node_not_seen_yet_is_asked_again_until_it_answers(tmp_path: Path) -> None:
    answer = transition(_env(tmp_path, "unseen", "unseen", "ok"), "/n", "configure", within=20)
    assert answer.code == 0 and TRANSITION_DONE in answer.out, answer
    assert _calls(tmp_path) == 3


def test_a_hang_with_no_answer_is_a_failure(tmp_path: Path) -> None:
    env = _env(tmp_path, "hang")
    (tmp_path / "bin" / "ros2").write_text(f"#!{sys.executable}\nimport time\ntime.sleep(600)\n")
    answer = transition(env, "/n", "configure", timeout=2, within=0)
    assert answer.code is None, answer
    assert "no answer within 2 s" in answer.err and "Fast DDS deadlocked" not in answer.err, answer


def test_a_hung_command_whose_child_holds_its_output_open_still_returns_what_it_printed(tmp_path: Path) -> None:
    """Reading what a killed command printed is bounded too: a process it started may keep its pipes open."""
    env = _env(tmp_path, "orphan")
    answers: list[object] = []
    asking = threading.Thread(target=lambda: answers.append(ros2(env, "node", "list", graph=False, timeout=2,
                                                                 within=0)), daemon=True)
    asking.start()
    try:
        asking.join(120)  # the child sleeps 600 s: an unbounded read would still wait
        assert answers, "ros2() still reads the output of a command killed 2 s after it started"
        answer = answers[0]
        assert isinstance(answer, Answer) and answer.code is None and answer.out == "partial\n", answer
    finally:
        orphan = tmp_path / "bin" / "ORPHAN"
        if orphan.exists():
            os.kill(int(orphan.read_text()), signal.SIGKILL)


@pytest.mark.skipif(not sys.platform.startswith("linux") or dds_deadlock.FUTEX < 0,
                    reason="reads /proc/PID/task/TID/syscall (Linux, x86_64 or aarch64)")
def test_a_command_with_no_answer_names_the_deadlocked_participants_of_its_domain_before_it_is_killed(
        tmp_path: Path) -> None:
    """The failure says what hung: each process of the command's domain whose Fast DDS event thread is
    deadlocked (here the command itself, looked at before it is killed); one of another domain is not named."""
    env = _env(tmp_path, "deadlocked", "mute", "deadlocked")
    elsewhere = subprocess.Popen([str(tmp_path / "bin" / "ros2")], env={**env, "ROS_DOMAIN_ID": "4244"})
    try:
        end = time.monotonic() + 30
        calls = tmp_path / "bin" / "CALLS"
        while not (calls.exists() and calls.read_text() == "1") and time.monotonic() < end:  # it took line one
            time.sleep(0.05)
        env["ROS_DOMAIN_ID"] = "4243"
        mute = ros2(env, "node", "list", graph=False, timeout=3, within=0)
        assert mute.code is None and "no answer within 3 s" in mute.err, mute
        assert "Fast DDS deadlocked" not in mute.err, mute
        stuck = ros2(env, "node", "list", graph=False, timeout=3, within=0)
        assert stuck.code is None and "no answer within 3 s" in stuck.err, stuck
        assert stuck.err.count("Fast DDS deadlocked") == 1 and "dds.ev.0" in stuck.err, stuck
        assert "ros2 node list" in stuck.err and f"pid {elsewhere.pid} " not in stuck.err, stuck
    finally:
        elsewhere.kill()
        elsewhere.wait(timeout=30)


def _argv(tmp_path: Path) -> list[str]:
    return [" ".join(line.split()[:3]) for line in (tmp_path / "bin" / "ARGV").read_text().splitlines()]


def test_a_hang_before_any_answer_with_the_node_then_in_the_target_state_counts_as_taken(tmp_path: Path) -> None:
    answer = transition(_env(tmp_path, "mute", "state active [3]"), "/n", "activate", timeout=2, within=20)
    assert answer.code == 0 and TRANSITION_DONE in answer.out and "the transition was taken" in answer.err, answer
    assert _argv(tmp_path) == ["lifecycle set /n", "lifecycle get /n"]


def test_a_hang_before_any_answer_with_the_node_still_in_its_state_is_asked_once_more(tmp_path: Path) -> None:
    answer = transition(_env(tmp_path, "mute", "state inactive [2]", "ok"), "/n", "activate", timeout=2, within=20)
    assert answer.code == 0 and TRANSITION_DONE in answer.out, answer
    assert _argv(tmp_path) == ["lifecycle set /n", "lifecycle get /n", "lifecycle set /n"]


def test_a_hang_before_any_answer_is_looked_at_once_and_a_node_in_a_transition_is_not_asked_again(
        tmp_path: Path) -> None:
    asked = ["lifecycle set /n", "lifecycle get /n", "lifecycle set /n"]
    for script, calls in ((("mute", "state inactive [2]", "mute", "state inactive [2]"), 3),
                          (("mute", "state activating [14]"), 2)):
        folder = tmp_path / str(calls)
        folder.mkdir()
        answer = transition(_env(folder, *script), "/n", "activate", timeout=2, within=20)
        assert answer.code is None and "no answer" in answer.err, answer
        assert _argv(folder) == asked[:calls], script


def test_a_query_is_asked_again_while_its_output_lacks_what_it_waits_for(tmp_path: Path) -> None:
    answer = ros2(_env(tmp_path, "unseen", "ok"), "node", "list", until=TRANSITION_DONE, within=20)
    assert answer.code == 0 and answer.tries == 2, answer


def test_a_query_ended_by_a_signal_is_asked_again(tmp_path: Path) -> None:
    answer = ros2(_env(tmp_path, "crash", "ok"), "lifecycle", "get", "/n", until=TRANSITION_DONE, within=20)
    assert answer.code == 0 and answer.tries == 2, answer


def _spins(tmp_path: Path) -> list[float]:
    lines = (tmp_path / "bin" / "ARGV").read_text().splitlines()
    return [float(line.split("--spin-time ")[1]) for line in lines]


def test_a_question_to_one_node_looks_longer_at_each_try_and_a_graph_query_looks_long(tmp_path: Path) -> None:
    """A miss costs a short try (0.5, 1, 2 s), not a long look every time; a transition counts its own tries."""
    env = _env(tmp_path, "unseen", "unseen", "unseen", "unseen", "ok")
    assert ros2(env, "param", "get", "/n", "rate", within=30).tries == 5
    assert _spins(tmp_path) == [0.5, 1.0, 2.0, 2.0, 2.0]
    (tmp_path / "bin" / "ARGV").unlink()
    (tmp_path / "bin" / "CALLS").unlink()
    assert transition(env, "/n", "configure", within=30).code == 0
    assert _spins(tmp_path) == [0.5, 1.0, 2.0, 2.0, 2.0]
    (tmp_path / "bin" / "ARGV").unlink()
    ros2(env, "node", "list")
    ros2(env, "node", "info", "/n", until=TRANSITION_DONE)
    assert _spins(tmp_path) == [SPIN_TIME, SPIN_TIME]  # they print what they saw: a short look would print less


def test_a_tests_leftovers_are_found_by_its_folder_in_their_environment_and_killed(tmp_path: Path) -> None:
    """What a test started and left running (in a session of its own, as the manager starts instances) is killed
    at its end; another test's process, whose folder only begins like this one's, is left alone."""
    own, other = tmp_path / "test0", tmp_path / "test01"
    env = {**os.environ, "ROS_LOG_DIR": f"{own}{os.sep}ros-log"}
    left = subprocess.Popen(["sleep", "60"], env=env, start_new_session=True)
    others = subprocess.Popen(["sleep", "60"], env={**os.environ, "ROS_LOG_DIR": f"{other}{os.sep}ros-log"},
                              start_new_session=True)
    try:
        killed = stop_leftovers(f"{own}{os.sep}", within=0.5)
        assert [k.split()[:3] for k in killed] == [[str(left.pid), "sleep", "60"]], killed
        assert left.wait(timeout=5) == -9
        assert proc_start(others.pid) is not None
        assert stop_leftovers(f"{own}{os.sep}", within=0.2) == []
    finally:
        for proc in (left, others):
            proc.kill()
            proc.wait(timeout=5)
