"""Helpers for the compatibility tests: compile fixtures, run the real CLI."""

from __future__ import annotations

import functools
import os
import subprocess
import sys
from pathlib import Path

from iface.semantics.compile import Compilation, Workspace

DATA = Path(__file__).parent / "data"


def compile_file(path: Path | str) -> Compilation:
    """Compile one fixture file in a fresh workspace."""
    return Workspace().compile_path(str(path))


def compile_text(tmp_path: Path, name: str, text: str) -> Compilation:
    """Write ``text`` to ``tmp_path/name`` and compile it."""
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return compile_file(p)


#: Two hash seeds that order sets and dicts of strings differently: output that depends on them differs.
HASH_SEEDS = ("1", "2")


def run_cli(*args: str, cwd: Path | None = None, hash_seed: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python -m iface ARGS`` and capture its output (with ``hash_seed``: under that ``PYTHONHASHSEED``)."""
    env = None if hash_seed is None else {**os.environ, "PYTHONHASHSEED": hash_seed}
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True,
                          cwd=str(cwd or DATA), timeout=120, check=False, env=env)


def run_main(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """The CLI run in this process (``tests.conftest.run_main``), in ``cwd`` (default: the fixtures)."""
    from tests.conftest import run_main as in_process

    return in_process(*args, cwd=cwd or DATA)


@functools.cache
def cached(path: Path) -> Compilation:
    """Compile a fixture once per test session (comparisons do not change compilations)."""
    return compile_file(path)
