"""Call one ROS 2 service as ``ros2 service call`` does, where that command cannot run (run in a ROS 2 environment).

    python call_service.py SERVICE TYPE [REQUEST_YAML] [--timeout S]

The runtime's ``ros2 service call`` is Kilted's ros2service, which writes ``with rclpy.init():``, a
context manager Jazzy's rclpy 7.1 does not have (../shared/ros2-runtime/README.md, Jazzy); on Jazzy
the tests call through this script instead. It prints the response after ``response:`` as ``ros2 service
call`` does (the message's repr), and exits 1 when the service does not answer within the timeout.
"""

from __future__ import annotations

import argparse
import importlib
import sys

import rclpy
import yaml
from rosidl_runtime_py import set_message_fields


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("service")
    ap.add_argument("type", help="e.g. thermostat_msgs/srv/SetPoint")
    ap.add_argument("request", nargs="?", default="{}")
    ap.add_argument("--timeout", type=float, default=20.0)
    a = ap.parse_args()
    package, kind, name = a.type.split("/")
    srv = getattr(importlib.import_module(f"{package}.{kind}"), name)
    request = srv.Request()
    set_message_fields(request, yaml.safe_load(a.request) or {})
    rclpy.init()
    node = rclpy.create_node("call_service")
    try:
        client = node.create_client(srv, a.service)
        if not client.wait_for_service(timeout_sec=a.timeout):
            print(f"{a.service}: no such service within {a.timeout:g} s", file=sys.stderr)
            return 1
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future, timeout_sec=a.timeout)
        if future.result() is None:
            print(f"{a.service}: no answer within {a.timeout:g} s", file=sys.stderr)
            return 1
        print("response:")
        print(repr(future.result()))
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
