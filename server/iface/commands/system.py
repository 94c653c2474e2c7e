"""``iface-lsp system status|replace|snapshot SYSTEM …``: clients of a running component manager (docs/system.md).

- ``system status SYSTEM [--format text|json|html]``: each instance's node, component, state, pid,
  restarts, interface hash, last snapshot and container, each container's instances, and the findings; exit 0
  when every instance is active, else 1.
- ``system replace SYSTEM INSTANCE --new NEW.iface --package DIR [--timeout S]``: one JSON record as
  ``handover`` prints; exit 0 replaced, 1 refused or rolled back.
- ``system snapshot SYSTEM [INSTANCE]``: save now; exit 0 when every chosen instance was saved, else 1.

Exit 2: a usage error, a system file with errors, no ROS 2, or no manager of SYSTEM answering.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

from ..live.stdout import native_output_to_stderr
from .common import display_path


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    sub = p.add_subparsers(dest="action", metavar="ACTION", required=True)
    add_status_arguments(sub.add_parser("status", help="the status of every instance"))
    add_replace_arguments(sub.add_parser("replace", help="replace an instance by a new package and interface"))
    add_snapshot_arguments(sub.add_parser("snapshot", help="save the state of the running instances now"))


def add_status_arguments(p: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    """``status SYSTEM [--format text|json|html]``; the actions by name, for completers."""
    found = {"system": p.add_argument("system", metavar="SYSTEM", help="the system file")}
    p.add_argument("--format", choices=("text", "json", "html"), default="text")
    found["manager_timeout"] = _manager_timeout(p)
    return found


def add_replace_arguments(p: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    """``replace SYSTEM INSTANCE --new NEW.iface --package DIR [--timeout S]``; the actions by name."""
    found = {"system": p.add_argument("system", metavar="SYSTEM", help="the system file"),
             "instance": p.add_argument("instance", metavar="INSTANCE", help="the instance to replace"),
             "new": p.add_argument("--new", required=True, metavar="NEW.iface",
                                   help="the interface of the replacement"),
             "package": p.add_argument("--package", required=True, type=Path, metavar="DIR",
                                       help="the replacement's install folder (ws/install/<package>)")}
    p.add_argument("--timeout", type=float, default=10.0, metavar="S",
                   help="how long each node may take to answer, and NEW's publishers to be matched as OLD's are "
                        "(default 10 s)")
    found["manager_timeout"] = _manager_timeout(p)
    return found


def add_snapshot_arguments(p: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    """``snapshot SYSTEM [INSTANCE]``; the actions by name."""
    found = {"system": p.add_argument("system", metavar="SYSTEM", help="the system file"),
             "instance": p.add_argument("instance", metavar="INSTANCE", nargs="?", default="",
                                        help="only this instance")}
    found["manager_timeout"] = _manager_timeout(p)
    return found


def _manager_timeout(p: argparse.ArgumentParser) -> argparse.Action:
    return p.add_argument("--manager-timeout", type=float, default=10.0, metavar="S",
                          help="how long to wait for the manager to answer (default 10 s)")


def run(args: argparse.Namespace) -> int:
    """See the module's docstring for the exit codes; messages start with ``args.prog`` (``iface-lsp system``,
    ``ros2 iface status``)."""
    with native_output_to_stderr():  # Fast DDS logs to descriptor 1 (live/stdout.py)
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    from ..nodes.system import SystemFileError, system_spec

    def _fail(message: str) -> int:
        print(f"{args.prog}: {message}", file=sys.stderr)
        return 2

    if args.action == "replace":
        if args.timeout <= 0:
            return _fail("--timeout must be more than 0")
        problem = None if os.path.isfile(args.new) else f"{args.new}: no such file"
        problem = problem or (None if args.package.is_dir() else f"{args.package}: no such folder")
        if problem:
            return _fail(problem)
    if args.manager_timeout <= 0:
        return _fail("--manager-timeout must be more than 0")
    try:
        spec = system_spec(args.system)
    except SystemFileError as e:
        return _fail(str(e))
    try:
        import iface_msgs.srv  # noqa: F401
        import rclpy  # noqa: F401
    except ImportError as e:
        return _fail(f"ROS 2 or iface_msgs cannot be imported ({e}): source your ROS 2 setup first")
    from ..operate.manager_client import ManagerClient, NoManager, status_data

    client = ManagerClient(args.manager_timeout)
    try:
        answer = client.status()
        if answer.system != spec.name:
            return _fail(f"the running manager manages {answer.system}, not {spec.name}")
        if args.action == "status":
            return _status(spec, status_data(answer), args.format)
        if args.action == "snapshot":
            done = client.snapshot(args.instance)
            print(json.dumps({"success": bool(done.success), "message": done.message, "files": list(done.files)},
                             indent=1))
            return 0 if done.success else 1
        if spec.instance(args.instance) is None:
            return _fail(f"{display_path(args.system)}: no instance {args.instance}")
        record = client.replace(args.instance, str(Path(args.new).resolve()), str(args.package.resolve()),
                                args.timeout)
        print(json.dumps(record, indent=1))
        return 0 if record.get("result") == "replaced" else 1
    except NoManager as e:
        return _fail(f"{e} (is `iface-lsp manager {display_path(args.system)}` running in this ROS domain?)")
    finally:
        client.close()


def containers(instances: list[dict[str, Any]]) -> dict[str, list[dict[str, Any]]]:
    """The instances of each container (by its current name), containers in the order of their first instance."""
    out: dict[str, list[dict[str, Any]]] = {}
    for i in instances:
        if i.get("container"):
            out.setdefault(i["container"], []).append(i)
    return out


def _status(spec: Any, data: dict[str, Any], fmt: str) -> int:
    data = {"instances": data["instances"], "findings": data["findings"]}
    code = 0 if all(i["state"] == "active" for i in data["instances"]) else 1
    if fmt == "json":
        print(json.dumps(data, indent=1))
    elif fmt == "html":
        from ..operate.status_html import render

        sys.stdout.write(render(spec, data))
    else:
        print(f"{spec.name}: {sum(i['state'] == 'active' for i in data['instances'])} of "
              f"{len(data['instances'])} instances active")
        for i in data["instances"]:
            box = i.get("container")
            print(f"  {i['name']:<16} {i['state']:<9} {i['node']:<24} pid {i['pid']:<7} restarts {i['restarts']}  "
                  f"{i['component']} {i['interface_hash'][:19]}  last snapshot {i['last_snapshot'] or '-'}"
                  + (f"  in container {box}" if box else ""))
        for box, members in containers(data["instances"]).items():
            pids = sorted({m["pid"] for m in members if m["pid"]})
            print(f"container {box}: {', '.join(m['name'] for m in members)}; "
                  + (f"pid {', '.join(str(p) for p in pids)}" if pids else "not running"))
        for f in data["findings"]:
            print(f"{f['instance']}: {f['message']}")
    return code
