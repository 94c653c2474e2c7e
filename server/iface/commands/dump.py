"""``iface-lsp dump FILE``: the model of a file as JSON (used for golden model files)."""

from __future__ import annotations

import argparse
import json
import sys

from ..forms.dump import dump_interface
from .common import UsageError, compile_files


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("file", metavar="FILE", help="an .iface or .thrift file")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR")


def run(args: argparse.Namespace) -> int:
    """Print the model; exit 1 when the file has errors (the model is printed anyway)."""
    try:
        (comp,) = compile_files([args.file], args.include_path)
    except UsageError as e:
        print(f"iface-lsp dump: {e}", file=sys.stderr)
        return 2
    json.dump(dump_interface(comp.interface), sys.stdout, indent=2, ensure_ascii=False)
    sys.stdout.write("\n")
    return 1 if comp.has_errors else 0
