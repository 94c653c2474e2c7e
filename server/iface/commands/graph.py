"""``iface-lsp graph FILES... [--format dot|mermaid|json]``"""

from __future__ import annotations

import argparse
import sys

from ..compat.graph import build, render_dot, render_json, render_mermaid
from .common import UsageError, display_path
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE", help="the components of the system")
    p.add_argument("--format", choices=("dot", "mermaid", "json"), default="dot", help="output format")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Print the graph (checks go to stderr, or into the JSON); exit 1 when a check is an error."""
    try:
        comps = load_checked(args.files, args.include_path, "graph")
    except UsageError as e:
        print(f"iface-lsp graph: {e}", file=sys.stderr)
        return 2
    g = build(comps)
    if args.format == "json":
        sys.stdout.write(render_json(g, display_path))
    else:
        sys.stdout.write(render_dot(g) if args.format == "dot" else render_mermaid(g))
        for d in g.checks:
            print(d.format(display_path(d.path)), file=sys.stderr)
    return 1 if g.has_errors else 0
