"""Helpers shared by the commands: loading files, printing diagnostics."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

from ..compat.systemfile import system_findings
from ..model.diagnostics import Diagnostic, Severity, make
from ..model.source import Source, Span
from ..semantics.compile import SUFFIXES, Compilation, Workspace

if TYPE_CHECKING:  # emit is not imported by `check`: it loads jinja2
    from ..emit.write import WriteReport


class UsageError(Exception):
    """A problem with the command line or with reading input files (exit code 2)."""


def display_path(path: str) -> str:
    """A path relative to the working directory when it lies below it."""
    try:
        return os.path.relpath(path)
    except ValueError:
        return path


def unreadable(path: str) -> str | None:
    """Why ``path`` cannot be read as an input file; None when it can."""
    if not os.path.isfile(path):
        return "is a folder, not a file" if os.path.isdir(path) else "no such file"
    if not os.access(path, os.R_OK):
        return "cannot read the file"
    return None


def compile_files(paths: Sequence[str], include_paths: Iterable[str] = ()) -> list[Compilation]:
    """Compile every file; a missing or unreadable file is a UsageError (raised before any is compiled)."""
    for p in paths:
        problem = unreadable(p)
        if problem is not None:
            raise UsageError(f"{p}: {problem}")
    return compile_readable(paths, include_paths)[0]


def compile_readable(paths: Sequence[str], include_paths: Iterable[str] = ()) -> tuple[list[Compilation],
                                                                                        list[Diagnostic]]:
    """Compile every file that can be read; each one that cannot gets one ``cannot-read`` diagnostic."""
    ws = Workspace(include_paths)
    comps: list[Compilation] = []
    problems: list[Diagnostic] = []
    for p in paths:
        problem = unreadable(p)
        if problem is None:
            comps.append(ws.compile_path(p))
        else:
            problems.append(make("cannot-read", problem, Source(p, ""), Span(0, 0)))
    return comps, problems


def gather(comps: Sequence[Compilation]) -> list[Diagnostic]:
    """Diagnostics of the compilations and their includes, each file once, in file order; a system file's
    with the conflicts of its system graph."""
    seen: set[tuple[str, int, int, str, str]] = set()
    out: list[Diagnostic] = []
    for c in comps:
        for d in [*c.all_diagnostics(), *system_findings(c)]:
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
        hint = ""
        if path.endswith((".msg", ".srv", ".action", ".idl")):
            hint = f"; import a ROS 2 interface first: iface-lsp import --from ros2 {path} --out DIR"
        raise UsageError(f"{path}: expected a .iface or .thrift file{hint}")


def print_link_notes(report: WriteReport, out: str, prog: str) -> None:
    """Say on stderr which symbolic links were refused, and which ``--force`` replaced (never followed); each line
    starts with ``prog`` (``iface-lsp generate``)."""
    for rel in report.links:
        print(f"{prog}: {os.path.join(out, rel)} is a symbolic link; not followed and not replaced "
              "(--force replaces the link itself with the file)", file=sys.stderr)
    for rel, target in report.replaced_links.items():
        print(f"{prog}: {os.path.join(out, rel)} was a symbolic link to {target}; --force replaced "
              "the link with the file and left its target untouched", file=sys.stderr)
