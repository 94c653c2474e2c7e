"""The one client for calling running nodes' services over rclpy: lifecycle, the component protocol, any other.

Every part that calls a running node uses it: the component manager, the hand-over, the ``system``
commands' calls to the manager, and the graph reader's parameter and Describe calls. It does, once:

- the service's type: known (``know``) or read from the graph, imported once; one client per
  service, kept until ``forget``;
- every wait in short steps (``STEP``), bounded, and cut short when ``alive()`` (the called
  process) turns false;
- a request that may be repeated (status, pause, save, restore, get_state, parameters, Describe)
  is sent again every ``resend`` seconds while unanswered, and its first answer counts: a server
  just seen in the graph may not have matched the caller's reply reader yet, and DDS then drops
  the reply (rmw_fastrtps: "client will not receive response");
- a lifecycle transition is sent again only when ``get_state`` shows the node still in the state
  it started from (the request was lost), never while the transition may run: a second request of
  one transition is one the lifecycle state machine refuses, so nothing happens twice;
- ``calls``: several requests at once, each answer or None.

It waits in one of two ways. A node spun elsewhere (an executor in another thread: the manager):
a wait is on the answers. A node of its own (``Link.own``: the hand-over command, the ``system``
commands, the graph reader), spun by the waits themselves.
"""

from __future__ import annotations

import importlib
import os
import threading
import time
from collections.abc import Callable, Sequence
from typing import Any

#: Seconds before an unanswered idempotent request is sent again (by default).
RESEND = 2.0
#: The longest single wait: a service's appearance and the end of a process are noticed this soon.
STEP = 0.02
#: Seconds a lifecycle transition waits for its answer before ``get_state`` is asked where the node is.
TRANSITION_WAIT = 0.5
#: The lifecycle state (lifecycle_msgs/State id) each transition ends in, and the one it starts from.
GOAL = {1: 2, 2: 1, 3: 3, 4: 2, 5: 4, 6: 4, 7: 4}
START = {1: 1, 2: 2, 3: 2, 4: 3, 5: 1, 6: 2, 7: 3}
#: lifecycle_msgs/State ids of the primary states; the others are a transition running.
PRIMARY = frozenset({0, 1, 2, 3, 4})


class LinkError(Exception):
    """A call did not get an answer in time, or was refused; the message says which."""


class Link:
    """Calls from ``node`` to other nodes' services.

    ``executor``: the waits spin it (a node nobody else spins); None: the node is spun elsewhere.
    """

    def __init__(self, node: Any, group: Any = None, executor: Any = None) -> None:
        self.node = node
        self.group = group
        self.executor = executor
        self._clients: dict[str, Any] = {}
        self._types: dict[str, Any] = {}
        self._lock = threading.Lock()
        self._close: Callable[[], None] | None = None

    @classmethod
    def own(cls, name: str, separate: bool = False) -> Link:
        """A link on a node of its own (no parameter services, no rosout), spun by its waits; ``close`` ends it.

        ``separate``: in a context of its own; else in rclpy's default one, initialised here when it is not.
        """
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        context = rclpy.Context() if separate else None
        made = separate or not rclpy.ok()
        if made:
            rclpy.init(context=context)
        node = rclpy.create_node(name, context=context, start_parameter_services=False, enable_rosout=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        link = cls(node, executor=executor)

        def close() -> None:
            executor.shutdown(timeout_sec=1.0)
            node.destroy_node()
            if made:
                rclpy.try_shutdown(context=context)

        link._close = close
        return link

    @staticmethod
    def unique(prefix: str) -> str:
        """A node name of this process that no other process takes (``prefix`` and the pid)."""
        return f"{prefix}_{os.getpid()}"

    def close(self) -> None:
        """End the node of ``Link.own`` (nothing for a node of someone else's)."""
        if self._close is not None:
            self._close()
            self._close = None

    # ---- services and clients ------------------------------------------------------------------
    def know(self, service: str, srv: Any) -> None:
        """Use ``srv`` as the type of ``service`` without asking the graph."""
        self._types[service] = srv

    def service_type(self, service: str) -> Any | None:
        """The type of ``service`` (known, or as the graph shows it, imported); None while it is not seen."""
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

    def client(self, service: str, srv: Any) -> Any:
        """The client of ``service`` (made once)."""
        with self._lock:
            client = self._clients.get(service)
            if client is None:
                client = self._clients[service] = self.node.create_client(srv, service, callback_group=self.group)
            return client

    def forget(self, node: str) -> None:
        """Drop the clients of ``node``'s services (it was replaced, is gone, or was read)."""
        with self._lock:
            for service in [s for s in self._clients if s.startswith(node + "/")]:
                self.node.destroy_client(self._clients.pop(service))
                self._types.pop(service, None)

    # ---- waiting ---------------------------------------------------------------------------------
    def pause(self, seconds: float, done: threading.Event | None = None) -> None:
        """Wait ``seconds`` (at most), spinning the own node; with ``done``, less when it is set."""
        if seconds <= 0:
            return
        if self.executor is not None:
            self.executor.spin_once(timeout_sec=seconds)
        elif done is not None:
            done.wait(seconds)
        else:
            time.sleep(seconds)

    def _ready(self, service: str, deadline: float, timeout: float,
               alive: Callable[[], bool] | None) -> tuple[Any, Any]:
        """(type, client) of ``service`` once the graph shows a server; LinkError past ``deadline``."""
        srv = self.service_type(service)
        while srv is None:
            _bounded(service, deadline, timeout, alive, "does not exist (not seen within {:g} s)")
            self.pause(STEP)
            srv = self.service_type(service)
        client = self.client(service, srv)
        while not client.service_is_ready():
            _bounded(service, deadline, timeout, alive, "does not answer within {:g} s")
            self.pause(STEP)
        return srv, client

    def ready(self, service: str, timeout: float, alive: Callable[[], bool] | None = None) -> None:
        """Wait (at most ``timeout`` s) until ``service`` is seen and its client made; LinkError if it is not."""
        self._ready(service, time.monotonic() + timeout, timeout, alive)

    # ---- calls -------------------------------------------------------------------------------------
    def send(self, service: str, fill: dict[str, Any]) -> Any | None:
        """Send a request without waiting: its future, or None while the service is not seen."""
        srv = self.service_type(service)
        if srv is None:
            return None
        client = self.client(service, srv)
        if not client.service_is_ready():
            return None
        return client.call_async(_request(srv, fill))

    def call(self, service: str, fill: dict[str, Any], timeout: float, idempotent: bool = True,
             alive: Callable[[], bool] | None = None, resend: float | None = None) -> Any:
        """Call ``service`` and wait at most ``timeout`` seconds for the answer (less when ``alive()`` turns false);
        an idempotent request unanswered after ``resend`` (default ``RESEND``) seconds is sent again."""
        resend = RESEND if resend is None else resend
        deadline = time.monotonic() + timeout
        srv, client = self._ready(service, deadline, timeout, alive)
        request = _request(srv, fill)
        done = threading.Event()
        futures: list[Any] = []
        resend_at = 0.0
        try:
            while True:
                now = time.monotonic()
                if not futures or (idempotent and now >= resend_at):
                    future = client.call_async(request)
                    future.add_done_callback(lambda _f: done.set())
                    futures.append(future)
                    resend_at = now + resend
                answer = _answer(futures)
                if answer is not None:
                    return answer
                _bounded(service, deadline, timeout, alive, "does not answer within {:g} s")
                done.clear()
                self.pause(min(0.1, deadline - now, resend_at - now if idempotent else 0.1), done)
        finally:
            _drop(client, futures)

    def calls(self, requests: Sequence[tuple[str, Any, Any]], timeout: float, keep: bool = True) -> list[Any]:
        """Several requests at once, ``(service, type, request)`` each (repeatable: sent again every ``RESEND``
        s while unanswered); each answer, or None when none came within ``timeout``. Without ``keep`` their
        clients are destroyed afterwards."""
        deadline = time.monotonic() + timeout
        done = threading.Event()
        pending: list[tuple[Any, Any, list[Any]]] = []  # (client, request, futures); client None: no server
        made: list[str] = []
        for service, srv, request in requests:
            self.know(service, srv)
            made.append(service)
            client = self.client(service, srv)
            while not client.service_is_ready() and time.monotonic() < deadline:
                self.pause(STEP)
            pending.append((client if client.service_is_ready() else None, request, []))
        try:
            resend_at = 0.0
            while True:
                now = time.monotonic()
                if now >= resend_at:
                    for client, request, futures in pending:
                        if client is not None and not _answer(futures):
                            future = client.call_async(request)
                            future.add_done_callback(lambda _f: done.set())
                            futures.append(future)
                    resend_at = now + RESEND
                if now >= deadline or all(c is None or _answer(f) is not None for c, _, f in pending):
                    return [_answer(futures) for _, _, futures in pending]
                done.clear()
                self.pause(min(0.05, deadline - now), done)
        finally:
            for client, _, futures in pending:
                if client is not None:
                    _drop(client, futures)
            if not keep:
                with self._lock:
                    for service in made:
                        client = self._clients.pop(service, None)
                        if client is not None:
                            self.node.destroy_client(client)

    # ---- the lifecycle and the component protocol -------------------------------------------------
    def lifecycle_state(self, node: str, timeout: float, alive: Callable[[], bool] | None = None) -> int:
        """``node``'s lifecycle state id."""
        return int(self.call(f"{node}/get_state", {}, timeout, resend=0.5, alive=alive).current_state.id)

    def transition(self, node: str, transition: int, timeout: float,
                   alive: Callable[[], bool] | None = None) -> None:
        """Bring ``node`` through a lifecycle transition; LinkError when it did not happen.

        Unanswered after ``TRANSITION_WAIT`` seconds, ``get_state`` says where the node is: at the
        transition's goal, done; in a transition state, running: its end is waited for; where the
        transition starts, or not answering (the node may not have seen the request), the request is
        sent again. A request that comes twice is refused by the node's state machine the second time
        (the transition is no longer valid from where the first one left the node), so it never runs twice.
        """
        deadline = time.monotonic() + timeout
        fill = {"transition": _transition_msg(transition)}
        while True:
            try:
                answer = self.call(f"{node}/change_state", fill,
                                   max(0.0, min(deadline - time.monotonic(), TRANSITION_WAIT)),
                                   idempotent=False, alive=alive)
            except LinkError:
                if alive is not None and not alive():
                    raise
                answer = None
            if answer is not None and answer.success:
                return
            state = self._state_or_none(node, deadline, alive)
            while state is not None and state not in PRIMARY:  # the transition runs: wait for its end
                self.pause(0.05)
                state = self._state_or_none(node, deadline, alive)
            if state == GOAL[transition]:
                return
            if answer is not None:
                raise LinkError(f"{node} refused the transition {transition}")
            if state is not None and state != START[transition]:
                raise LinkError(f"{node} is in lifecycle state {state}, not where transition {transition} starts")
            if time.monotonic() >= deadline:
                raise LinkError(f"{node}/change_state does not answer within {timeout:g} s")

    def _state_or_none(self, node: str, deadline: float, alive: Callable[[], bool] | None) -> int | None:
        """``node``'s lifecycle state, or None when it does not answer (asked at most 3 s, and not past
        ``deadline`` but for 0.5 s)."""
        try:
            return self.lifecycle_state(node, min(3.0, max(0.5, deadline - time.monotonic())), alive)
        except LinkError:
            if alive is not None and not alive():
                raise
            return None

    def control(self, node: str, command: int, timeout: float, alive: Callable[[], bool] | None = None,
                wait: float | None = None) -> Any:
        """``~/control`` of ``node`` (``timeout_sec``: ``timeout``; the answer waited for ``wait``, else
        ``timeout`` + 2 s)."""
        return self.call(f"{node}/control", {"command": command, "timeout_sec": timeout},
                         timeout + 2 if wait is None else wait, alive=alive)

    def save(self, node: str, timeout: float, alive: Callable[[], bool] | None = None,
             wait: float | None = None) -> Any:
        """``node``'s ``~/save_state`` answer; LinkError when it did not save."""
        answer = self.call(f"{node}/save_state", {"timeout_sec": timeout}, timeout + 2 if wait is None else wait,
                           alive=alive)
        if not answer.success:
            raise LinkError(f"{node} could not save its state: {answer.message}")
        return answer

    def restore(self, node: str, document: str, timeout: float, alive: Callable[[], bool] | None = None,
                wait: float | None = None) -> Any:
        """Put the state ``document`` into ``node``: its ``~/restore_state`` answer; LinkError when refused."""
        answer = self.call(f"{node}/restore_state", {"state": document, "timeout_sec": timeout},
                           timeout + 2 if wait is None else wait, alive=alive)
        if not answer.success:
            raise LinkError(f"{node} refused the state: {answer.message}")
        return answer


def _transition_msg(transition: int) -> Any:
    from lifecycle_msgs.msg import Transition

    return Transition(id=transition)


def _bounded(service: str, deadline: float, timeout: float, alive: Callable[[], bool] | None, why: str) -> None:
    if alive is not None and not alive():
        raise LinkError(f"{service}: its process ended")
    if time.monotonic() >= deadline:
        raise LinkError(f"{service} {why.format(timeout)}")


def _drop(client: Any, futures: list[Any]) -> None:
    """Forget the requests no answer came for (the client would keep them)."""
    for future in futures:
        if not future.done():
            remove = getattr(client, "remove_pending_request", None)
            if remove is not None:
                remove(future)


def _answer(futures: list[Any]) -> Any | None:
    return next((f.result() for f in futures if f.done() and f.result() is not None), None)


def _request(srv: Any, fill: dict[str, Any]) -> Any:
    request = srv.Request()
    for key, value in fill.items():
        setattr(request, key, value)
    return request
