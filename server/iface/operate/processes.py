"""The processes of a system's instances: started, found again after a manager restart, stopped.

Each instance runs as a process of its own, started from the sourced workspace (its package's
executable under ``lib/<package>/`` of a prefix on ``AMENT_PREFIX_PATH``) in a session of its own,
so that a manager killed with ``kill -9`` takes none of them along. For each one the manager keeps
a record in ``<state dir>/processes/<instance>.json``: pid, the process's start time (field 22 of
``/proc/<pid>/stat``) and its command line. A new manager adopts a recorded process only when a
process with that pid still runs, started at that time, with that command line; a recycled pid
fails the check, so no instance is started twice and no stranger is adopted.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from dataclasses import asdict, dataclass
from pathlib import Path


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


def running(record: ProcessRecord) -> bool:
    """Whether the recorded process still runs (same pid, start time and command line; not a zombie)."""
    stat = proc_stat(record.pid)
    if stat is None or stat[0] in ("Z", "X") or stat[1] != record.start_ticks:
        return False
    return proc_cmdline(record.pid) == record.cmdline


def find_executable(package: str, executable: str, env: dict[str, str]) -> str:
    """``<prefix>/lib/<package>/<executable>`` of the first prefix on ``AMENT_PREFIX_PATH`` that has it."""
    prefixes = [p for p in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for prefix in prefixes:
        path = Path(prefix) / "lib" / package / executable
        if path.is_file() and os.access(path, os.X_OK):
            return str(path)
    raise StartError(f"no executable {executable} of package {package} in the sourced workspace "
                     f"({len(prefixes)} prefixes on AMENT_PREFIX_PATH): build it and source its install/setup.bash")


def package_environment(package_dir: Path, env: dict[str, str]) -> dict[str, str]:
    """``env`` with the workspace of ``package_dir`` sourced on top (its ``local_setup.bash``).

    ``package_dir`` is a package's install prefix (``ws/install/thermostat``) or a workspace's
    ``install`` folder; the first of it and its parent that has ``local_setup.bash`` is sourced.
    """
    for folder in (package_dir, package_dir.parent):
        setup = folder / "local_setup.bash"
        if setup.is_file():
            done = subprocess.run(["bash", "-c", f'set +u; . "{setup}" >/dev/null && env -0'], env=env,
                                  capture_output=True, timeout=60, check=False)
            if done.returncode != 0:
                raise StartError(f"{setup} failed: {done.stderr.decode(errors='replace').strip()[-300:]}")
            return dict(item.split("=", 1) for item in done.stdout.decode().split("\0") if "=" in item)
    raise StartError(f"{package_dir}: no local_setup.bash here or in its parent (name a package's install "
                     "folder, e.g. ws/install/thermostat)")


class InstanceProcess:
    """A started or adopted process of an instance."""

    def __init__(self, record: ProcessRecord, child: subprocess.Popen[bytes] | None = None) -> None:
        self.record = record
        self.child = child

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
        if self.child is not None:
            return self.child.poll() is None
        return running(self.record)

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
            time.sleep(0.05)
        return True

    def stop(self, grace: float) -> None:
        """SIGTERM, then SIGKILL after ``grace`` seconds; reaped when it is a child."""
        self.signal_group(signal.SIGTERM)
        if not self.wait(grace):
            self.signal_group(signal.SIGKILL)
            self.wait(10.0)


def start(instance: str, node: str, argv: list[str], env: dict[str, str], log: Path, *, package_dir: str,
          iface_file: str, interface_hash: str, generation: int) -> InstanceProcess:
    """Start ``argv`` in a session of its own, output appended to ``log``."""
    log.parent.mkdir(parents=True, exist_ok=True)
    with open(log, "ab") as out:
        try:
            child = subprocess.Popen(argv, env=env, stdin=subprocess.DEVNULL, stdout=out, stderr=subprocess.STDOUT,
                                     start_new_session=True)
        except OSError as e:
            raise StartError(f"cannot start {argv[0]}: {e}") from e
    stat = proc_stat(child.pid)
    cmdline = _settled_cmdline(child, tuple(argv))
    record = ProcessRecord(instance, node, child.pid, stat[1] if stat else 0, cmdline, package_dir,
                           iface_file, interface_hash, generation)
    return InstanceProcess(record, child)


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


def find_by_node(node: str) -> list[ProcessRecord]:
    """Running processes started for the node ``node`` (``__node:=node`` on their command line)."""
    wanted = f"__node:={node}"
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        cmdline = proc_cmdline(int(entry))
        stat = proc_stat(int(entry))
        if cmdline and stat and wanted in cmdline and stat[0] not in ("Z", "X"):
            found.append(ProcessRecord("", node, int(entry), stat[1], cmdline, "", "", "", 1))
    return found


class Records:
    """The process records of one state folder: ``<state dir>/processes/<instance>.json``."""

    def __init__(self, state_dir: Path) -> None:
        self.folder = state_dir / "processes"

    def save(self, record: ProcessRecord) -> None:
        """Write ``record`` atomically."""
        self.folder.mkdir(parents=True, exist_ok=True)
        final = self.folder / f"{record.instance}.json"
        temp = final.with_name(f".tmp-{record.instance}-{os.getpid()}")
        data = asdict(record)
        data["cmdline"] = list(record.cmdline)
        with open(temp, "w", encoding="utf-8") as f:
            json.dump(data, f, sort_keys=True)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, final)

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
