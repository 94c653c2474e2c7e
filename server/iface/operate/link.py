"""The manager's line to its components: lifecycle transitions, status, save and restore (rclpy).

One rclpy node makes every call; an executor spins it in another thread, and each call here
waits (bounded) on its future. The protocol services' types are read from the graph, so the
manager needs no component's packages. A request that may be repeated is sent again every
:data:`RESEND` seconds while unanswered (a server just discovered may drop the first reply,
see ``handover``); a lifecycle transition is sent once, and its outcome read from ``get_state``.
"""

from __future__ import annotations

import importlib
import threading
import time
from collections.abc import Callable
from typing import Any


#: Seconds before an unanswered idempotent request is sent again.
RESEND = 2.0
#: The lifecycle state (lifecycle_msgs/State id) each transition the manager asks for ends in.
GOAL = {1: 2, 3: 3, 4: 2, 5: 4, 6: 4, 7: 4}


class LinkError(Exception):
    """A call did not get an answer in time, or was refused; the message says which."""


class Link:
    """Calls from ``node`` (spun elsewhere) to components."""

    def __init__(self, node: Any, group: Any = None) -> None:
        self.node = node
        self.group = group
        self._clients: dict[str, Any] = {}
        self._types: dict[str, Any] = {}
        self._lock = threading.Lock()

    def service_type(self, service: str) -> Any | None:
        """The type of ``service`` as the graph shows it, imported; None while it is not seen."""
        known = self._types.get(service)
        if known is not None:
            return known
        for name, types in self.node.get_service_names_and_types():
            if name == service and types:
                package, kind, type_name = types[0].split("/")
                found = getattr(importlib.import_module(f"{package}.{kind}"), type_name)
                self._types[service] = found
                return found
        return None

    def know(self, service: str, srv: Any) -> None:
        """Use ``srv`` as the type of ``service`` without asking the graph."""
        self._types[service] = srv

    def _client(self, service: str, srv: Any) -> Any:
        with self._lock:
            client = self._clients.get(service)
            if client is None:
                client = self._clients[service] = self.node.create_client(srv, service, callback_group=self.group)
            return client

    def forget(self, node: str) -> None:
        """Drop the clients of ``node`` (it was replaced or is gone)."""
        with self._lock:
            for service in [s for s in self._clients if s.startswith(node + "/")]:
                self.node.destroy_client(self._clients.pop(service))
                self._types.pop(service, None)

    def send(self, service: str, fill: dict[str, Any]) -> Any | None:
        """Send a request without waiting: its future, or None while the service is not seen."""
        srv = self.service_type(service)
        if srv is None:
            return None
        client = self._client(service, srv)
        if not client.service_is_ready():
            return None
        return client.call_async(_request(srv, fill))

    def call(self, service: str, fill: dict[str, Any], timeout: float, idempotent: bool = True,
             alive: Callable[[], bool] | None = None, resend: float = RESEND) -> Any:
        """Call ``service`` and wait at most ``timeout`` seconds for the answer (less when ``alive()`` turns false);
        an idempotent request unanswered after ``resend`` seconds is sent again."""
        deadline = time.monotonic() + timeout
        srv = self.service_type(service)
        while srv is None:
            if time.monotonic() >= deadline:
                raise LinkError(f"{service} does not exist (not seen within {timeout:g} s)")
            time.sleep(0.05)
            srv = self.service_type(service)
        client = self._client(service, srv)
        if not client.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic())):
            raise LinkError(f"{service} does not answer within {timeout:g} s")
        request = _request(srv, fill)
        done = threading.Event()
        futures: list[Any] = []
        while True:
            future = client.call_async(request)
            future.add_done_callback(lambda _f: done.set())
            futures.append(future)
            resend_at = time.monotonic() + resend
            while True:
                answer = next((f.result() for f in futures if f.done() and f.result() is not None), None)
                if answer is not None:
                    return answer
                now = time.monotonic()
                if now >= deadline:
                    raise LinkError(f"{service} does not answer within {timeout:g} s")
                if alive is not None and not alive():
                    raise LinkError(f"{service}: its process ended")
                if idempotent and now >= resend_at:
                    break
                done.wait(min(0.1, deadline - now))
                done.clear()

    # ---- the protocol ------------------------------------------------------------------------
    def control(self, node: str, command: int, timeout: float, alive: Callable[[], bool] | None = None) -> Any:
        """``~/control`` of ``node``."""
        return self.call(f"{node}/control", {"command": command, "timeout_sec": timeout}, timeout + 2, alive=alive)

    def lifecycle_state(self, node: str, timeout: float) -> int:
        """``node``'s lifecycle state id."""
        return int(self.call(f"{node}/get_state", {}, timeout, resend=0.5).current_state.id)

    def transition(self, node: str, transition: int, timeout: float,
                   alive: Callable[[], bool] | None = None) -> None:
        """Ask for a lifecycle transition (sent once); LinkError when it did not happen."""
        from lifecycle_msgs.msg import Transition

        try:
            answer = self.call(f"{node}/change_state", {"transition": Transition(id=transition)}, timeout,
                               idempotent=False, alive=alive)
        except LinkError:
            if alive is not None and not alive():
                raise
            if self.lifecycle_state(node, min(timeout, 3.0)) == GOAL[transition]:
                return
            raise
        if not answer.success:
            raise LinkError(f"{node} refused the transition {transition}")

    def save(self, node: str, timeout: float) -> str:
        """``node``'s state document."""
        answer = self.call(f"{node}/save_state", {"timeout_sec": timeout}, timeout + 2)
        if not answer.success:
            raise LinkError(f"{node} did not save its state: {answer.message}")
        return str(answer.state)

    def restore(self, node: str, document: str, timeout: float, alive: Callable[[], bool] | None = None) -> str:
        """Put ``document`` into ``node``; what it restored."""
        answer = self.call(f"{node}/restore_state", {"state": document, "timeout_sec": timeout}, timeout + 2,
                           alive=alive)
        if not answer.success:
            raise LinkError(f"{node} refused the state: {answer.message}")
        return str(answer.message)


def _request(srv: Any, fill: dict[str, Any]) -> Any:
    request = srv.Request()
    for key, value in fill.items():
        setattr(request, key, value)
    return request

