"""``iface-lsp handover OLD_NODE NEW_NODE --old OLD.iface --new NEW.iface [--system FILES...] [--timeout S]
[--trust-store DIR --new-package DIR]``: replace a running component by another (docs/runtime.md)."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..compat.report import render_text
from ..live.stdout import native_output_to_stderr
from .common import UsageError, display_path
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("old_node", metavar="OLD_NODE", help="the running node to replace (e.g. /counter)")
    p.add_argument("new_node", metavar="NEW_NODE", help="the node that takes over, started and not active")
    p.add_argument("--old", required=True, metavar="OLD.iface", help="the interface of OLD_NODE")
    p.add_argument("--new", required=True, metavar="NEW.iface", help="the interface of NEW_NODE")
    p.add_argument("--system", nargs="+", default=None, metavar="FILE",
                   help="the other components of the system: decides whether changed elements are used")
    p.add_argument("--timeout", type=float, default=10.0, metavar="S",
                   help="how long each node may take to answer, and NEW's publishers to be matched as OLD's are "
                        "(default 10 s)")
    p.add_argument("--trust-store", type=Path, metavar="DIR",
                   help="a folder of trusted public keys (*.pub): NEW's package must be signed by one of them")
    p.add_argument("--new-package", type=Path, metavar="DIR",
                   help="the folder of NEW's component package whose signature is checked")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def run(args: argparse.Namespace) -> int:
    """Exit 0 when NEW took over, 1 when the hand-over was refused (OLD untouched), 2 on a usage error."""
    with native_output_to_stderr():  # Fast DDS logs to descriptor 1 (live/stdout.py)
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    if args.timeout <= 0:
        print("iface-lsp handover: --timeout must be more than 0", file=sys.stderr)
        return 2
    try:
        import rclpy  # noqa: F401
    except ImportError as e:
        print(f"iface-lsp handover: rclpy cannot be imported ({e}); source your ROS 2 setup first", file=sys.stderr)
        return 2
    try:
        old, new = load_checked([args.old, args.new], args.include_path)
        system = load_checked(args.system, args.include_path) if args.system is not None else None
    except UsageError as e:
        print(f"iface-lsp handover: {e}", file=sys.stderr)
        return 2
    from ..operate.handover import HandOver, decide

    report = decide(old, new, system)
    h = HandOver(args.old_node, args.new_node, report.new_hash, args.timeout, args.trust_store, args.new_package)
    if not h.check_compat(report, display_path(args.new), display_path(args.old)):
        sys.stderr.write(render_text(report, display_path))
        print(json.dumps(h.record(report), indent=1))
        return 1
    done = h.run()
    print(json.dumps(h.record(report), indent=1))
    if not done:
        print(f"iface-lsp handover: refused: {h.steps[-1].detail}" if h.steps else "iface-lsp handover: refused",
              file=sys.stderr)
    return 0 if done else 1
