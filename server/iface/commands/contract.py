"""``iface-lsp contract FILE [--format text|json]``"""

from __future__ import annotations

import argparse
import sys

from ..compat.contract import contract, render_contract
from .common import UsageError
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("file", metavar="FILE", help="an .iface or .thrift file")
    p.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Print the assumptions and guarantees; exit 2 on a tool error."""
    try:
        (comp,) = load_checked([args.file], args.include_path, "contract")
    except UsageError as e:
        print(f"iface-lsp contract: {e}", file=sys.stderr)
        return 2
    sys.stdout.write(render_contract(contract(comp), args.format))
    return 0
