"""``iface-lsp check [--format text|json] FILE...``"""

from __future__ import annotations

import argparse
import sys

from .common import (
    UsageError,
    check_suffix,
    compile_files,
    gather,
    has_errors,
    print_diagnostics,
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE", help=".iface or .thrift files")
    p.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Exit 0 without errors, 1 with errors, 2 on usage or I/O errors."""
    try:
        for f in args.files:
            check_suffix(f)
        comps = compile_files(args.files, args.include_path)
    except UsageError as e:
        print(f"iface-lsp check: {e}", file=sys.stderr)
        return 2
    diags = gather(comps)
    print_diagnostics(diags, args.format)
    return 1 if has_errors(diags) else 0
