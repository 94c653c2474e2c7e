"""``iface-lsp graph FILES... [--format dot|mermaid|json|svg] [--layout auto|dot|builtin]``

The files are the components of a system, or one system file: then each instance is a node of the graph.
"""

from __future__ import annotations

import argparse
import sys

from ..compat.graph import build, render_dot, render_json, render_mermaid
from ..compat.systemfile import is_system, system_graph
from ..compat.svg import LAYOUTS, LayoutUnavailable, render_svg
from .common import UsageError, display_path
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE",
                   help="the components of the system, or one system file (its instances)")
    p.add_argument("--format", choices=("dot", "mermaid", "json", "svg"), default="dot", help="output format")
    p.add_argument("--layout", choices=LAYOUTS, default="auto",
                   help="how --format svg lays the graph out: Graphviz's dot, the built-in layout, or "
                        "auto (dot where it is installed, else built-in)")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Print the graph (checks go to stderr, or into the JSON); exit 1 when a check is an error."""
    try:
        comps = load_checked(args.files, args.include_path, "graph")
    except UsageError as e:
        print(f"iface-lsp graph: {e}", file=sys.stderr)
        return 2
    if args.layout != "auto" and args.format != "svg":
        print("iface-lsp graph: --layout applies to --format svg only", file=sys.stderr)
        return 2
    systems = [c for c in comps if is_system(c)]
    if systems and len(comps) > 1:
        print(f"iface-lsp graph: {display_path(systems[0].path)} is a system file: give it alone "
              "(its instances are the graph)", file=sys.stderr)
        return 2
    g = system_graph(systems[0]) if systems else build(comps)
    if args.format == "json":
        sys.stdout.write(render_json(g, display_path))
    else:
        if args.format == "svg":
            try:
                text = render_svg(g, display_path, args.layout)
            except LayoutUnavailable as e:
                print(f"iface-lsp graph: {e}", file=sys.stderr)
                return 2
        else:
            text = render_dot(g) if args.format == "dot" else render_mermaid(g)
        sys.stdout.write(text)
        for d in g.checks:
            print(d.format(display_path(d.path)), file=sys.stderr)
    return 1 if g.has_errors else 0
