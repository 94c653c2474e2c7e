"""``iface-lsp impact --system FILES... --replace OLD NEW [--format text|json]``"""

from __future__ import annotations

import argparse
import sys

from ..compat.impact import impact, render_json, render_text
from .common import UsageError, display_path
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("--system", nargs="+", required=True, metavar="FILE", help="the components of the system")
    p.add_argument("--replace", nargs=2, required=True, metavar=("OLD", "NEW"),
                   help="the component to replace and its replacement")
    p.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Exit 0 when nothing breaks, 1 when the replacement breaks the system, 2 on a tool error."""
    try:
        old, new = load_checked(args.replace, args.include_path, "impact")
        system = load_checked(args.system, args.include_path, "impact")
    except UsageError as e:
        print(f"iface-lsp impact: {e}", file=sys.stderr)
        return 2
    result = impact(system, old, new)
    sys.stdout.write(render_json(result, display_path) if args.format == "json" else render_text(result, display_path))
    return 1 if result.breaks else 0
