"""Calls to a running ``iface_container``: load a component (its trust checked first), unload, list, hand over inside.

``ContainerCalls`` talks to one container by its node name over a protocol client (``call(service,
fill, timeout, idempotent)``, as ``live.link.Link`` has it): the standard ``~/_container/load_node``,
``unload_node`` and ``list_nodes`` (composition_interfaces) and the container's ``~/handover``
(iface_msgs/srv/HandOver, docs/runtime.md "The hand-over inside a container"). ``load`` refuses a
component the trust store does not trust **before** it sends the request: the container never opens its
library. A load is sent once (a second LoadNode would load a second node).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from ..nodes import protocol
from .containers import Component, ContainerError


class Caller(Protocol):
    """The protocol client the calls go through."""

    def call(self, service: str, fill: dict[str, Any], timeout: float, idempotent: bool = True,
             alive: Callable[[], bool] | None = None, resend: float | None = None) -> Any: ...


@dataclass(frozen=True, slots=True)
class Loaded:
    """A node a container loaded: the id its ``unload_node`` takes, and the node's fully qualified name."""

    unique_id: int
    node: str


@dataclass(frozen=True, slots=True)
class Switched:
    """What a container's ``~/handover`` did (``success`` False: OLD is as it was)."""

    success: bool
    message: str
    state: dict[str, Any] = field(default_factory=dict)
    restored: tuple[str, ...] = ()
    kept: tuple[str, ...] = ()
    pause_ms: float = 0.0
    critical_ms: float = 0.0
    after_tick: str = ""


def _parameter(name: str, value: bool | str | list[str]) -> Any:
    """An rcl_interfaces/Parameter for LoadNode's extra_arguments."""
    from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue

    if isinstance(value, bool):
        v = ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=value)
    elif isinstance(value, str):
        v = ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=value)
    else:
        v = ParameterValue(type=ParameterType.PARAMETER_STRING_ARRAY, string_array_value=list(value))
    return Parameter(name=name, value=v)


class ContainerCalls:
    """The services of the container whose node is ``name`` (``box`` or ``/box``)."""

    def __init__(self, link: Caller, name: str) -> None:
        self.link = link
        self.name = name if name.startswith("/") else "/" + name
        self._known = False

    def _know(self) -> None:
        """The container's services' types (composition_interfaces, iface_msgs): no wait for the graph to say them."""
        if self._known or not hasattr(self.link, "know"):
            return
        from composition_interfaces.srv import ListNodes, LoadNode, UnloadNode
        from iface_msgs.srv import HandOver

        for service, srv in (("_container/load_node", LoadNode), ("_container/unload_node", UnloadNode),
                             ("_container/list_nodes", ListNodes), (protocol.HAND_OVER[2:], HandOver)):
            self.link.know(f"{self.name}/{service}", srv)
            if hasattr(self.link, "client"):
                # made now, before the container (re)starts: its endpoints are matched with the others of the
                # process as it is discovered, so a load sent once it answers list_nodes is heard by it
                self.link.client(f"{self.name}/{service}", srv)
        self._known = True

    def load(self, component: Component, node_name: str, *, params_files: tuple[Path, ...] = (),
             intra_process: bool = True, configure: bool = False, activate: bool = False, state: str = "",
             trust_store: Path | None = None, timeout: float = 30.0) -> Loaded:
        """Load ``component`` as the node ``node_name`` (configured, restored, activated as asked); with a trust store,
        only when it trusts the component's package: ContainerError (nothing sent) otherwise, and when the
        container refuses."""
        if trust_store is not None:
            problems = component.untrusted(trust_store)
            if problems:
                raise ContainerError(f"{component.package} ({component.prefix}) is not trusted, not loaded: "
                                     + "; ".join(problems[:5]))
        self._know()
        extra = [_parameter("use_intra_process_comms", intra_process)]
        if params_files:
            extra.append(_parameter("params_files", [str(p) for p in params_files]))
        if configure or activate or state:
            extra.append(_parameter("configure", True))
        if state:
            extra.append(_parameter("state", state))
        if activate:
            extra.append(_parameter("activate", True))
        answer = self.link.call(f"{self.name}/_container/load_node",
                                {"package_name": str(component.resource), "plugin_name": component.plugin,
                                 "node_name": node_name, "extra_arguments": extra}, timeout, idempotent=False)
        if not answer.success:
            raise ContainerError(f"{self.name} did not load {component.plugin} as {node_name}: {answer.error_message}")
        return Loaded(int(answer.unique_id), str(answer.full_node_name))

    def unload(self, unique_id: int, timeout: float = 30.0) -> None:
        """Unload the node ``unique_id`` (the container quiesces it first); ContainerError when it is not there."""
        self._know()
        answer = self.link.call(f"{self.name}/_container/unload_node", {"unique_id": unique_id}, timeout,
                                idempotent=False)
        if not answer.success:
            raise ContainerError(f"{self.name} did not unload node {unique_id}: {answer.error_message}")

    def ready(self, timeout: float, alive: Callable[[], bool] | None = None, resend: float = 0.05) -> dict[str, int]:
        """Wait until the container answers ``list_nodes``, then ``load_node`` (each asked every ``resend`` s: an
        answer comes from a process that runs, never from one that just ended); its nodes.

        ``load_node`` is asked for a package no index has (``NO_PACKAGE``), which every container refuses at
        once and loads nothing for: a real load is sent once (a second one would load a second node), so it
        must not go out before the service's request and answer both reach this process's client; after a
        container restart the graph may still show the dead process's server, and ``list_nodes`` answering
        does not say that ``load_node``'s endpoints are matched yet.
        """
        self._know()
        deadline = time.monotonic() + timeout
        answer = self.link.call(f"{self.name}/_container/list_nodes", {}, timeout, alive=alive, resend=resend)
        self.link.call(f"{self.name}/_container/load_node", {"package_name": NO_PACKAGE, "plugin_name": NO_PACKAGE,
                                                             "node_name": NO_PACKAGE},
                       max(1.0, deadline - time.monotonic()), alive=alive, resend=resend)
        return dict(zip((str(n) for n in answer.full_node_names), (int(i) for i in answer.unique_ids), strict=True))

    def nodes(self, timeout: float = 10.0) -> dict[str, int]:
        """The nodes the container holds: fully qualified name → id."""
        self._know()
        answer = self.link.call(f"{self.name}/_container/list_nodes", {}, timeout)
        return dict(zip((str(n) for n in answer.full_node_names), (int(i) for i in answer.unique_ids), strict=True))

    def hand_over(self, old: str, new: str, timeout: float = 10.0) -> Switched:
        """The container switches from ``old`` (active) to ``new`` (configured) in its process."""
        self._know()
        start = time.monotonic()
        answer = self.link.call(f"{self.name}/handover", {"old_node": old, "new_node": new, "timeout_sec": timeout},
                                timeout + ALIGN_WAIT, idempotent=False)
        if not answer.success:
            return Switched(False, str(answer.message) or f"no answer in {time.monotonic() - start:.1f} s")
        return Switched(True, str(answer.message), json.loads(answer.state) if answer.state else {},
                        tuple(answer.restored), tuple(answer.kept), float(answer.pause_ms), float(answer.critical_ms),
                        str(answer.after_tick))


#: The package of ``ready``'s LoadNode: none has this name, so the container refuses it and loads nothing.
NO_PACKAGE = "iface_no_such_package"
#: Seconds beyond the hand-over's own timeout its answer may take (the wait for OLD's next tick, the call itself).
ALIGN_WAIT = protocol.ALIGN_SEC + 5.0
