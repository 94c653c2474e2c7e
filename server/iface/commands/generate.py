"""``iface-lsp generate FILE... --target T [--out DIR] [--dry-run] [--check] [--force] [-q]``

Exit 0 on success; 1 when the input has errors (nothing is written), when ``--check``
finds files that differ, or when a hand-edited file is refused; 2 on usage or I/O errors,
including an output path the file system cannot hold (found before anything is written);
3 when a target fails with an unexpected exception (its ``internal-error``: a bug, nothing written).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from typing import Any

from ..emit.base import GeneratedFile, GenerationError, Target
from ..emit.registry import guarded, targets
from ..emit.write import WriteReport, write_files
from ..model.diagnostics import Diagnostic, Severity
from ..nodes.launch import TARGET as LAUNCH
from .common import (
    UsageError,
    check_suffix,
    compile_files,
    display_path,
    gather,
    has_errors,
    print_diagnostics,
    print_link_notes,
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE", help=".iface or .thrift files")
    p.add_argument("-t", "--target", required=True, metavar="T", help="the target (see `iface-lsp targets`)")
    p.add_argument("-o", "--out", default=".", metavar="DIR", help="the output folder (default: .)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--dry-run", action="store_true", help="list what would be written, write nothing")
    mode.add_argument("--check", action="store_true", help="exit 1 when files on disk differ from what "
                      "would be generated")
    p.add_argument("--force", action="store_true", help="overwrite generated files edited by hand")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines and no warnings")
    p.add_argument("--templates", metavar="DIR", help="a folder of templates that override the target's")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def _fail(message: str) -> int:
    print(f"iface-lsp generate: {message}", file=sys.stderr)
    return 2


Input = tuple[str, frozenset[str], list[GeneratedFile]]  # (shown path, files it includes, its files)


def _merge(per_input: Sequence[Input]) -> tuple[list[GeneratedFile], list[str]]:
    """All files, once each; a path two inputs generate differently is a conflict.

    When one input includes the other (a package split over two files, as the ROS 2
    importer writes a message and a service of one name), the including input's
    version wins: it was rendered with everything the included one has.
    """
    by_path: dict[str, tuple[str, frozenset[str], GeneratedFile]] = {}
    conflicts = []
    for source, includes, files in per_input:
        for f in files:
            seen = by_path.get(f.path)
            if seen is None or seen[2].text == f.text:
                by_path.setdefault(f.path, (source, includes, f))
            elif seen[0] in includes:
                by_path[f.path] = (source, includes, f)
            elif source not in seen[1]:
                conflicts.append(f"{f.path}: generated differently from {seen[0]} and {source}")
    return [f for _, _, f in sorted(by_path.values(), key=lambda sf: sf[2].path)], conflicts


def _generate(target: Target, args: argparse.Namespace,
              notes: list[str]) -> tuple[list[GeneratedFile], list[Diagnostic], int]:
    """Compile and render every input; (files, diagnostics, exit code so far); the targets' notes into ``notes``."""
    for f in args.files:
        check_suffix(f)
    comps = compile_files(args.files, args.include_path)
    diags = gather(comps)
    if has_errors(diags):  # a file's own errors first: a binary or broken file declares neither kind
        return [], diags, 1
    for comp in comps:
        if (comp.interface.system is not None) != (target.name == LAUNCH.name):
            raise UsageError(f"{display_path(comp.path)} is a system file: generate its launch file with "
                             "--target launch (and each component from its own file)"
                             if comp.interface.system is not None else
                             f"{display_path(comp.path)} declares no system: --target launch writes a system "
                             "file's launch file")
    options: dict[str, Any] = {"out": args.out, "check": bool(args.check)}
    if args.templates:
        options["templates"] = args.templates
    per_input = []
    found: list[Diagnostic] = []
    for comp in comps:
        result = target.generate(comp, options)
        found.extend(result.diagnostics)
        notes.extend(n for n in result.notes if n not in notes)
        included = frozenset(display_path(c.path) for c in comp.closure()[1:])
        per_input.append((display_path(comp.path), included, result.files))
    if has_errors(found):
        return [], found, 1
    files, conflicts = _merge(per_input)
    for c in conflicts:
        print(f"iface-lsp generate: {c}", file=sys.stderr)
    return files, found, 1 if conflicts else 0


def _report(report: WriteReport, args: argparse.Namespace) -> int:
    """Print what happened; the exit code."""
    out = args.out
    if report.errors:
        for e in report.errors:
            print(f"iface-lsp generate: {e}", file=sys.stderr)
        if not report.written:
            print("iface-lsp generate: nothing was written", file=sys.stderr)
        return 2
    if args.check:
        for p in report.differing:
            print(f"differs: {os.path.join(out, p)}")
        if not report.differing and not args.quiet:
            n = len(report.unchanged)
            print(f"ok: {n} file{'' if n == 1 else 's'} up to date"
                  + (f", {len(report.kept)} kept (yours)" if report.kept else ""))
        return 1 if report.differing else 0
    if args.dry_run:
        for p in report.written:
            print(f"would write: {os.path.join(out, p)}")
    elif not args.quiet:
        for p in report.written:
            print(f"wrote {os.path.join(out, p)}", file=sys.stderr)
    for p in report.refused:
        if p in report.links:
            continue
        if p in report.foreign:
            print(f"iface-lsp generate: {os.path.join(out, p)} exists and was not written by iface (it has no "
                  "iface-text-hash stamp); not overwritten (--force overwrites it)", file=sys.stderr)
        else:
            print(f"iface-lsp generate: {os.path.join(out, p)} was edited by hand since it was generated; "
                  "not overwritten (--force overwrites it)", file=sys.stderr)
    print_link_notes(report, out, "iface-lsp generate")
    if not args.quiet and not args.dry_run:
        print(f"{len(report.written)} written, {len(report.unchanged)} unchanged"
              + (f", {len(report.kept)} kept (yours)" if report.kept else "")
              + (f", {len(report.refused)} refused" if report.refused else ""), file=sys.stderr)
    return 1 if report.refused else 0


def run(args: argparse.Namespace) -> int:
    """Generate, then write, list (--dry-run) or compare (--check)."""
    available = targets()
    # the system launch target is iface's own: found even where the installed entry points predate it
    available.setdefault(LAUNCH.name, guarded(LAUNCH))
    target = available.get(args.target)
    if target is None:
        return _fail(f"unknown target '{args.target}'; available: {', '.join(sorted(available)) or 'none'}")
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        return _fail(f"{args.out}: not a folder")
    if args.templates and not os.path.isdir(args.templates):
        return _fail(f"{args.templates}: not a folder")
    notes: list[str] = []
    try:
        files, diags, code = _generate(target, args, notes)
    except UsageError as e:
        return _fail(str(e))
    except GenerationError as e:
        return _fail(str(e))
    shown = [d for d in diags if d.severity == Severity.ERROR or not args.quiet]
    if code:
        print_diagnostics(shown)
        # a target that raised (the guard's internal-error) is a bug, not a finding: exit 3 as any internal error
        return 3 if any(d.code == "internal-error" for d in diags) else code
    print_diagnostics(shown, stream=sys.stderr)
    if not args.quiet:
        for note in notes:
            print(f"iface-lsp generate: {note}", file=sys.stderr)
    try:
        report = write_files(files, args.out, force=args.force, dry_run=args.dry_run, check=args.check)
    except OSError as e:
        return _fail(f"cannot write: {e}")
    return _report(report, args)
