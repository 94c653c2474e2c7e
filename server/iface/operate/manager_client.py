"""Calls to a running component manager (``/iface_manager``) from the command line's ``system`` clients."""

from __future__ import annotations

import json
import threading
import time
from typing import Any

from .link import Link, LinkError
from .manager import REPLACE_SERVICE, SNAPSHOT_SERVICE, STATUS_SERVICE


class NoManager(Exception):
    """No manager answers; the message says what was tried."""


class ManagerClient:
    """A short-lived rclpy node that calls the manager's services."""

    def __init__(self, timeout: float) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.timeout = timeout
        self._rclpy = rclpy
        self._own = not rclpy.ok()
        if self._own:
            rclpy.init()
        self.node = rclpy.create_node(f"iface_system_{int(time.monotonic() * 1000) % 1000000}")
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.link = Link(self.node)

    def close(self) -> None:
        """Destroy the node (and the context it made)."""
        self.executor.shutdown(timeout_sec=1.0)
        self.node.destroy_node()
        if self._own:
            self._rclpy.try_shutdown()

    def _call(self, service: str, fill: dict[str, Any], timeout: float) -> Any:
        from iface_msgs import srv

        kind = {STATUS_SERVICE: srv.SystemStatus, SNAPSHOT_SERVICE: srv.Snapshot, REPLACE_SERVICE: srv.Replace}
        self.link.know(service, kind[service])
        answer: list[Any] = []
        problem: list[str] = []

        def call() -> None:
            try:
                answer.append(self.link.call(service, fill, timeout, idempotent=service != REPLACE_SERVICE))
            except LinkError as e:
                problem.append(str(e))

        worker = threading.Thread(target=call, daemon=True)
        worker.start()
        while worker.is_alive():
            self.executor.spin_once(timeout_sec=0.05)
        if problem:
            raise NoManager(f"no component manager answers: {problem[0]}")
        return answer[0]

    def status(self) -> Any:
        """``/iface_manager/status``."""
        return self._call(STATUS_SERVICE, {}, self.timeout)

    def snapshot(self, instance: str = "") -> Any:
        """``/iface_manager/snapshot``."""
        return self._call(SNAPSHOT_SERVICE, {"instance": instance}, self.timeout)

    def replace(self, instance: str, new_iface: str, package: str, timeout: float) -> dict[str, Any]:
        """``/iface_manager/replace``: the hand-over record."""
        answer = self._call(REPLACE_SERVICE, {"instance": instance, "new_iface": new_iface, "package": package,
                                               "timeout_sec": timeout}, 8 * timeout + 60)
        record: dict[str, Any] = json.loads(answer.record)
        return record


def status_data(answer: Any) -> dict[str, Any]:
    """A SystemStatus response as the ``--format json`` form."""
    instances: list[dict[str, Any]] = []
    findings: list[dict[str, str]] = []
    for i in answer.instances:
        instances.append({"name": i.name, "node": i.node, "state": i.state, "pid": int(i.pid),
                          "restarts": int(i.restarts), "interface_hash": i.interface_hash,
                          "last_snapshot": i.last_snapshot or None,
                          "container": getattr(i, "container", "") or None})
        findings.extend({"instance": i.name, "message": f} for f in i.findings)
    return {"system": answer.system, "instances": instances, "findings": findings}
