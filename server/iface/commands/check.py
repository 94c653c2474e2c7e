"""``iface-lsp check [--format text|json] [-q] FILE...``

Text output: one ``path:line:col: severity[code]: message`` line per finding, then one
summary line — ``ok: 2 files, 16 definitions`` when nothing is an error (with the number
of warnings when there are some), ``failed: …`` otherwise. ``-q`` prints errors only and
no summary.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ..model.diagnostics import Diagnostic, Severity
from ..semantics.compile import Compilation
from .common import (
    UsageError,
    check_suffix,
    compile_readable,
    gather,
    has_errors,
    print_diagnostics,
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE", help=".iface or .thrift files")
    p.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    p.add_argument("-q", "--quiet", action="store_true", help="print errors only, and no summary line")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def _count(n: int, what: str) -> str:
    return f"{n} {what}{'' if n == 1 else 's'}"


def summary(comps: Sequence[Compilation], diags: Sequence[Diagnostic], unread: int = 0) -> str:
    """``ok: 2 files, 16 definitions`` (``, 3 warnings`` when there are some), or ``failed: …`` with errors.

    Files named but not read count among the files, with ``(N not read)``.
    """
    files = {c.path: c for comp in comps for c in comp.closure()}
    parts = [_count(len(files) + unread, "file") + (f" ({unread} not read)" if unread else ""),
             _count(sum(len(c.interface.definitions) for c in files.values()), "definition")]
    errors = sum(1 for d in diags if d.severity == Severity.ERROR)
    warnings = sum(1 for d in diags if d.severity == Severity.WARNING)
    if errors:
        return f"failed: {_count(errors, 'error')}" + (f", {_count(warnings, 'warning')}" if warnings else "") + \
            f" in {', '.join(parts)}"
    return "ok: " + ", ".join(parts + ([_count(warnings, "warning")] if warnings else []))


def run(args: argparse.Namespace) -> int:
    """Exit 0 without errors, 1 with errors, 2 on usage or I/O errors.

    A file that cannot be read is one ``cannot-read`` diagnostic (exit 2); the
    other files are still checked and their diagnostics printed.
    """
    try:
        for f in args.files:
            check_suffix(f)
    except UsageError as e:
        print(f"iface-lsp check: {e}", file=sys.stderr)
        return 2
    comps, unread = compile_readable(args.files, args.include_path)
    diags = gather(comps) + unread
    shown = [d for d in diags if d.severity == Severity.ERROR] if args.quiet else diags
    print_diagnostics(shown, args.format)
    if args.format == "text" and not args.quiet:
        print(summary(comps, diags, len({d.path for d in unread})))
    return 2 if unread else 1 if has_errors(diags) else 0
