"""The processes of a system's instances: started, watched, found again after a manager restart, stopped.

Each instance runs as a process of its own, started from the sourced workspace (its package's
executable under ``lib/<package>/`` of a prefix on ``AMENT_PREFIX_PATH``, or of its install folder
for a replacement) in a session of its own, so that a manager killed with ``kill -9`` takes none of
them along. For each one the manager keeps a record in ``<state dir>/processes/<instance>.json``:
pid, the process's start time (field 22 of ``/proc/<pid>/stat``), its command line and what it runs
(``implementation.Implementation``). A new manager adopts a recorded process only when a process
with that pid still runs, started at that time, with that command line; a recycled pid fails the
check, so no instance is started twice and no stranger is adopted.

``ExitWatcher`` tells the manager the moment a process ends, not at its next look: one thread waits
on a pidfd per process (Linux 5.3 and later), for a child of the manager as for an adopted process;
without pidfds, a thread per process waits for a child (``waitpid``), or looks at ``/proc`` every
0.1 s for an adopted one. ``InstanceProcess`` is what the manager knows of an instance's process:
``alive``, ``ended``, ``exit_code``, ``stop`` and its record; a node loaded into a container process
could stand behind the same few calls.
"""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path

from .implementation import Implementation, NotStartable, find_in_install, write_json


class StartError(Exception):
    """An instance's process could not be started; the message says why."""


@dataclass(frozen=True, slots=True)
class ProcessRecord:
    """What the manager remembers of a running instance."""

    instance: str
    node: str
    pid: int
    start_ticks: int
    cmdline: tuple[str, ...]
    package_dir: str
    iface_file: str
    interface_hash: str
    generation: int
    component: str = ""
    package: str = ""
    executable: str = ""

    def implementation(self) -> Implementation | None:
        """What the process runs, None in a record that does not say (one made before the record did)."""
        if not self.package:
            return None
        return Implementation(self.component, self.iface_file, self.interface_hash, self.package, self.executable,
                              self.package_dir)


def proc_stat(pid: int) -> tuple[str, int] | None:
    """(state letter, start time in clock ticks) of a process, None when there is none."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2:].split()
    return fields[0], int(fields[19])


def proc_cmdline(pid: int) -> tuple[str, ...] | None:
    """The command line of a process, None when there is none."""
    try:
        raw = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return None
    return tuple(part.decode(errors="replace") for part in raw.split(b"\0") if part)


def catches(pid: int, signum: int) -> bool:
    """Whether ``pid`` has a handler for ``signum`` (``SigCgt`` of ``/proc/<pid>/status``); False when there is
    no such process."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    mask = next((line.split()[1] for line in text.splitlines() if line.startswith("SigCgt:")), "0")
    return bool(int(mask, 16) >> (signum - 1) & 1)


def running(record: ProcessRecord) -> bool:
    """Whether the recorded process still runs (same pid, start time and command line; not a zombie)."""
    stat = proc_stat(record.pid)
    if stat is None or stat[0] in ("Z", "X") or stat[1] != record.start_ticks:
        return False
    return proc_cmdline(record.pid) == record.cmdline


def find_executable(package: str, executable: str, env: dict[str, str], package_dir: str = "") -> str:
    """``<prefix>/lib/<package>/<executable>`` of the install folder ``package_dir`` when one is given (a
    replacement's), else of the first prefix on ``AMENT_PREFIX_PATH`` that has it."""
    if package_dir:
        try:
            return str(find_in_install(Path(package_dir), package, executable))
        except NotStartable as e:
            raise StartError(str(e)) from e
    prefixes = [p for p in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for prefix in prefixes:
        path = Path(prefix) / "lib" / package / executable
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    raise StartError(f"no executable {executable} of package {package} in the sourced workspace "
                     f"({len(prefixes)} prefixes on AMENT_PREFIX_PATH): build it and source its install/setup.bash")


def package_environment(package_dir: Path, env: dict[str, str]) -> dict[str, str]:
    """``env`` with the workspace of ``package_dir`` sourced on top: its ``setup.bash`` (the workspaces it was
    built on, then itself), else its ``local_setup.bash``.

    ``package_dir`` is a package's install prefix (``ws/install/thermostat``) or a workspace's
    ``install`` folder; the first of it and its parent that has a setup script is sourced.
    """
    for folder in (package_dir, package_dir.parent):
        setup = next((folder / name for name in ("setup.bash", "local_setup.bash") if (folder / name).is_file()),
                     None)
        if setup is not None:
            done = subprocess.run(["bash", "-c", f'set +u; . "{setup}" >/dev/null && env -0'], env=env,
                                  capture_output=True, timeout=60, check=False)
            if done.returncode != 0:
                raise StartError(f"{setup} failed: {done.stderr.decode(errors='replace').strip()[-300:]}")
            return dict(item.split("=", 1) for item in done.stdout.decode().split("\0") if "=" in item)
    raise StartError(f"{package_dir}: no setup.bash here or in its parent (name a package's install "
                     "folder, e.g. ws/install/thermostat)")


class InstanceProcess:
    """A started or adopted process of an instance."""

    def __init__(self, record: ProcessRecord, child: subprocess.Popen[bytes] | None = None,
                 pidfd: int | None = None) -> None:
        self.record = record
        self.child = child
        #: Set the moment the process is known to have ended (by ``ExitWatcher``, or ``alive``).
        self.ended = threading.Event()
        self._pidfd = pidfd

    @property
    def pid(self) -> int:
        """The process id."""
        return self.record.pid

    @property
    def adopted(self) -> bool:
        """True when another manager started it."""
        return self.child is None

    def alive(self) -> bool:
        """Whether it still runs."""
        if self.ended.is_set():
            return False
        running_now = self.child.poll() is None if self.child is not None else running(self.record)
        if not running_now:
            self.ended.set()
        return running_now

    def exit_code(self) -> int | None:
        """Its exit status when it was this manager's child and has ended, else None."""
        return self.child.poll() if self.child is not None else None

    def signal_group(self, sig: int) -> None:
        """Send ``sig`` to its process group (it leads a session of its own)."""
        if not self.alive():
            return
        try:
            os.killpg(self.pid, sig)
        except ProcessLookupError:
            pass

    def wait(self, timeout: float) -> bool:
        """Wait at most ``timeout`` seconds for it to end; whether it did."""
        deadline = time.monotonic() + timeout
        while self.alive():
            if time.monotonic() >= deadline:
                return False
            self.ended.wait(min(0.05, max(0.0, deadline - time.monotonic())))
        return True

    def stop(self, grace: float) -> None:
        """SIGTERM, then SIGKILL after ``grace`` seconds; reaped when it is a child."""
        self.signal_group(signal.SIGTERM)
        if not self.wait(grace):
            self.signal_group(signal.SIGKILL)
            self.wait(10.0)

    def take_pidfd(self) -> int | None:
        """A pidfd of the process (opened at its start, or now), handed over to the caller; None without pidfds."""
        fd, self._pidfd = self._pidfd, None
        if fd is None:
            fd = open_pidfd(self.pid)
            if fd is not None and not self.alive():  # opened on a process already gone (or its pid recycled)
                os.close(fd)
                return None
        return fd


def open_pidfd(pid: int) -> int | None:
    """A pidfd of ``pid`` (Linux 5.3 and later); None where there are none or the process is gone."""
    opener = getattr(os, "pidfd_open", None)
    if opener is None:
        return None
    try:
        return int(opener(pid))
    except OSError:
        return None


class ExitWatcher:
    """Calls ``then(process)`` as soon as a watched process ends (``ended`` set first), from a thread of its own.

    One thread polls a pidfd per process (and a pipe that wakes it for a new one); a process without a
    pidfd gets a thread that waits for it (a child: ``waitpid``; adopted: ``/proc`` every 0.1 s).
    """

    def __init__(self) -> None:
        self._poll = select.poll()
        self._watched: dict[int, tuple[InstanceProcess, Callable[[InstanceProcess], None]]] = {}
        self._lock = threading.Lock()
        self._wake_r, self._wake_w = os.pipe()
        self._poll.register(self._wake_r, select.POLLIN)
        self._closed = False
        self._thread: threading.Thread | None = None

    def watch(self, process: InstanceProcess, then: Callable[[InstanceProcess], None]) -> None:
        """Tell ``then`` when ``process`` ends (at once when it has already)."""
        fd = process.take_pidfd()
        if fd is None:
            threading.Thread(target=_wait_without_pidfd, args=(process, then), daemon=True,
                             name=f"iface-exit-{process.pid}").start()
            return
        with self._lock:
            if self._closed:
                os.close(fd)
                return
            self._watched[fd] = (process, then)
            self._poll.register(fd, select.POLLIN)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="iface-exit-watcher", daemon=True)
                self._thread.start()
        os.write(self._wake_w, b"x")

    def close(self) -> None:
        """Stop watching (every pidfd closed); nothing is told after."""
        with self._lock:
            self._closed = True
        os.write(self._wake_w, b"x")
        if self._thread is not None:
            self._thread.join(timeout=5)
        with self._lock:
            for fd in self._watched:
                os.close(fd)
            self._watched.clear()
        os.close(self._wake_r)
        os.close(self._wake_w)

    def _run(self) -> None:
        while True:
            events = self._poll.poll()
            told = []
            with self._lock:
                if self._closed:
                    return
                for fd, _ in events:
                    if fd == self._wake_r:
                        os.read(self._wake_r, 4096)
                    elif fd in self._watched:
                        self._poll.unregister(fd)
                        os.close(fd)
                        told.append(self._watched.pop(fd))
            for process, then in told:
                _ended(process, then)


def _wait_without_pidfd(process: InstanceProcess, then: Callable[[InstanceProcess], None]) -> None:
    if process.child is not None:
        process.child.wait()
    else:
        while running(process.record):
            time.sleep(0.1)
    _ended(process, then)


def _ended(process: InstanceProcess, then: Callable[[InstanceProcess], None]) -> None:
    if process.child is not None:
        process.child.poll()  # reap it: its exit status
    process.ended.set()
    then(process)


def start(instance: str, node: str, argv: list[str], env: dict[str, str], log: Path, *,
          implementation: Implementation, generation: int) -> InstanceProcess:
    """Start ``argv`` in a session of its own, output appended to ``log``."""
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as out:
        try:
            child = subprocess.Popen(argv, env=env, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                                     start_new_session=True)
        except OSError as e:
            raise StartError(f"cannot start {argv[0]}: {e}") from e
    pidfd = open_pidfd(child.pid)  # before anything may reap it: the pid cannot be another process's yet
    stat = proc_stat(child.pid)
    cmdline = _settled_cmdline(child, tuple(argv))
    i = implementation
    record = ProcessRecord(instance, node, child.pid, stat[1] if stat else 0, cmdline, i.package_dir, i.iface_file,
                           i.interface_hash, generation, i.component, i.package, i.executable)
    return InstanceProcess(record, child, pidfd)


def _settled_cmdline(child: subprocess.Popen[bytes], argv: tuple[str, ...]) -> tuple[str, ...]:
    """The command line of a just started process once the kernel shows the new program's.

    Right after ``Popen`` returns, ``/proc/<pid>/cmdline`` may still be empty or show the parent's
    (the new program's memory is set up after the close-on-exec pipe that ``Popen`` waits on is closed);
    a script's interpreter comes first (``python script args``), so it ends with ``argv``.
    """
    deadline = time.monotonic() + 5.0
    while True:
        cmdline = proc_cmdline(child.pid) or ()
        if cmdline[-len(argv):] == argv or time.monotonic() >= deadline or child.poll() is not None:
            return cmdline or argv
        time.sleep(0.005)


def find_by_node(node: str, domain: str) -> list[ProcessRecord]:
    """Running processes started for the node ``node`` (``__node:=node`` on their command line) in the ROS
    domain ``domain`` (their ``ROS_DOMAIN_ID``, ``0`` when unset): a node of that name in another domain is
    another system's, which this manager must neither adopt nor stop."""
    wanted = f"__node:={node}"
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        cmdline = proc_cmdline(int(entry))
        stat = proc_stat(int(entry))
        if cmdline and stat and wanted in cmdline and stat[0] not in ("Z", "X") and proc_domain(int(entry)) == domain:
            found.append(ProcessRecord("", node, int(entry), stat[1], cmdline, "", "", "", 1))
    return found


def ros_domain(env: Mapping[str, str]) -> str:
    """The ROS domain an environment puts its nodes in (``ROS_DOMAIN_ID``; 0 when unset or empty)."""
    return env.get("ROS_DOMAIN_ID", "").strip() or "0"


def proc_domain(pid: int) -> str | None:
    """The ROS domain of a running process (its environment's ``ROS_DOMAIN_ID``), None when it cannot be read."""
    try:
        raw = Path(f"/proc/{pid}/environ").read_bytes()
    except OSError:
        return None
    env = dict(item.split("=", 1) for item in raw.decode(errors="replace").split("\0") if "=" in item)
    return ros_domain(env)


class Records:
    """The process records of one state folder: ``<state dir>/processes/<instance>.json``."""

    def __init__(self, state_dir: Path) -> None:
        self.folder = state_dir / "processes"

    def save(self, record: ProcessRecord) -> None:
        """Write ``record`` atomically."""
        data = asdict(record)
        data["cmdline"] = list(record.cmdline)
        write_json(self.folder / f"{record.instance}.json", data)

    def load(self, instance: str) -> ProcessRecord | None:
        """The record of ``instance``, None when there is none or it cannot be read."""
        try:
            data = json.loads((self.folder / f"{instance}.json").read_text(encoding="utf-8"))
            data["cmdline"] = tuple(data["cmdline"])
            return ProcessRecord(**data)
        except (OSError, ValueError, TypeError, KeyError):
            return None

    def remove(self, instance: str) -> None:
        """Forget ``instance``."""
        (self.folder / f"{instance}.json").unlink(missing_ok=True)
