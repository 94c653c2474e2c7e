"""``iface-lsp compat OLD NEW [--system FILES...] [--format text|json|sarif|html]``"""

from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..compat import compare
from ..compat.html import render_html
from ..compat.report import render_json, render_sarif, render_text
from .common import UsageError, display_path
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("old", metavar="OLD", help="the interface of the running component")
    p.add_argument("new", metavar="NEW", help="the interface of the replacement")
    p.add_argument("--system", nargs="+", default=None, metavar="FILE",
                   help="the other components of the system: decides whether changed elements are used")
    p.add_argument("--format", choices=("text", "json", "sarif", "html"), default="text", help="output format")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Exit 0 for equivalent and replaceable, 1 for incompatible (and replaceable-if-unused without
    --system), 2 on a tool error."""
    try:
        old, new = load_checked([args.old, args.new], args.include_path)
        system = load_checked(args.system, args.include_path) if args.system is not None else None
    except UsageError as e:
        print(f"iface-lsp compat: {e}", file=sys.stderr)
        return 2
    report = compare(old, new, system)
    if args.format == "json":
        sys.stdout.write(render_json(report, display_path))
    elif args.format == "sarif":
        sys.stdout.write(render_sarif(report, display_path, __version__))
    elif args.format == "html":
        sys.stdout.write(render_html(report, display_path, __version__))
    else:
        sys.stdout.write(render_text(report, display_path))
    return report.exit_code
