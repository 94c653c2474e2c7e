"""Helpers shared by the commands: loading files, printing diagnostics."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterable, Sequence

from ..model.diagnostics import Diagnostic, Severity
from ..semantics.compile import SUFFIXES, Compilation, Workspace


class UsageError(Exception):
    """A problem with the command line or with reading input files (exit code 2)."""


def display_path(path: str) -> str:
    """A path relative to the working directory when it lies below it."""
    try:
        return os.path.relpath(path)
    except ValueError:
        return path


def compile_files(paths: Sequence[str], include_paths: Iterable[str] = ()) -> list[Compilation]:
    """Compile every file; a missing or unreadable file is a UsageError."""
    ws = Workspace(include_paths)
    out = []
    for p in paths:
        if not os.path.isfile(p):
            raise UsageError(f"{p}: no such file")
        if not os.access(p, os.R_OK):
            raise UsageError(f"{p}: cannot read the file")
        out.append(ws.compile_path(p))
    return out


def gather(comps: Sequence[Compilation]) -> list[Diagnostic]:
    """Diagnostics of the compilations and their includes, each file once, in file order."""
    seen: set[tuple[str, int, int, str, str]] = set()
    out: list[Diagnostic] = []
    for c in comps:
        for d in c.all_diagnostics():
            key = (d.path, d.span.start, d.span.end, d.code, d.message)
            if key in seen:
                continue
            seen.add(key)
            out.append(d)
    return out


def print_diagnostics(diags: Sequence[Diagnostic], fmt: str = "text", stream=None) -> None:
    """Print diagnostics as ``path:line:col: severity[code]: message`` lines or as JSON."""
    stream = stream or sys.stdout
    if fmt == "json":
        json.dump({"diagnostics": [d.to_json(display_path(d.path)) for d in diags]}, stream, indent=2)
        stream.write("\n")
        return
    for d in diags:
        stream.write(d.format(display_path(d.path)) + "\n")


def has_errors(diags: Iterable[Diagnostic]) -> bool:
    """True when any diagnostic is an error."""
    return any(d.severity == Severity.ERROR for d in diags)


def check_suffix(path: str) -> None:
    """Refuse files that are neither .iface nor .thrift."""
    if not path.endswith(SUFFIXES):
        raise UsageError(f"{path}: expected a .iface or .thrift file")
