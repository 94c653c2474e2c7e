"""Helpers for the core tests."""

from __future__ import annotations

import re
from pathlib import Path

from iface.semantics.compile import Compilation, Workspace

DATA = Path(__file__).parent / "data"
EXPECT = re.compile(r"expect: ([a-z0-9-]+(?:\s*,\s*[a-z0-9-]+)*)")


def compile_file(path: Path | str) -> Compilation:
    """Compile a file with a fresh workspace."""
    return Workspace().compile_path(str(path))


def expectations(path: Path) -> set[tuple[int, str]]:
    """(1-based line, code) pairs marked in a fixture with ``// expect: code``."""
    out = set()
    for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        m = EXPECT.search(line)
        if m:
            for code in m.group(1).split(","):
                out.add((i, code.strip()))
    return out
