"""QoS probe for test_rclpy_qos.py, run with the ROS 2 runtime's Python in the workspace's environment.

``qosdrive.py wire NODE ENDPOINT...``: waits (bounded) until NODE's endpoints are discovered and prints,
as JSON, the QoS each one announces on the wire (what ``ros2 topic info --verbose`` shows). An
ENDPOINT is ``pub:NAME`` or ``sub:NAME``; a NAME without a leading ``/`` is a raw DDS topic (``rq/…``).

``qosdrive.py entities PACKAGE CLASS``: creates the node in this process, configures it and prints the
QoS of the entities it created: history and depth, which DDS discovery does not carry.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from typing import Any

import rclpy
from rclpy.node import Node

WAIT_SEC = 30.0


def _policies(q: Any) -> dict[str, Any]:
    return {"reliability": q.reliability.name.lower(), "durability": q.durability.name.lower(),
            "history": q.history.name.lower(), "depth": q.depth, "deadline": q.deadline.nanoseconds,
            "lifespan": q.lifespan.nanoseconds, "liveliness": q.liveliness.name.lower(),
            "liveliness_lease_duration": q.liveliness_lease_duration.nanoseconds}


def wire(node_name: str, endpoints: list[str]) -> dict[str, Any]:
    """The announced QoS of each of ``node_name``'s endpoints (missing ones are left out)."""
    reader = Node("qos_reader")
    found: dict[str, Any] = {}
    end = time.monotonic() + WAIT_SEC
    while time.monotonic() < end and len(found) < len(endpoints):
        rclpy.spin_once(reader, timeout_sec=0.2)
        for endpoint in endpoints:
            kind, _, name = endpoint.partition(":")
            infos = (reader.get_publishers_info_by_topic if kind == "pub" else
                     reader.get_subscriptions_info_by_topic)(name, no_mangle=not name.startswith("/"))
            mine = [i for i in infos if i.node_name == node_name]
            if mine:
                found[endpoint] = _policies(mine[0].qos_profile)
    reader.destroy_node()
    return found


def entities(package: str, class_name: str) -> dict[str, Any]:
    """History and depth of the publishers, subscriptions and services the configured node created."""
    cls = getattr(importlib.import_module(f"{package}.node"), class_name)
    node = cls()
    try:
        node.trigger_configure()
        out: dict[str, Any] = {}
        for kind, items in (("pub", node.publishers), ("sub", node.subscriptions), ("srv", node.services)):
            for item in items:
                name = getattr(item, "topic_name", None) or getattr(item, "srv_name", "")
                q = item.qos_profile
                out[f"{kind}:{name}"] = {"history": q.history.name.lower(), "depth": q.depth}
        return out
    finally:
        node.destroy_node()


def main(argv: list[str]) -> int:
    rclpy.init()
    try:
        if argv[0] == "wire":
            result = wire(argv[1], argv[2:])
        else:
            result = entities(argv[1], argv[2])
    finally:
        rclpy.try_shutdown()
    print(json.dumps(result, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
