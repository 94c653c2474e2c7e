"""Read running nodes off the ROS 2 graph through rclpy (imported here only, when a command needs it).

``open_graph(timeout)`` starts a probe node in a context of its own; ``Graph.read_node(name)`` reads
one node: its publishers and subscriptions with their QoS (``get_*_info_by_topic``), services,
clients, action servers and clients, parameters with their descriptors (the node's parameter
services), whether it is a lifecycle node, and its Describe answer when it serves one. The calls
go through the one client (``link``); every wait is bounded by the timeout.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from .link import Link
from .reading import (
    DESCRIBE_SERVICE,
    DESCRIBE_TYPE,
    LIFECYCLE_SERVICES,
    NamedEndpoint,
    NodeReading,
    Param,
    Qos,
    TopicEndpoint,
)

QOS_OVERRIDES = "qos_overrides."
_KINDS = {1: "bool", 2: "integer", 3: "double", 4: "string", 5: "byte_array", 6: "bool_array",
          7: "integer_array", 8: "double_array", 9: "string_array"}
_SLOTS = {"bool": "bool_value", "integer": "integer_value", "double": "double_value", "string": "string_value",
          "byte_array": "byte_array_value", "bool_array": "bool_array_value",
          "integer_array": "integer_array_value", "double_array": "double_array_value",
          "string_array": "string_array_value"}
_INFINITE_NS = 2147483647 * 10**9


class RosMissing(Exception):
    """ROS 2 is not sourced: rclpy cannot be imported."""


def ros_missing() -> str:
    """Why rclpy cannot be used here, or "" when it can."""
    try:
        import rclpy  # noqa: F401
    except ImportError as e:
        return f"ROS 2 is not sourced (rclpy cannot be imported: {e}); source ros2-env.sh or /opt/ros/<distro>/setup.bash"
    return ""


def _seconds(duration: Any) -> float | None:
    ns = int(duration.nanoseconds)
    return None if ns <= 0 or ns >= _INFINITE_NS else ns / 1e9


def _policy(value: Any) -> str:
    return str(getattr(value, "name", value)).lower()


def _value(value: Any) -> bool | int | float | str | tuple[bool | int | float | str, ...] | None:
    kind = _KINDS.get(int(value.type))
    if kind is None:
        return None
    got = getattr(value, _SLOTS[kind])
    if kind.endswith("_array"):
        return tuple(int(x) if kind == "byte_array" else x for x in got)
    return got


#: How long the graph must stay unchanged before a node not on it counts as not running: longer than
#: Fast DDS's participant announcement period (3 s), so a node whose first announcements were lost
#: (a loaded machine) is heard once more before it is called missing.
GRACE_SEC = 4.0
#: The shortest the whole graph must stay the same before it is read whole: other participants (nodes no file
#: declares, on the declared names) are discovered in bursts, and a gap of 0.3 s came before one on Jazzy and
#: of 1 s on Kilted under load (a participant not heard at once announces itself every 3 s).
WHOLE_QUIET_SEC = 2.0


class Graph:
    """A probe node on the graph and the calls that read other nodes."""

    def __init__(self, timeout: float) -> None:
        self.timeout = timeout
        self.link = Link.own(f"_iface_probe_{os.getpid()}", separate=True)
        self.node = self.link.node

    def close(self) -> None:
        """Stop the probe node and its context."""
        self.link.close()

    # ---- discovery ---------------------------------------------------------------------------
    def node_names(self) -> list[str]:
        """Full names of the visible nodes, hidden ones (``_…``) left out, sorted."""
        out = set()
        for name, ns in self.node.get_node_names_and_namespaces():
            if name.startswith("_"):
                continue
            out.add(ns.rstrip("/") + "/" + name)
        return sorted(out)

    def _shape(self, full: str) -> tuple[Any, ...]:
        ns, _, name = full.rpartition("/")
        ns = ns or "/"
        n = self.node
        try:
            return (tuple(sorted((t, tuple(ty)) for t, ty in n.get_publisher_names_and_types_by_node(name, ns))),
                    tuple(sorted((t, tuple(ty)) for t, ty in n.get_subscriber_names_and_types_by_node(name, ns))),
                    tuple(sorted((t, tuple(ty)) for t, ty in n.get_service_names_and_types_by_node(name, ns))),
                    tuple(sorted((t, tuple(ty)) for t, ty in n.get_client_names_and_types_by_node(name, ns))))
        except Exception:  # noqa: BLE001 - the node left the graph between the two calls
            return ()

    def _whole(self) -> tuple[Any, ...]:
        """Every node, topic and service on the graph with their types."""
        n = self.node
        return (tuple(self.node_names()), tuple(sorted((t, tuple(ty)) for t, ty in n.get_topic_names_and_types())),
                tuple(sorted((s, tuple(ty)) for s, ty in n.get_service_names_and_types())))

    def wait_for(self, names: list[str], settle: float = 0.3, grace: float = GRACE_SEC,
                 expect: dict[str, set[str]] | None = None, whole: bool = False) -> list[str]:
        """Wait until every name is on the graph and what each has stops changing; the names missing at the end.

        A name still missing when others have come and the graph has not changed for ``grace`` seconds
        is taken as not running (so a missing node costs ``grace``, not the whole timeout). ``expect``
        names, per node, the topics and services it should have: while one of those is not seen, what
        the nodes have must stay the same for ``grace`` (not ``settle``) before it counts as absent,
        since endpoints of a node are discovered one by one, with pauses under load. With ``whole``, the
        whole graph's nodes, topics and services (and their types) must also have stopped changing, for as
        long as the named nodes took to come (at least ``WHOLE_QUIET_SEC``, at most ``grace``): the other nodes on the
        names a file declares are discovered on the same schedule, and a loaded machine delays them all.
        """
        start = time.monotonic()
        deadline = start + self.timeout
        missing = list(names)
        last: set[str] = set()
        changed = start
        while time.monotonic() < deadline:
            present = set(self.node_names())
            missing = [n for n in names if n not in present]
            if not missing:
                break
            if present != last:
                last, changed = present, time.monotonic()
            if len(missing) < len(names) and time.monotonic() - changed >= grace:
                break
            time.sleep(0.05)
        if len(missing) == len(names):
            return missing
        quiet = max(settle, WHOLE_QUIET_SEC, min(time.monotonic() - start, grace)) if whole else settle
        names = [n for n in names if n not in missing]
        wanted = {n: (expect or {}).get(n, set()) for n in names}

        def complete(shape: tuple[Any, ...]) -> bool:
            for n, parts in zip(names, shape[0], strict=True):
                seen = {name for group in parts for name, _ in group}
                if not wanted[n] <= seen:
                    return False
            return True

        def read() -> tuple[Any, ...]:
            return tuple(self._shape(n) for n in names), self._whole() if whole else ()

        shape = read()
        stable_since = time.monotonic()
        while time.monotonic() < deadline and \
                time.monotonic() - stable_since < (quiet if complete(shape) else max(quiet, grace)):
            time.sleep(0.05)
            now = read()
            if now != shape:
                shape, stable_since = now, time.monotonic()
        return missing

    def wait_for_all(self, settle: float = 1.0) -> list[str]:
        """Every node once the list of nodes has stopped changing for ``settle`` seconds (within the timeout)."""
        deadline = time.monotonic() + self.timeout
        last = self.node_names()
        stable_since = time.monotonic()
        while time.monotonic() < deadline and (time.monotonic() - stable_since < settle or not last):
            time.sleep(0.05)
            now = self.node_names()
            if now != last:
                last, stable_since = now, time.monotonic()
        self.wait_for(last, settle=0.2)
        return last

    # ---- reading nodes -----------------------------------------------------------------------
    def describes(self, full: str) -> bool:
        """Whether the node ``full`` serves iface's ``Describe`` (as far as the graph shows now)."""
        ns, _, name = full.rpartition("/")
        try:
            services = self.node.get_service_names_and_types_by_node(name, ns or "/")
        except Exception:  # noqa: BLE001 - the node left the graph
            return False
        return any(NodeReading(full).relative(s) == DESCRIBE_SERVICE and list(t) == [DESCRIBE_TYPE]
                   for s, t in services)

    def read_node(self, full: str) -> NodeReading:
        """Everything the graph tells of the node ``full`` (``/ns/name``)."""
        return self.read_nodes([full])[full]

    def read_nodes(self, names: list[str], describe: bool = True) -> dict[str, NodeReading]:
        """Readings of several nodes; their parameter and Describe services (unless not ``describe``) are
        asked all at once."""
        snaps = {full: self._graph_part(full) for full in names}
        with_params = [s for s in snaps.values() if "list_parameters" in s.own_services]
        describing = [s for s in snaps.values()
                      if describe and s.own_services.get(DESCRIBE_SERVICE) == DESCRIBE_TYPE]
        self._parameters(with_params)
        self._describe(describing)
        for snap in snaps.values():
            snap.topics.sort(key=lambda t: (t.topic, t.role))
            snap.endpoints.sort(key=lambda e: (e.kind, e.name, e.role))
        return snaps

    def _graph_part(self, full: str) -> NodeReading:
        from rclpy.action import graph as action_graph

        ns, _, name = full.rpartition("/")
        ns = ns or "/"
        n = self.node
        snap = NodeReading(full)
        services = {s: tuple(t) for s, t in n.get_service_names_and_types_by_node(name, ns)}
        for s, t in services.items():
            rel = snap.relative(s)
            if rel is not None and len(t) == 1:
                snap.own_services[rel] = t[0]
        snap.lifecycle = snap.own_services.get("get_state") == "lifecycle_msgs/srv/GetState" or all(
            r in snap.own_services for r in LIFECYCLE_SERVICES)
        if snap.own_services.get("list_parameters") != "rcl_interfaces/srv/ListParameters":
            snap.own_services.pop("list_parameters", None)
        for role, listing, info in (
                ("publishes", n.get_publisher_names_and_types_by_node, n.get_publishers_info_by_topic),
                ("subscribes", n.get_subscriber_names_and_types_by_node, n.get_subscriptions_info_by_topic)):
            for topic, types in listing(name, ns):
                if "/_action/" in topic:
                    continue
                for ep in info(topic):
                    if ep.node_name != name or (ep.node_namespace.rstrip("/") or "/") != (ns.rstrip("/") or "/"):
                        continue
                    q = ep.qos_profile
                    qos = Qos(_policy(q.reliability), _policy(q.durability), _policy(q.liveliness),
                              _seconds(q.deadline), _seconds(q.lifespan), _seconds(q.liveliness_lease_duration))
                    snap.topics.append(TopicEndpoint(role, topic, ep.topic_type, qos))
                    break
                else:
                    for t in types:
                        snap.topics.append(TopicEndpoint(role, topic, t, Qos("unknown", "unknown", "unknown")))
        for sname, types in sorted(services.items()):
            if "/_action/" not in sname:
                snap.endpoints.append(NamedEndpoint("provides", "service", sname, types[0]))
        for sname, types in n.get_client_names_and_types_by_node(name, ns):
            if "/_action/" not in sname:
                snap.endpoints.append(NamedEndpoint("calls", "service", sname, types[0]))
        for aname, types in action_graph.get_action_server_names_and_types_by_node(n, name, ns):
            snap.endpoints.append(NamedEndpoint("provides", "action", aname, types[0]))
        for aname, types in action_graph.get_action_client_names_and_types_by_node(n, name, ns):
            snap.endpoints.append(NamedEndpoint("calls", "action", aname, types[0]))
        return snap

    def peers(self, topic: str) -> list[tuple[str, str, str, Qos]]:
        """(node, role, type, QoS) of every publisher and subscription on ``topic``."""
        out = []
        for role, info in (("publishes", self.node.get_publishers_info_by_topic),
                           ("subscribes", self.node.get_subscriptions_info_by_topic)):
            for ep in info(topic):
                if ep.node_name.startswith("_"):
                    continue
                q = ep.qos_profile
                node = ep.node_namespace.rstrip("/") + "/" + ep.node_name
                out.append((node, role, ep.topic_type, Qos(_policy(q.reliability), _policy(q.durability),
                                                           _policy(q.liveliness), _seconds(q.deadline),
                                                           _seconds(q.lifespan),
                                                           _seconds(q.liveliness_lease_duration))))
        return sorted(out, key=lambda x: (x[0], x[1]))

    def names_and_types(self, kind: str) -> dict[str, tuple[str, ...]]:
        """Every service (``kind`` ``service``) or action name on the graph with the types its servers and
        clients have (one call: what the graph holds, no node asked)."""
        if kind == "action":
            from rclpy.action import graph as action_graph

            listing = action_graph.get_action_names_and_types(self.node)
        else:
            listing = self.node.get_service_names_and_types()
        return {name: tuple(types) for name, types in listing}

    def named_peers(self, kind: str, names: set[str]) -> dict[str, list[tuple[str, str, str]]]:
        """(node, role, type) of every server (``provides``) and client (``calls``) of the services or actions
        ``names``, read node by node (hidden nodes left out); nothing is read when ``names`` is empty."""
        out: dict[str, list[tuple[str, str, str]]] = {}
        if not names:
            return out
        n = self.node
        listings: tuple[tuple[str, Any], ...] = (("provides", n.get_service_names_and_types_by_node),
                                                 ("calls", n.get_client_names_and_types_by_node))
        if kind == "action":
            from rclpy.action import graph as ag

            listings = (("provides", lambda name, ns: ag.get_action_server_names_and_types_by_node(n, name, ns)),
                        ("calls", lambda name, ns: ag.get_action_client_names_and_types_by_node(n, name, ns)))
        for full in self.node_names():
            ns, _, name = full.rpartition("/")
            for role, listing in listings:
                try:
                    found = listing(name, ns or "/")
                except Exception:  # noqa: BLE001 - the node left the graph meanwhile
                    found = []
                for sname, types in found:
                    if sname in names:
                        out.setdefault(sname, []).extend((full, role, t) for t in types)
        for peers in out.values():
            peers.sort()
        return out

    def _calls(self, calls: list[tuple[Any, str, Any]]) -> list[Any]:
        """Call several services at once (``(type, service, request)``): each answer, or None when it did not come
        within the timeout."""
        return self.link.calls([(name, kind, request) for kind, name, request in calls], self.timeout, keep=False)

    def _parameters(self, snaps: list[NodeReading]) -> None:
        from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters

        lists = self._calls([(ListParameters, f"{s.name}/list_parameters", ListParameters.Request()) for s in snaps])
        asked: list[tuple[NodeReading, list[str]]] = []
        for snap, listed in zip(snaps, lists, strict=True):
            if listed is None:
                snap.notes.append("its parameter services did not answer: parameters not read")
            elif listed.result.names:
                asked.append((snap, sorted(listed.result.names)))
        calls: list[tuple[Any, str, Any]] = []
        for snap, names in asked:
            calls.append((DescribeParameters, f"{snap.name}/describe_parameters", DescribeParameters.Request(names=names)))
            calls.append((GetParameters, f"{snap.name}/get_parameters", GetParameters.Request(names=names)))
        answers = self._calls(calls)
        for i, (snap, _) in enumerate(asked):
            described, got = answers[2 * i], answers[2 * i + 1]
            if described is None or got is None:
                snap.notes.append("its parameter services did not answer: parameters not read")
                continue
            _read_parameters(snap, described.descriptors, got.values)

    def _describe(self, snaps: list[NodeReading]) -> None:
        if not snaps:
            return
        try:
            from iface_msgs.srv import Describe
        except ImportError:
            for snap in snaps:
                snap.notes.append(f"it serves {DESCRIBE_TYPE} but iface_msgs is not installed here: read from the graph")
            return
        answers = self._calls([(Describe, f"{s.name}/{DESCRIBE_SERVICE}", Describe.Request()) for s in snaps])
        for snap, answer in zip(snaps, answers, strict=True):
            if answer is None:
                snap.notes.append("its Describe service did not answer: read from the graph")
                continue
            snap.describe_json = str(answer.interface_json)
            snap.describe_hash = str(answer.interface_hash)


def _read_parameters(snap: NodeReading, descriptors: Any, values: Any) -> None:
    """Parameters from the answers of describe_parameters and get_parameters; ``qos_overrides.*`` give QoS."""
    overrides: dict[tuple[str, str], dict[str, Any]] = {}
    for d, v in zip(descriptors, values, strict=True):
        value = _value(v)
        if d.name.startswith(QOS_OVERRIDES):
            topic, _, rest = d.name[len(QOS_OVERRIDES):].rpartition(".")
            topic, _, role = topic.rpartition(".")
            overrides.setdefault((topic, role), {})[rest] = value
            continue
        kind = _KINDS.get(int(d.type)) or _KINDS.get(int(v.type)) or "string"
        low: float | None = None
        high: float | None = None
        if d.integer_range:
            low, high = int(d.integer_range[0].from_value), int(d.integer_range[0].to_value)
        elif d.floating_point_range:
            low, high = float(d.floating_point_range[0].from_value), float(d.floating_point_range[0].to_value)
        snap.params.append(Param(d.name, kind, value, d.description, bool(d.read_only), low, high,
                                 d.additional_constraints))
    if not overrides:
        return
    role_of = {"publishes": "publisher", "subscribes": "subscription"}
    topics = []
    for t in snap.topics:
        o = overrides.get((t.topic, role_of[t.role]), {})
        if o:
            q = t.qos
            history, depth = o.get("history"), o.get("depth")
            t = TopicEndpoint(t.role, t.topic, t.type, Qos(
                q.reliability, q.durability, q.liveliness, q.deadline, q.lifespan, q.lease_duration,
                str(history).lower() if history is not None else None,
                int(depth) if isinstance(depth, int) and not isinstance(depth, bool) else None))
        topics.append(t)
    snap.topics = topics


@contextmanager
def open_graph(timeout: float) -> Iterator[Graph]:
    """A probe on the graph (raises RosMissing when rclpy cannot be imported), closed on exit."""
    why = ros_missing()
    if why:
        raise RosMissing(why)
    graph = Graph(timeout)
    try:
        yield graph
    finally:
        graph.close()
