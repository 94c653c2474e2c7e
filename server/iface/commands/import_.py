"""``iface-lsp import --from ros2|px4|json INPUT... --out DIR [--force] [-q]``, and
``iface-lsp import --from node NODE... [--out DIR] [--all] [--all-endpoints] [--system NAME] [--no-describe]
[--timeout S]``"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..importers import InputError, Problem, get_importer, importers
from ..importers.output import write_imported
from ..model.diagnostics import Diagnostic, Severity
from .common import compile_readable, gather, print_diagnostics, print_link_notes


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("inputs", nargs="*", metavar="INPUT",
                   help="ROS 2 package folders or .msg/.srv/.action/.idl files (ros2), a folder of uORB .msg "
                        "files (px4), JSON files (json), or running nodes (node: /name or /ns/name)")
    p.add_argument("--from", dest="source", required=True, metavar="FORMAT",
                   help="what to import: " + ", ".join(sorted([*importers(), "node"])))
    add_node_arguments(p, "node: ")
    p.add_argument("--deps", metavar="DIR",
                   help="ros2: a folder of ROS 2 packages; the packages the inputs use that are found there are "
                        "imported too, each into its own .iface, with includes between them")
    add_output_arguments(p)


def add_node_arguments(p: argparse.ArgumentParser, mark: str = "") -> list[argparse.Action]:
    """The options of ``--from node`` (``mark`` starts their help: ``node: ``); the actions of --out and --timeout."""
    out = p.add_argument("--out", metavar="DIR", help=f"the folder to write the .iface files to ({mark}default .)")
    p.add_argument("--all", action="store_true", help=f"{mark}import every node on the graph")
    p.add_argument("--all-endpoints", action="store_true",
                   help=f"{mark}keep ROS 2's own endpoints and parameters (parameter services, /rosout, lifecycle's)")
    p.add_argument("--system", metavar="NAME", help=f"{mark}also write the system file NAME.iface naming every node")
    p.add_argument("--no-describe", action="store_true",
                   help=f"{mark}read every node off the graph, also one that answers iface's Describe")
    timeout = p.add_argument("--timeout", type=float, default=5.0, metavar="S",
                             help=f"{mark}seconds to wait for discovery and for each answer (default 5)")
    return [out, timeout]


def add_output_arguments(p: argparse.ArgumentParser) -> None:
    """--force and -q, which every source shares."""
    p.add_argument("--force", action="store_true", help="overwrite existing files whose content differs")
    p.add_argument("-q", "--quiet", action="store_true", help="print problems only, not the files written")


def print_problems(problems: list[Problem], stream=None) -> None:
    """One ``file:line: message`` line per problem."""
    stream = stream or sys.stderr
    for p in problems:
        stream.write(p.format(p.path) + "\n")


def run(args: argparse.Namespace) -> int:
    """Exit 0 when everything imported; 1 when an input had errors or an existing file was refused
    (as ``generate`` does); 2 on usage or I/O errors."""
    if args.source == "node":
        from .live import import_nodes
        return import_nodes(args)
    if args.all or args.all_endpoints or args.system or args.no_describe:
        print("iface-lsp import: --all, --all-endpoints, --system and --no-describe apply to --from node only",
              file=sys.stderr)
        return 2
    if not args.inputs or not args.out:
        print(f"iface-lsp import: --from {args.source} needs INPUT... and --out DIR", file=sys.stderr)
        return 2
    importer = get_importer(args.source)
    if importer is None:
        print(f"iface-lsp import: unknown format '{args.source}'; known: {', '.join(sorted(importers()))}",
              file=sys.stderr)
        return 2
    try:
        if args.deps and args.source != "ros2":
            print("iface-lsp import: --deps applies to --from ros2 only", file=sys.stderr)
            return 2
        result = importer.run(list(args.inputs), {"deps": args.deps} if args.deps else {})
    except InputError as e:
        print(f"iface-lsp import: {e}", file=sys.stderr)
        return 2
    print_problems(result.problems)
    report = write_imported(result.files, args.out, force=args.force)
    for line in report.errors:
        print(f"iface-lsp import: {line}", file=sys.stderr)
    for path in report.refused:
        if path not in report.links:
            print(f"iface-lsp import: {Path(args.out) / path}: exists with other content; not overwritten "
                  "(use --force)", file=sys.stderr)
    print_link_notes(report, args.out, "iface-lsp import")
    if not args.quiet:
        for path in report.written:
            print(f"wrote {Path(args.out) / path}")
        for path in report.unchanged:
            print(f"unchanged {Path(args.out) / path}")
    if report.errors:
        return 2
    invalid = errors_of(args.out, [*report.written, *report.unchanged])
    if invalid:
        print("iface-lsp import: what was written does not pass `check`:", file=sys.stderr)
        print_diagnostics(invalid, stream=sys.stderr)
    return 1 if result.has_errors or report.refused or invalid else 0


def errors_of(out: str, written: list[str]) -> list[Diagnostic]:
    """The errors ``check`` finds in the ``.iface`` files just written to ``out``: an import never reports
    success for a file ``check`` refuses (a JSON form edited by hand can hold a definition twice)."""
    comps, _ = compile_readable([str(Path(out) / p) for p in written if p.endswith(".iface")])
    return [d for d in gather(comps) if d.severity == Severity.ERROR]
