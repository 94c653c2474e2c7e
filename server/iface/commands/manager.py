"""``iface-lsp manager SYSTEM [--state-dir DIR] [--trust-store DIR]``: run the component manager of a system
(ROS 2 sourced; docs/system.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..operate.restart import DEFAULT_MAX_RESTARTS, DEFAULT_PERIOD
from ..operate.snapshots import DEFAULT_KEEP


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("system", metavar="SYSTEM", help="the system file (system NAME, instance …)")
    p.add_argument("--state-dir", type=Path, metavar="DIR",
                   help="where snapshots, process records and instance logs go "
                        "(default: .iface-state/<system> beside the system file)")
    p.add_argument("--trust-store", type=Path, metavar="DIR",
                   help="a folder of trusted public keys (*.pub): a replacement, and an instance loaded into a container, "
                        "must be signed by one of them")
    p.add_argument("--max-restarts", type=int, default=DEFAULT_MAX_RESTARTS, metavar="R",
                   help=f"restarts of one instance allowed within --restart-period (default {DEFAULT_MAX_RESTARTS})")
    p.add_argument("--restart-period", type=float, default=DEFAULT_PERIOD, metavar="T",
                   help=f"seconds of the restart limit's window (default {DEFAULT_PERIOD:g})")
    p.add_argument("--heartbeat-timeout", type=float, default=5.0, metavar="S",
                   help="an instance silent this long is failed (default 5)")
    p.add_argument("--grace", type=float, default=3.0, metavar="S",
                   help="how long a replacement must stay up and active before OLD is let go (default 3)")
    p.add_argument("--keep", type=int, default=DEFAULT_KEEP, metavar="N",
                   help=f"snapshots kept per instance (default {DEFAULT_KEEP})")


def run(args: argparse.Namespace) -> int:
    """Exit 0 after a clean shutdown (SIGINT/SIGTERM), 2 on a usage error or without ROS 2."""
    from ..nodes.system import SystemFileError, system_spec

    for name, value in (("--max-restarts", args.max_restarts), ("--keep", args.keep)):
        if value < 1:
            print(f"iface-lsp manager: {name} must be at least 1", file=sys.stderr)
            return 2
    for name, value in (("--restart-period", args.restart_period), ("--heartbeat-timeout", args.heartbeat_timeout),
                        ("--grace", args.grace)):
        if value <= 0:
            print(f"iface-lsp manager: {name} must be more than 0", file=sys.stderr)
            return 2
    try:
        spec = system_spec(args.system)
    except SystemFileError as e:
        print(f"iface-lsp manager: {e}", file=sys.stderr)
        return 2
    try:
        import iface_msgs.srv  # noqa: F401
        import rclpy  # noqa: F401
    except ImportError as e:
        print(f"iface-lsp manager: ROS 2 or iface_msgs cannot be imported ({e}); source your ROS 2 setup and the "
              "workspace with the system's packages first", file=sys.stderr)
        return 2
    from ..operate.manager import Options
    from ..operate.manager import run as run_manager

    state_dir = args.state_dir or spec.file.parent / ".iface-state" / spec.name
    try:
        state_dir.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        print(f"iface-lsp manager: {state_dir}: cannot create the state folder ({e.strerror})", file=sys.stderr)
        return 2
    options = Options(state_dir=state_dir.resolve(), trust_store=args.trust_store, max_restarts=args.max_restarts,
                      restart_period=args.restart_period, heartbeat_timeout=args.heartbeat_timeout,
                      grace=args.grace, keep=args.keep)
    return run_manager(spec, options)
