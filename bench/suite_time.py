"""Where the test suite's time goes (docs/testing.md, "How long each part takes"):

    python bench/suite_time.py                     # run scripts/test.sh (every test) and print the figures
    python bench/suite_time.py -- tests/core       # one part: what follows -- goes to scripts/test.sh
    python bench/suite_time.py --keep DIR          # keep the run's records in DIR (junit.xml, cpu.*, run.json)
    python bench/suite_time.py --read DIR          # the figures of a run kept in DIR, without running anything
    python bench/suite_time.py --processes         # also the CPU of every process by its name (process accounting)

A run sets ``IFACE_TEST_CPU`` (each test's CPU and wall seconds, tests/conftest.py) and a JUnit report. It
prints the run's wall time and CPU (user + system of every process it waited for, as ``/usr/bin/time`` counts),
the share of the cores left idle, the outcome; the worker-seconds and CPU-seconds per folder, per module (once
per ROS 2 release where a module runs per release) and per worker (the balance); per minute of the run, the
share of the cores idle and how many workers were in a ``runtime/`` test (mostly waiting on the processes it
started) or in another one; the load average before and after. Run it on a quiet machine: a figure taken beside
other work measures that work too, and the idle share is the whole machine's.

``--processes`` turns on the kernel's process accounting for the run (``accton``, root, Debian's ``acct``) and
adds the CPU of every process that ended during it, by its name: the ``ros2`` commands, nodes, language servers,
compilers, Chromium… (a process started through a script is named after the script; one started as ``python -m``
is ``python``/``python3``, the workers among them). It counts the whole machine's processes, as the idle share does.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Self

ROOT = Path(__file__).resolve().parents[1]
RELEASES = ("kilted", "jazzy")


@dataclass(frozen=True)
class Test:
    """One line of an ``IFACE_TEST_CPU`` file."""

    worker: str
    cpu: float
    wall: float
    module: str
    release: str
    #: Unix time the test started (None in records written before the column was added).
    start: float | None


def parse_cpu_line(worker: str, line: str) -> Test | None:
    """``CPU<TAB>WALL<TAB>NODEID[<TAB>START]`` (written by tests/conftest.py), or None for a line that is not one."""
    parts = line.rstrip("\n").split("\t")
    if len(parts) < 3:
        return None
    try:
        cpu, wall = float(parts[0]), float(parts[1])
        start = float(parts[3]) if len(parts) > 3 else None
    except ValueError:
        return None
    nodeid = parts[2]
    group = nodeid.rsplit("@", 1)[1] if "@" in nodeid else ""
    release = next((r for r in RELEASES if group.endswith(f"-{r}")), "")
    return Test(worker, cpu, wall, nodeid.split("::", 1)[0], release, start)


def read_cpu(prefix: Path) -> list[Test]:
    """Every test of the files ``PREFIX.WORKER``."""
    tests = []
    for path in sorted(prefix.parent.glob(prefix.name + ".*")):
        worker = path.name[len(prefix.name) + 1:]
        for line in path.read_text(encoding="utf-8").splitlines():
            if (test := parse_cpu_line(worker, line)) is not None:
                tests.append(test)
    return tests


def outcome(junit: Path) -> dict[str, int]:
    """Tests, failures, errors and skipped of a JUnit report (every suite of it)."""
    root = ET.parse(junit).getroot()
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    keys = ("tests", "failures", "errors", "skipped")
    return {k: sum(int(s.get(k, 0)) for s in suites) for k in keys}


@dataclass(frozen=True)
class Ended:
    """One process that ended, from the accounting file (``dump-acct``)."""

    name: str
    cpu: float


def parse_acct_line(line: str, ticks: float = 100.0) -> Ended | None:
    """``NAME|v3|USER|SYSTEM|ELAPSED|…`` (``dump-acct``; times in clock ticks), or None for a line that is not one."""
    parts = line.split("|")
    if len(parts) < 4:
        return None
    try:
        return Ended(parts[0].strip(), (float(parts[2]) + float(parts[3])) / ticks)
    except ValueError:
        return None


def read_acct(path: Path) -> list[Ended]:
    """The processes recorded in the accounting file ``path`` (empty when ``dump-acct`` is not installed)."""
    try:
        dump = subprocess.run(["dump-acct", str(path)], capture_output=True, text=True, check=False).stdout
    except FileNotFoundError:
        return []
    ticks = float(os.sysconf("SC_CLK_TCK"))
    return [e for e in (parse_acct_line(line, ticks) for line in dump.splitlines()) if e is not None]


def by_name(ended: list[Ended], top: int) -> list[str]:
    """CPU-seconds, count and median per process name, the most CPU first; a line for the rest."""
    names: dict[str, list[float]] = defaultdict(list)
    for e in ended:
        names[e.name].append(e.cpu)
    rows = sorted(names.items(), key=lambda kv: -sum(kv[1]))
    total = sum(e.cpu for e in ended)
    width = max([len(n) for n, _ in rows[:top]] + [12])
    out = [f"processes by name ({len(ended):,} ended, {total:.0f} CPU-seconds)",
           f"{'name':<{width}}  {'count':>6}  {'CPU-s':>7}  {'median':>6}"]
    for name, cpus in rows[:top]:
        out.append(f"{name:<{width}}  {len(cpus):6d}  {sum(cpus):7.0f}  {sorted(cpus)[len(cpus) // 2]:6.2f}")
    if rest := rows[top:]:
        out.append(f"{f'{len(rest)} others':<{width}}  {sum(len(c) for _, c in rest):6d}  "
                   f"{sum(sum(c) for _, c in rest):7.0f}")
    return out


def folder_of(module: str) -> str:
    """``tests/runtime/test_x.py`` -> ``runtime/``; a module at the top of tests/ stands for itself."""
    parts = module.split("/")
    return f"{parts[1]}/" if len(parts) > 2 else parts[-1]


def cpu_times() -> tuple[float, float]:
    """(idle, total) jiffies of every core since boot (``/proc/stat``)."""
    with open("/proc/stat", encoding="ascii") as f:
        values = [float(v) for v in f.readline().split()[1:]]
    return values[3] + values[4], sum(values[:8])  # idle + iowait; user … steal


class Sampler:
    """The machine's CPU use, looked at every second in a thread of its own: (Unix time, idle, total) samples."""

    def __init__(self) -> None:
        self.samples: list[tuple[float, float, float]] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while True:
            self.samples.append((time.time(), *cpu_times()))
            if self._stop.wait(1.0):
                return

    def __enter__(self) -> Self:
        self._thread.start()
        return self

    def __exit__(self, *_: object) -> None:
        self._stop.set()
        self._thread.join()
        self.samples.append((time.time(), *cpu_times()))


def timeline(tests: list[Test], samples: list[list[float]], minute: float = 60.0) -> list[str]:
    """Per minute of the run: the share of the cores idle (the samples), and how many workers were in a
    ``runtime/`` test and in another one, on average (the tests' start and wall seconds)."""
    timed = [t for t in tests if t.start is not None]
    if not timed and len(samples) < 2:
        return []
    begin = min([t.start for t in timed if t.start is not None] + [s[0] for s in samples[:1]])
    end = max([t.start + t.wall for t in timed if t.start is not None] + [s[0] for s in samples[-1:]])
    buckets = max(1, math.ceil((end - begin) / minute))
    busy = {"runtime/": [0.0] * buckets, "other": [0.0] * buckets}
    for t in timed:
        assert t.start is not None
        kind = "runtime/" if folder_of(t.module) == "runtime/" else "other"
        a, b = t.start - begin, t.start - begin + t.wall
        for i in range(int(a // minute), min(buckets, int(b // minute) + 1)):
            busy[kind][i] += max(0.0, min(b, (i + 1) * minute) - max(a, i * minute)) / minute
    idle: list[str] = ["" for _ in range(buckets)]
    for i in range(buckets):
        inside = [s for s in samples if begin + i * minute <= s[0] <= begin + (i + 1) * minute]
        if len(inside) >= 2 and inside[-1][2] > inside[0][2]:
            idle[i] = f"{(inside[-1][1] - inside[0][1]) / (inside[-1][2] - inside[0][2]):.0%}"
    out = [f"{'minute':>6}  {'cores idle':>10}  {'workers in runtime/':>19}  {'in others':>9}"]
    out += [f"{i:6d}  {idle[i]:>10}  {busy['runtime/'][i]:19.1f}  {busy['other'][i]:9.1f}" for i in range(buckets)]
    return out


def tally(tests: list[Test], name: Callable[[Test], str]) -> list[tuple[str, float, float]]:
    """(name, worker-seconds, CPU-seconds) of the tests under each ``name``, the longest first."""
    wall: defaultdict[str, float] = defaultdict(float)
    cpu: defaultdict[str, float] = defaultdict(float)
    for t in tests:
        wall[name(t)] += t.wall
        cpu[name(t)] += t.cpu
    return sorted(((n, wall[n], cpu[n]) for n in wall), key=lambda row: -row[1])


def table(rows: list[tuple[str, float, float]], head: str) -> list[str]:
    """Aligned lines: name, worker-seconds, CPU-seconds."""
    width = max([len(head), *(len(r[0]) for r in rows)])
    out = [f"{head:<{width}}  {'worker-s':>9}  {'CPU-s':>7}"]
    out += [f"{name:<{width}}  {wall:9.0f}  {cpu:7.0f}" for name, wall, cpu in rows]
    return out


def report(tests: list[Test], run: dict[str, Any], counts: dict[str, int] | None, top: int,
           samples: list[list[float]] | None = None) -> str:
    """The figures, as lines of text."""
    lines = []
    if run:
        wall, cpu, cores = float(run["wall"]), float(run["cpu"]), int(run["cores"])
        idle = max(0.0, 1 - cpu / (cores * wall)) if wall else 0.0
        lines.append(f"run: {run.get('commit', '?')} {run.get('date', '')}, exit {run.get('exit')}, "
                     f"{run.get('workers')} workers on {cores} cores")
        lines.append(f"wall {wall / 60:.1f} min ({wall:.0f} s); CPU {cpu / 60:.1f} min ({cpu:.0f} s, user "
                     f"{float(run['user']):.0f} + system {float(run['system']):.0f}); "
                     f"cores idle {idle:.0%}")
        lines.append(f"load average before {run.get('load_before')}, after {run.get('load_after')}")
    if counts is not None:
        passed = counts["tests"] - counts["failures"] - counts["errors"] - counts["skipped"]
        lines.append(f"tests {counts['tests']:,}: {passed:,} passed, {counts['failures']} failed, "
                     f"{counts['errors']} errors, {counts['skipped']} skipped")
    if not tests:
        return "\n".join(lines + ["(no IFACE_TEST_CPU records)"])
    total_wall, total_cpu = sum(t.wall for t in tests), sum(t.cpu for t in tests)
    lines.append(f"in the tests: {total_wall:.0f} worker-seconds, {total_cpu:.0f} CPU-seconds")
    lines += ["", *table(tally(tests, lambda t: folder_of(t.module)), "folder")]
    modules = tally(tests, lambda t: t.module + (f" [{t.release}]" if t.release else ""))
    lines += ["", *table(modules[:top], f"longest {top} modules")]
    lines += ["", *table(sorted(tally(tests, lambda t: f"worker {t.worker}")), "worker")]
    if steps := timeline(tests, samples or []):
        lines += ["", *steps]
    return "\n".join(lines)


def run_suite(records: Path, args: list[str], processes: bool = False) -> dict[str, Any]:
    """Run scripts/test.sh ARGS with its records in ``records`` (``processes``: and the process accounting's, in
    ``records/pacct``); what the run took."""
    for old in records.glob("cpu.*"):  # the conftest appends: a kept folder's last run would count twice
        old.unlink()
    env = dict(os.environ)
    env["IFACE_TEST_CPU"] = str(records / "cpu")
    env["PYTEST_ADDOPTS"] = f"{env.get('PYTEST_ADDOPTS', '')} --junitxml={records / 'junit.xml'}".strip()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True,
                            check=False).stdout.strip()
    cores = len(os.sched_getaffinity(0))
    before, load_before, start = resource.getrusage(resource.RUSAGE_CHILDREN), os.getloadavg(), time.monotonic()
    accounting = records / "pacct"
    accounting.unlink(missing_ok=True)  # a kept folder's last run: its processes are not this run's
    if processes:
        accounting.write_bytes(b"")
        on = subprocess.run(["accton", str(accounting)], check=False, capture_output=True, text=True)
        if on.returncode != 0:
            print(f"suite_time.py: process accounting not turned on: {on.stderr.strip()}", file=sys.stderr)
            accounting.unlink()
            processes = False
    try:
        with Sampler() as machine:
            code = subprocess.run(["bash", str(ROOT / "scripts" / "test.sh"), *args], cwd=ROOT, env=env,
                                  check=False).returncode
    finally:
        if processes:
            subprocess.run(["accton", "off"], check=False, capture_output=True)
    (records / "machine.json").write_text(json.dumps(machine.samples) + "\n", encoding="utf-8")
    wall, after = time.monotonic() - start, resource.getrusage(resource.RUSAGE_CHILDREN)
    user, system = after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime
    run = {"commit": commit, "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "exit": code,
           "wall": round(wall, 1), "user": round(user, 1), "system": round(system, 1), "cpu": round(user + system, 1),
           "cores": cores, "workers": env.get("IFACE_TEST_WORKERS", str(cores + 1)),
           "load_before": " ".join(f"{x:.2f}" for x in load_before),
           "load_after": " ".join(f"{x:.2f}" for x in os.getloadavg())}
    (records / "run.json").write_text(json.dumps(run, indent=1) + "\n", encoding="utf-8")
    return run


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    passed = argv[argv.index("--") + 1:] if "--" in argv else []
    own = argv[:argv.index("--")] if "--" in argv else argv
    parser = argparse.ArgumentParser(prog="suite_time.py", description=__doc__.splitlines()[0])
    parser.add_argument("--read", type=Path, metavar="DIR", help="print the figures of a run kept in DIR")
    parser.add_argument("--keep", type=Path, metavar="DIR", help="keep the run's records in DIR")
    parser.add_argument("--top", type=int, default=25, help="modules listed (default 25)")
    parser.add_argument("--processes", action="store_true",
                        help="also the CPU of every process by its name (process accounting: root and accton)")
    options = parser.parse_args(own)
    if options.processes and options.read is None and (os.geteuid() != 0 or not shutil.which("accton")):
        print("suite_time.py: --processes needs root and accton (apt-get install acct)", file=sys.stderr)
        return 2
    if options.read is not None:
        records = options.read
        if not records.is_dir():
            print(f"suite_time.py: {records}: no such folder", file=sys.stderr)
            return 2
        run, code = None, 0
    else:
        records = options.keep or Path(tempfile.mkdtemp(prefix="iface-suite-time-"))
        records.mkdir(parents=True, exist_ok=True)
        run = run_suite(records, passed, options.processes)
        code = int(run["exit"])
    try:
        print(figures(records, run, options.top))
    except (OSError, ValueError, LookupError, TypeError, ET.ParseError) as e:
        print(f"suite_time.py: {records}: records not readable: {e}", file=sys.stderr)
        return 2
    print(f"(records: {records})")
    return code


def figures(records: Path, run: dict[str, Any] | None, top: int) -> str:
    """The report of the records in ``records`` (``run``: the run just made, else its run.json if any)."""
    run_file, junit, machine = records / "run.json", records / "junit.xml", records / "machine.json"
    if run is None:
        run = json.loads(run_file.read_text(encoding="utf-8")) if run_file.is_file() else {}
    samples = json.loads(machine.read_text(encoding="utf-8")) if machine.is_file() else []
    text = report(read_cpu(records / "cpu"), run, outcome(junit) if junit.is_file() else None, top, samples)
    if (records / "pacct").is_file():
        ended = read_acct(records / "pacct")
        text += "\n\n" + ("\n".join(by_name(ended, top)) if ended else
                           "(process accounting kept, but dump-acct is not installed or read nothing)")
    return text


if __name__ == "__main__":
    sys.exit(main())
