"""Shared test helpers: run the real CLI, find fixtures."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# A shell starts background jobs with SIGINT ignored, and an ignored signal stays ignored in every
# child: the CLI under test would then never see Ctrl-C. Tests that send SIGINT to the CLI must not
# depend on how pytest was started, so the session handles SIGINT itself (children get the default).
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


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


def run_main(*args: str) -> subprocess.CompletedProcess[str]:
    """Run ``iface-lsp ARGS`` in this process (``iface.cli.main``: no interpreter start) and capture its output."""
    from iface.cli import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(list(args))
    return subprocess.CompletedProcess(["iface-lsp", *args], code, out.getvalue(), err.getvalue())


@pytest.fixture
def cli():
    """The CLI runner as a fixture."""
    return run_cli


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the groups
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under pytest-xdist (``--dist loadgroup``, as scripts/test.sh runs it), each module's tests run in one
    worker, so that its module-scoped fixtures (servers, builds) are made once, and every test that runs ROS 2
    goes to one worker per ROS 2 release, because they share one colcon workspace built per session and release.
    Those groups are the longest, so they are handed out first."""
    # in a worker xdist turns "dist" into "no" and keeps "loadgroup"; the controller collects nothing
    if not getattr(config.option, "loadgroup", False):
        return
    ros = [item for item in items if "ros_venv" in getattr(item, "fixturenames", ())]
    for item in ros:  # one group per ROS 2 release (tests/runtime/conftest.py): each builds its own workspace
        release = getattr(item, "callspec", None) and item.callspec.params.get("ros_release")
        item.add_marker(pytest.mark.xdist_group(f"ros-{release}" if release else "ros"))
    rest = [item for item in items if "ros_venv" not in getattr(item, "fixturenames", ())]
    for item in rest:
        item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::", 1)[0]))
    items[:] = ros + rest
