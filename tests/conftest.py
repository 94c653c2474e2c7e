"""Shared test helpers: run the real CLI, find fixtures."""

from __future__ import annotations

import io
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


def run_cli(*args: str, cwd: Path | None = None, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python -m iface ARGS`` and capture its output."""
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True,
                          cwd=cwd, input=stdin, timeout=300)


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
