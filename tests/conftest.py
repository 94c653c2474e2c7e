"""Shared test helpers: run the real CLI, find fixtures."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run_cli(*args: str, cwd: Path | None = None, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python -m iface ARGS`` and capture its output."""
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True,
                          cwd=cwd, input=stdin, timeout=300)


@pytest.fixture
def cli():
    """The CLI runner as a fixture."""
    return run_cli
