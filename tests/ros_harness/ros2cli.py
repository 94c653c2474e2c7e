"""The ``ros2`` command as the tests run it, and the processes ``ros2 launch`` and ``ros2 run`` start.

A graph query runs with ``--no-daemon`` (the ros2 daemon is a detached process that would outlive the
test, with no handle of ours to stop it) and ``--spin-time``: without the daemon each command discovers the
graph itself during its spin time, and the default 0.5 s missed running nodes on this machine under load
(../shared/ros2-runtime/README.md). A test that starts the daemon of its domain itself and stops it at its
end (``ros2 daemon start``/``stop``: test_launch.py) asks it instead (``daemon=True``): it answers from the
graph it keeps, a question in 1-2 s where a command that discovers the whole graph itself took 2-5 s. A query
that does not see its node yet (``Node not found``, ``Unable to find node``) is asked again, within a
bound; a question to one node (its lifecycle state, a parameter) looks longer each time (0.5, 1, 2 s), any
other query 2 s, as it prints what it discovered in its spin time. ``Launched`` starts ``ros2 launch``/``ros2
run`` from Python with a handle of its own (a shell's ``&`` would start it with SIGINT ignored), knows the
processes under it, and stops it with one SIGINT.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

HARNESS = Path(__file__).parent
#: Seconds a ros2 graph query looks at the graph.
SPIN_TIME = 2.0
#: Seconds the first try of a question to one node looks (see ``spin_time``).
FIRST_SPIN = 0.5
#: Questions to one node, answered by its services once it is seen: they say so when they do not see it
#: (``NOT_SEEN``), and a node they see gets the whole answer. (``node info`` is no such question: it prints what
#: it has discovered of the node so far.)
NODE_QUESTIONS = (("lifecycle", "get"), ("lifecycle", "set"), ("param", "get"), ("param", "describe"))
#: Releases whose ``ros2 service call`` the runtime cannot run (Kilted's ros2service on Jazzy's rclpy).
NO_SERVICE_CALL = ("jazzy",)
#: What a query says about a node it has not discovered (yet).
NOT_SEEN = ("Node not found", "Unable to find node")


@dataclass(frozen=True)
class Answer:
    """What one ``ros2`` command printed, its exit status and how many times it was asked."""

    argv: tuple[str, ...]
    code: int | None
    out: str
    err: str
    tries: int

    def __str__(self) -> str:
        return f"$ {' '.join(self.argv)}\nexit {self.code} after {self.tries} tries\n{self.out}{self.err}"


#: A file to which each ``ros2`` command the tests run adds a line: its seconds, its exit status and itself.
TRACE_VARIABLE = "IFACE_TEST_ROS2_TRACE"


def trace(argv: tuple[str, ...], code: int | None, seconds: float) -> None:
    """One line for the command in the file ``$IFACE_TEST_ROS2_TRACE`` names, when it names one."""
    if path := os.environ.get(TRACE_VARIABLE):
        with open(path, "a", encoding="utf-8") as out:
            out.write(f"{seconds:6.2f} s  exit {code}  {' '.join(argv)}\n")


def spin_time(args: tuple[str, ...], tries: int) -> float:
    """The spin time of try ``tries`` of ``ros2 ARGS``: a question to one node (``NODE_QUESTIONS``) looks
    ``FIRST_SPIN`` s first, twice as long at each try after, up to ``SPIN_TIME``: a miss says so and costs a
    try. Any other query looks ``SPIN_TIME`` s, as what it prints is what it discovered in that time."""
    if args[:2] not in NODE_QUESTIONS:
        return SPIN_TIME
    return min(SPIN_TIME, FIRST_SPIN * 2 ** (tries - 1))


def ros2(env: dict[str, str], *args: str, graph: bool = True, timeout: float = 25.0, within: float = 60.0,
         until: str | None = None, first_try: int = 1, daemon: bool = False) -> Answer:
    """``ros2 ARGS`` (with ``--no-daemon --spin-time S`` when ``graph``: ``spin_time``; as it is when ``daemon``:
    the test runs its domain's ros2 daemon, which answers from the graph it keeps), asked again while it
    does not see its node, or (with ``until``) while its output lacks ``until``, or it gave no answer within
    ``timeout`` (a ``ros2`` command can hang at its own exit) or was ended by a signal, for at most ``within``
    seconds. A command that is not a query (a transition, a goal, a service call) is asked once: ``within=0``,
    or ``transition``, which counts its tries from ``first_try``."""
    end = time.monotonic() + within
    tries = 0
    while True:
        tries += 1
        spin = spin_time(args, first_try + tries - 1)
        argv = ("ros2", *args, *(("--no-daemon", "--spin-time", f"{spin:g}") if graph and not daemon else ()))
        started = time.monotonic()
        answer = Answer(argv, *run_once(argv, env, timeout), tries)
        trace(argv, answer.code, time.monotonic() - started)
        unseen = any(s in answer.out + answer.err for s in NOT_SEEN)
        missing = until is not None and until not in answer.out
        ended = answer.code is None or answer.code < 0  # hung, or ended by a signal (SIGSEGV at its exit)
        if not (unseen or missing or ended) or time.monotonic() >= end:
            return answer
        time.sleep(0.5)


def run_once(argv: tuple[str, ...], env: dict[str, str], timeout: float) -> tuple[int | None, str, str]:
    """Run ``argv``: (exit status, stdout, stderr). With no exit within ``timeout`` seconds: status None, and
    stderr says so and names each process of the domain (``ROS_DOMAIN_ID``) whose Fast DDS is deadlocked
    (``iface.live.deadlock``), looked at while the command still runs, before it is killed: the command itself,
    or the node it waited on."""
    with subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          stdin=subprocess.DEVNULL) as proc:
        try:
            out, err = proc.communicate(timeout=timeout)
            return proc.returncode, out, err
        except subprocess.TimeoutExpired:
            from iface.live import deadlock

            stuck = deadlock.note(env.get("ROS_DOMAIN_ID", "0"))
            proc.kill()
            try:  # what it printed; bounded, as a process it started may hold the pipes open
                out, err = proc.communicate(timeout=10)
            except subprocess.TimeoutExpired as e:
                out, err = _text(e.stdout), _text(e.stderr)
            return None, out, f"{err}\n(no answer within {timeout:g} s){stuck}"


#: The state each lifecycle transition ends in.
TRANSITION_TARGET = {"configure": "inactive", "activate": "active", "deactivate": "inactive",
                     "cleanup": "unconfigured", "shutdown": "finalized"}
#: What ``ros2 lifecycle set`` prints when the node took the transition.
TRANSITION_DONE = "Transitioning successful"
#: What ``ros2 lifecycle get`` prints for a node in a primary state (not in a transition).
PRIMARY_STATE = re.compile(r"(unconfigured|inactive|active|finalized) \[\d\]$")


def transition(env: dict[str, str], node: str, label: str, timeout: float = 30.0, within: float = 40.0,
               daemon: bool = False) -> Answer:
    """``ros2 lifecycle set NODE LABEL``, asked again only while it does not see the node (for at most
    ``within`` seconds): a transition is not idempotent (asked again after it was taken, it is refused). The
    command has been seen to hang at its own exit after printing its answer (rclpy/Fast DDS tearing its node
    down, 1 run of ~40 on a loaded machine), and to die of SIGSEGV there (Kilted, 2026-11-30): killed at
    ``timeout`` or ended by a signal, an answer that printed ``Transitioning successful`` still counts; the
    caller checks the state the node reached. It has also hung before printing anything (Kilted, a quiet
    machine, 2026-12-01; the node then stopped cleanly at SIGINT, so it was the command that hung): the node's
    state then tells, once (``ros2 lifecycle get``): in the transition's target state it took the transition; in
    another state it did not, and is asked once more."""
    end = time.monotonic() + within
    tries = 0
    looked = False
    while True:
        tries += 1
        answer = ros2(env, "lifecycle", "set", node, label, timeout=timeout, within=0, first_try=tries,
                      daemon=daemon)
        if any(s in answer.out + answer.err for s in NOT_SEEN) and time.monotonic() < end:
            time.sleep(0.5)
            continue
        if answer.code is None and TRANSITION_DONE not in answer.out and not looked:
            looked = True
            state = ros2(env, "lifecycle", "get", node, timeout=timeout, within=0, daemon=daemon).out.strip()
            if state.startswith(f"{TRANSITION_TARGET.get(label)} ["):
                return Answer(answer.argv, 0, f"{TRANSITION_DONE}\n",
                              f"{answer.err} (then `ros2 lifecycle get`: {state}: the transition was taken)",
                              answer.tries)
            if PRIMARY_STATE.match(state):
                continue
        break
    if TRANSITION_DONE in answer.out and (answer.code is None or answer.code < 0):
        how = "hung at exit: killed" if answer.code is None else f"ended by signal {-answer.code} at exit"
        return Answer(answer.argv, 0, answer.out, f"{answer.err} (answered, then {how})", answer.tries)
    return answer


def service_call(env: dict[str, str], release: str, service: str, srv_type: str, request: str = "{}",
                 timeout: float = 60.0) -> Answer:
    """``ros2 service call SERVICE TYPE REQUEST``; on a release whose runtime cannot run it, the same call from
    ``call_service.py`` with the runtime's Python (``ROS2_RUNTIME_VENV``)."""
    if release not in NO_SERVICE_CALL:
        return ros2(env, "service", "call", service, srv_type, request, graph=False, timeout=timeout, within=0)
    python = str(Path(env["ROS2_RUNTIME_VENV"]) / "bin" / "python")
    argv = (python, str(HARNESS / "call_service.py"), service, srv_type, request, "--timeout", f"{timeout / 2:g}")
    return Answer(argv, *run_once(argv, env, timeout), 1)


def iface_lsp_on_path(folder: Path, root: Path, python: str) -> str:
    """A folder holding ``iface-lsp`` of the checkout ``root`` (run by ``python``), whatever is installed; for PATH."""
    folder.mkdir(parents=True, exist_ok=True)
    wrapper = folder / "iface-lsp"
    wrapper.write_text(f'#!/bin/sh\nPYTHONPATH="{root / "server"}${{PYTHONPATH:+:$PYTHONPATH}}" exec "{python}" -m iface "$@"\n')
    wrapper.chmod(0o755)
    return str(folder)


def _text(data: bytes | str | None) -> str:
    if data is None:
        return ""
    return data if isinstance(data, str) else data.decode(errors="replace")


def proc_start(pid: int) -> int | None:
    """The start time (clock ticks) of a running process; None when it is gone or a zombie."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2:].split()
    return None if fields[0] in ("Z", "X") else int(fields[19])


def descendants(pid: int) -> dict[int, int]:
    """Every running process below ``pid`` (children, theirs…), by pid, with its start time."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            text = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = text[text.rindex(")") + 2:].split()
        children.setdefault(int(fields[1]), []).append(int(entry))
    found: dict[int, int] = {}
    todo = list(children.get(pid, []))
    while todo:
        child = todo.pop()
        start = proc_start(child)
        if start is not None:
            found[child] = start
        todo += children.get(child, [])
    return found


def cmdline(pid: int) -> list[str]:
    """A process's command line ([] when it is gone)."""
    try:
        return [p.decode(errors="replace") for p in Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0") if p]
    except OSError:
        return []


def node_processes(node: str, own: str = "", standby: bool | None = None) -> list[int]:
    """The running processes started for the node ``node`` (``__node:=node`` on their command line) whose
    environment holds ``own`` (a test's own folder: another test may run a node of that name): all of them, only
    standbys (``standby=True``: ``--standby`` on the command line, which one that became the node keeps) or none
    (``False``)."""
    found = []
    for pid in processes_of(own):
        line = cmdline(pid)
        if f"__node:={node}" not in line:
            continue
        if standby is not None and ("--standby" in line) != standby:
            continue
        found.append(pid)
    return found


def processes_of(own: str) -> dict[int, int]:
    """Every running process but this one whose environment holds ``own`` (a test's own folder, which its ROS
    environment names in ``ROS_LOG_DIR``), by pid, with its start time: what the test started, at any depth or
    session."""
    found = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            held = own.encode() in Path(f"/proc/{entry}/environ").read_bytes()
        except OSError:
            continue
        start = proc_start(int(entry))
        if held and start is not None:
            found[int(entry)] = start
    return found


def stop_leftovers(own: str, within: float = 10.0) -> list[str]:
    """Kill what still runs of a test's processes (``processes_of``) after ``within`` seconds of letting them end;
    each one killed, described. A test's cleanup: a failed test leaves what it started, which a later test of the
    same domain would meet."""
    end = time.monotonic() + within
    while (left := processes_of(own)) and time.monotonic() < end:
        time.sleep(0.2)
    killed = []
    for pid in still_running(left):
        killed.append(f"{pid} {' '.join(cmdline(pid))[:300]}")
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return killed


def still_running(seen: dict[int, int]) -> list[int]:
    """The pids of ``seen`` that still run (the same process: same start time)."""
    return [pid for pid, start in seen.items() if proc_start(pid) == start]


class Launched:
    """``ros2 launch …`` or ``ros2 run …`` started in a session of its own, output to a log."""

    def __init__(self, argv: list[str], env: dict[str, str], log: Path, cwd: Path | None = None) -> None:
        self.argv = argv
        self.log_path = log
        log.parent.mkdir(parents=True, exist_ok=True)
        with open(log, "w") as out:
            self.proc = subprocess.Popen(argv, env=env, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out,
                                         stderr=subprocess.STDOUT, start_new_session=True)
        #: Every process seen below it so far (``watch``), by pid, with its start time.
        self.seen: dict[int, int] = {}

    def log(self) -> str:
        """What it printed so far."""
        return self.log_path.read_text(errors="replace")

    def watch(self) -> dict[int, int]:
        """The processes below it now (and remember them)."""
        now = descendants(self.proc.pid)
        self.seen.update(now)
        return now

    def interrupt(self, timeout: float = 60.0) -> int | None:
        """One SIGINT to its pid (as Ctrl-C to ``ros2 launch``); its exit status, None when it did not end in time."""
        self.watch()
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def left_running(self, within: float = 10.0) -> list[int]:
        """The processes seen below it that still run after ``within`` seconds."""
        end = time.monotonic() + within
        while True:
            left = still_running(self.seen)
            if not left or time.monotonic() >= end:
                return left
            time.sleep(0.2)

    def stop(self) -> None:
        """Stop it and whatever it started that still runs (SIGINT, then SIGTERM, then SIGKILL): a test's cleanup."""
        if self.proc.poll() is None:
            self.watch()
            self.proc.send_signal(signal.SIGINT)
            try:
                self.proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGTERM)
                try:
                    self.proc.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    os.killpg(self.proc.pid, signal.SIGKILL)
                    self.proc.wait(timeout=10)
        for pid in still_running(self.seen):
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
