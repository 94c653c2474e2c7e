"""``iface-lsp verify FILES_OR_SYSTEM [--format text|json|sarif] [--timeout S]``"""

from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..live.stdout import native_output_to_stderr
from ..semantics.compile import Compilation
from .common import UsageError, check_suffix, compile_files, display_path, gather, print_diagnostics
from .live import ros_missing_line


def add_arguments(p: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    """Declare the command's arguments; their actions by name (``ros2 iface verify`` sets completers on them)."""
    files = p.add_argument("files", nargs="+", metavar="FILE_OR_SYSTEM",
                           help="the .iface files of the running nodes (each names its node: ros2.node, else "
                                "/<component>), or a system file (one node per instance)")
    p.add_argument("--format", choices=("text", "json", "sarif"), default="text", help="output format")
    timeout = p.add_argument("--timeout", type=float, default=5.0, metavar="S",
                             help="seconds to wait for discovery and for each answer (default 5)")
    include = p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                             help="a folder to search for included files")
    return {"files": files, "timeout": timeout, "include_path": include}


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every node conforms, 1 on findings (warnings included), 2 on usage, I/O or no ROS 2; messages
    start with ``args.prog`` (``iface-lsp verify``, ``ros2 iface verify``)."""
    with native_output_to_stderr():  # Fast DDS logs to descriptor 1 (live/stdout.py)
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    if args.timeout <= 0:
        print(f"{args.prog}: --timeout must be more than 0 seconds", file=sys.stderr)
        return 2
    try:
        comps = _load(args.files, args.include_path)
    except UsageError as e:
        print(f"{args.prog}: {e}", file=sys.stderr)
        return 2
    missing_ros = ros_missing_line(args.prog)
    if missing_ros:
        print(missing_ros, file=sys.stderr)
        return 2
    from ..live.graph import open_graph
    from ..live.report import render_json, render_sarif, render_text
    from ..live.verify import declared_all, read_live, verify

    decls = declared_all(comps)
    if not decls:
        print(f"{args.prog}: no component or system in the given files (a node is declared by a `component` "
              "or an `instance`)", file=sys.stderr)
        return 2
    with open_graph(args.timeout) as graph:
        live = read_live(graph, decls)
    findings = verify(decls, live)
    if args.format == "json":
        sys.stdout.write(render_json(findings, display_path, len(decls)))
    elif args.format == "sarif":
        sys.stdout.write(render_sarif(findings, display_path, __version__))
    else:
        sys.stdout.write(render_text(findings, display_path, len(decls)))
    return 1 if findings else 0


def _load(paths: list[str], include_paths: list[str]) -> list[Compilation]:
    """Compile the files; errors stop verify, except the conflicts of a system's declared graph (``graph-*``):
    those are what verify looks for in the running one."""
    for p in paths:
        check_suffix(p)
    comps = compile_files(paths, include_paths)
    errors = [d for d in gather(comps) if d.severity.label == "error" and not d.code.startswith("graph-")]
    if errors:
        print_diagnostics(errors, "text", sys.stderr)
        raise UsageError(f"{len(errors)} error{'s' if len(errors) != 1 else ''} in the input: fix "
                         f"{'it' if len(errors) == 1 else 'them'} before running verify")
    return comps
