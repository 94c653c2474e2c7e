"""What ``import --from node`` and ``verify`` share: opening the graph, and the import itself."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path, PurePosixPath

from ..emit.base import GeneratedFile
from ..importers.output import write_imported
from .common import print_link_notes


def ros_missing_line(prog: str) -> str | None:
    """The one line a command (``prog``: ``iface-lsp verify``) prints when ROS 2 is not sourced, or None when it is."""
    from ..live.graph import ros_missing

    why = ros_missing()
    return f"{prog}: {why}" if why else None


def described_files(name: str, interface_json: str) -> list[GeneratedFile]:
    """The files of a node's Describe answer (the JSON form, with what it includes)."""
    from ..forms.jsonform import from_json
    from ..importers.json import _included_files

    doc = json.loads(interface_json)
    path = f"{name}.iface"
    files = [GeneratedFile(path, from_json(doc))]
    files += [GeneratedFile(p, t) for p, t in _included_files(doc, PurePosixPath(path).parent, "")]
    return files


def system_text(name: str, imported: list[tuple[str, str, str]]) -> str:
    """The system file naming every imported node as an instance: (node, component, file).

    A system names nodes without a namespace: the namespace of a node in one is said in a comment.
    """
    lines = [f"/** The running system, imported from the graph (iface-lsp import --from node --system {name}). */",
             f"system {name}", ""]
    lines += [f'include "{path}"' for _, _, path in sorted(imported, key=lambda x: x[2])]
    lines.append("")
    for node, component, _ in imported:
        base = node.rsplit("/", 1)[-1]
        if node.rsplit("/", 1)[0]:
            lines.append(f"// runs as {node}")
        lines.append(f"instance {component} : {component}" + (f' (node = "{base}")' if base != component else ""))
    return "\n".join(lines) + "\n"


def import_nodes(args: argparse.Namespace) -> int:
    """``iface-lsp import --from node`` (``ros2 iface import``): exit 0 all imported, 1 a node missing or a file
    refused, 2 usage/no ROS 2. Messages start with ``args.prog``."""
    prog = args.prog
    missing_ros = ros_missing_line(prog)
    if missing_ros:
        print(missing_ros, file=sys.stderr)
        return 2
    if not args.inputs and not args.all:
        print(f"{prog}: name the nodes to import (NODE...), or --all", file=sys.stderr)
        return 2
    if args.timeout <= 0:
        print(f"{prog}: --timeout must be more than 0 seconds", file=sys.stderr)
        return 2
    from ..live.graph import open_graph
    from ..live.stdout import native_output_to_stderr
    from ..live.to_iface import component_name, node_iface

    names = [n if n.startswith("/") else "/" + n for n in args.inputs]
    out = args.out or "."
    files: list[GeneratedFile] = []
    instances: list[tuple[str, str, str]] = []
    with native_output_to_stderr(), open_graph(args.timeout) as graph:  # Fast DDS logs to descriptor 1
        if args.all:
            names = sorted(set(names) | set(graph.wait_for_all()))
        absent = graph.wait_for(names)
        present = [n for n in names if n not in absent]
        if present and (args.no_describe or not all(graph.describes(n) for n in present)):
            # read off the graph: wait until the whole graph is quiet, not only until these nodes' endpoints
            # stop changing for a moment (endpoints are discovered one by one, with pauses under load)
            graph.wait_for(present, whole=True)
        for name in absent:
            print(f"{prog}: {name}: no such node on the graph (waited {args.timeout:g} s)", file=sys.stderr)
        snaps = graph.read_nodes([n for n in names if n not in absent], describe=not args.no_describe)
        for name, snap in snaps.items():
            if snap.describe_json:
                try:
                    got = described_files(component_name(name), snap.describe_json)
                except (ValueError, RecursionError) as e:  # FormError and PrintError are ValueErrors
                    snap.notes.append(f"its Describe answer is not the iface JSON form ({e}): read from the graph")
                else:
                    files += got
                    instances.append((name, component_name(name), got[0].path))
                    continue
            imported = node_iface(snap, everything=args.all_endpoints)
            files.append(GeneratedFile(imported.path, imported.text))
            instances.append((name, imported.component, imported.path))
    seen: set[str] = set()
    for f in files:
        if f.path in seen:
            print(f"{prog}: two nodes would both be written to {f.path}; import them one at a time",
                  file=sys.stderr)
            return 2
        seen.add(f.path)
    if args.system:
        files.append(GeneratedFile(f"{args.system}.iface", system_text(args.system, instances)))
    report = write_imported(files, out, force=args.force)
    for line in report.errors:
        print(f"{prog}: {line}", file=sys.stderr)
    for path in report.refused:
        if path not in report.links:
            print(f"{prog}: {Path(out) / path}: exists with other content; not overwritten (use --force)",
                  file=sys.stderr)
    print_link_notes(report, out, prog)
    if not args.quiet:
        for path in report.written:
            print(f"wrote {Path(out) / path}")
        for path in report.unchanged:
            print(f"unchanged {Path(out) / path}")
    if report.errors:
        return 2
    return 1 if absent or report.refused else 0
