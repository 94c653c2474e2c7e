"""Shared test helpers: run the real CLI, find fixtures."""

from __future__ import annotations

import contextlib
import io
import os
import resource
import signal
import subprocess
import sys
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# A shell starts background jobs with SIGINT ignored, and an ignored signal stays ignored in every
# child: the CLI under test would then never see Ctrl-C. Tests that send SIGINT to the CLI must not
# depend on how pytest was started, so the session handles SIGINT itself (children get the default).
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _stopped(signum: int, frame: object) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


# A run stopped by SIGTERM (`timeout`, a cancelled CI job) ends as on Ctrl-C: the fixtures tear down, and so
# stop every process they started (ROS nodes, launch, managers) instead of leaving them to run on.
if signal.getsignal(signal.SIGTERM) is signal.SIG_DFL:
    signal.signal(signal.SIGTERM, _stopped)


def run_cli(*args: str, cwd: Path | None = None, stdin: str | None = None,
            hash_seed: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python -m iface ARGS`` and capture its output (with ``hash_seed``: under that ``PYTHONHASHSEED``)."""
    env = None if hash_seed is None else {**os.environ, "PYTHONHASHSEED": hash_seed}
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True,
                          cwd=cwd, input=stdin, timeout=300, env=env)


#: Two hash seeds that order sets and dicts of strings differently: output that depends on them differs.
HASH_SEEDS = ("1", "2")

#: What ``generated_in_two_processes`` runs: every file ``target`` generates for each path, with its findings.
_GENERATE = """import sys
from iface.emit import generate
from iface.semantics.compile import Workspace
target = sys.argv[1]
for path in sys.argv[2:]:
    result = generate(Workspace().compile_path(path), target)
    print(path, [(f.path, f.text) for f in result.files], [d.format() for d in result.diagnostics])
"""


def in_two_processes(code: str, *args: str) -> tuple[str, str]:
    """The output of the Python ``code`` (with ``args``) run in two processes under different hash seeds."""
    outs = []
    for seed in HASH_SEEDS:
        r = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, cwd=ROOT,
                           timeout=300, env={**os.environ, "PYTHONHASHSEED": seed})
        assert r.returncode == 0, r.stderr[-2000:]
        outs.append(r.stdout)
    return outs[0], outs[1]


def generated_in_two_processes(target: str, paths: list[Path]) -> tuple[str, str]:
    """What ``target`` generates for each of ``paths``, in two processes under different hash seeds."""
    return in_two_processes(_GENERATE, target, *(str(p) for p in paths))


def run_main(*args: str, cwd: Path | str | None = None, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``iface-lsp ARGS`` in this process (``iface.cli.main``: no interpreter start) and capture its output.

    For a test of what the CLI prints and returns; what only the process shows (its exit status as the
    interpreter ends, signals, a closed pipe, ``python -m iface``, hash seeds) needs ``run_cli``.
    ``cwd``: the folder it runs in (this process's is changed, then restored); ``stdin``: its input.
    """
    from iface.cli import main

    # streams as a process has them: UTF-8, strict on stdout and backslashreplace on stderr, so that what
    # a terminal cannot take fails here as it would there (the CLI reconfigures them as it does a real one)
    out = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict", newline="\n", write_through=True)
    err = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="backslashreplace", newline="\n",
                           write_through=True)
    saved = sys.stdin
    if stdin is not None:
        sys.stdin = io.TextIOWrapper(io.BytesIO(stdin.encode("utf-8")), encoding="utf-8")
    try:
        with contextlib.chdir(cwd or os.getcwd()), redirect_stdout(out), redirect_stderr(err):
            try:
                code = main(list(args))
            except SystemExit as e:  # as the interpreter would turn it into the exit status
                code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    finally:
        sys.stdin = saved
    texts = [stream.buffer.getvalue().decode("utf-8") for stream in (out, err)]
    return subprocess.CompletedProcess(["iface-lsp", *args], code, *texts)


@pytest.fixture
def cli():
    """The CLI runner as a fixture."""
    return run_cli


#: Seconds the longest modules take in one worker (a module run once per ROS 2 release: each run), measured on a
#: warm test cache with three workers (2026-11-30, the tests of 29111dc; docs/testing.md, "How long each part takes").
LONG = {
    "tests/core/test_every_command.py": 243,
    "tests/runtime/test_launch.py": 154,
    "tests/runtime/test_manager.py": 122,
    "tests/runtime/test_ros2_iface.py": 106,
    "tests/runtime/test_rclcpp_e2e.py": 86,
    "tests/emit/test_reserved_names.py": 82,
    "tests/core/test_incremental.py": 78,
    "tests/test_vscode_extension.py": 71,
    "tests/runtime/test_manager_containers.py": 63,
    "tests/runtime/test_live.py": 42,
    "tests/importers/test_json_roundtrip_all.py": 41,
    "tests/runtime/test_rclpy_e2e.py": 38,
    "tests/lsp/test_limits.py": 35,
    "tests/runtime/test_handover.py": 34,
    "tests/runtime/test_rclpy_start.py": 30,
    "tests/core/test_typing.py": 24,
    "tests/lsp/test_incremental.py": 21,
    "tests/lsp/test_robustness.py": 18,
    "tests/importers/test_jsonform.py": 18,
    "tests/core/test_layering.py": 17,
    "tests/runtime/test_containers.py": 13,
    "tests/runtime/test_ros2cli_harness.py": 12,
}
#: Seconds taken for a module that ``LONG`` does not name.
SHORT = 3.0
#: The ROS modules that build C++ (minutes each on a cold cache): the first ROS modules handed out.
CPP_FIRST = ("tests/runtime/test_rclcpp_e2e.py", "tests/runtime/test_manager_containers.py",
             "tests/runtime/test_containers.py")
#: Workers in a ``runtime/`` module for each one in another module. A ROS test mostly waits on the nodes, launch
#: trees and discovery it started (0.4-0.5 of a core, "How long each part takes"); the others compute (0.7-0.8):
#: three ROS modules at once had left the cores a quarter idle, two and one leave them a fifth.
WAITING_PER_COMPUTING = 2.0


def _module_of(group: str) -> str:
    return group.split(".py", 1)[0] + ".py"


def _release_of(group: str) -> str:
    """The release a group runs on, "" for a group that is its module alone."""
    return group[len(_module_of(group)) + 1:]


def handed_out(groups: list[str]) -> list[str]:
    """The order in which the workers get ``groups`` (``module`` or ``module-release``): the ``runtime/`` ones (a
    release after the other; the C++ builders first, then the longest first) and the others (the longest first)
    interleaved, so that ``WAITING_PER_COMPUTING`` worker-seconds of the first go with each one of the second, as
    long as both last."""
    per_release = {_module_of(g) for g in groups if _release_of(g)}

    def seconds(group: str) -> float:
        module = _module_of(group)
        if not _release_of(group) and module in per_release:
            return SHORT  # a per-release module's few tests that run once
        return LONG.get(module, SHORT)

    releases = list(dict.fromkeys(_release_of(g) for g in groups if _release_of(g)))

    def release(group: str) -> int:  # a worker then changes release once: its session fixtures are made twice
        return releases.index(_release_of(group)) if _release_of(group) else 0

    waiting = sorted((g for g in groups if g.startswith("tests/runtime/")),
                     key=lambda g: (release(g), _module_of(g) not in CPP_FIRST, -seconds(g)))
    computing = sorted((g for g in groups if not g.startswith("tests/runtime/")), key=lambda g: -seconds(g))
    order: list[str] = []
    waited = computed = 0.0
    while waiting or computing:
        if waiting and (not computing or waited <= WAITING_PER_COMPUTING * computed):
            group = waiting.pop(0)
            waited += seconds(group)
        else:
            group = computing.pop(0)
            computed += seconds(group)
        order.append(group)
    return order


#: The group (``module`` or ``module-release``) of an item under ``--dist loadgroup``.
GROUP = pytest.StashKey[str]()


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the groups
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under pytest-xdist (``--dist loadgroup --no-loadscope-reorder``, as scripts/test.sh runs it), each module's
    tests run in one worker (a module run once per ROS 2 release: once per release), so that its module-scoped
    fixtures (servers, scenarios) are made once; the groups are handed out in the order of ``handed_out``
    (``HandOut``; a worker gets the next group when it is about to finish one). The ROS modules spread over the
    workers like the others: their workspaces come from the test cache (tests/ros_harness/cache.py), where a
    worker waits for, or takes, what another one builds, never building it twice."""
    # in a worker xdist turns "dist" into "no" and keeps "loadgroup"; the controller collects nothing
    if not getattr(config.option, "loadgroup", False):
        return
    for item in items:
        callspec = getattr(item, "callspec", None)
        release = callspec.params.get("ros_release") if callspec is not None else None
        module = item.nodeid.split("::", 1)[0]
        item.stash[GROUP] = f"{module}-{release}" if release else module
        item.add_marker(pytest.mark.xdist_group(item.stash[GROUP]))


class HandOut:
    """Puts the groups in the order of ``handed_out``: after pytest's own hook, which keeps the tests of one ROS 2
    release (a session-scoped parameter) together, and so had every Kilted module handed out before the others."""

    @pytest.hookimpl(trylast=True)
    def pytest_collection_modifyitems(self, items: list[pytest.Item]) -> None:
        if not items or any(GROUP not in item.stash for item in items):
            return
        order = handed_out(list(dict.fromkeys(item.stash[GROUP] for item in items)))
        rank = {group: i for i, group in enumerate(order)}
        items.sort(key=lambda item: rank[item.stash[GROUP]])  # stable: a module's order is kept


def pytest_configure(config: pytest.Config) -> None:
    config.pluginmanager.register(HandOut(), "iface-hand-out")


def _cpu_seconds() -> float:
    """User and system CPU of this process and of the children it has waited for."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None):
    """With ``IFACE_TEST_CPU=FILE``, one line per test in FILE.<worker>: CPU seconds (the test's process and the
    processes it started and waited for: nodes, ``ros2`` commands, builds), wall seconds, node id, start (Unix
    time). A module's fixtures count in the test that set them up or tore them down (docs/testing.md, "Running
    one part")."""
    target = os.environ.get("IFACE_TEST_CPU")
    if not target:
        yield
        return
    cpu, wall, start = _cpu_seconds(), time.monotonic(), time.time()
    yield
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(f"{target}.{worker}", "a", encoding="utf-8") as out:
        out.write(f"{_cpu_seconds() - cpu:.2f}\t{time.monotonic() - wall:.2f}\t{item.nodeid}\t{start:.2f}\n")
