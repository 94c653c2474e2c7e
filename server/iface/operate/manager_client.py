"""Calls to a running component manager (``/iface_manager``) from the command line's ``system`` clients."""

from __future__ import annotations

import json
from typing import Any

from ..live.link import Link, LinkError
from .manager import REPLACE_SERVICE, SNAPSHOT_SERVICE, STATUS_SERVICE


class NoManager(Exception):
    """No manager answers; the message says what was tried."""


class ManagerClient:
    """A short-lived rclpy node that calls the manager's services (through the one client, ``live.link``)."""

    def __init__(self, timeout: float) -> None:
        from iface_msgs import srv

        self.timeout = timeout
        self.link = Link.own(Link.unique("iface_system"))
        for service, kind in ((STATUS_SERVICE, srv.SystemStatus), (SNAPSHOT_SERVICE, srv.Snapshot),
                              (REPLACE_SERVICE, srv.Replace)):
            self.link.know(service, kind)

    def close(self) -> None:
        """Destroy the node (and the context it made)."""
        self.link.close()

    def _call(self, service: str, fill: dict[str, Any], timeout: float) -> Any:
        try:
            return self.link.call(service, fill, timeout, idempotent=service != REPLACE_SERVICE)
        except LinkError as e:
            raise NoManager(f"no component manager answers: {e}") from e

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
        instances.append({"name": i.name, "node": i.node, "component": i.component, "state": i.state,
                          "pid": int(i.pid), "restarts": int(i.restarts), "interface_hash": i.interface_hash,
                          "last_snapshot": i.last_snapshot or None,
                          "container": getattr(i, "container", "") or None})
        findings.extend({"instance": i.name, "message": f} for f in i.findings)
    return {"system": answer.system, "instances": instances, "findings": findings}
