"""Read running nodes off the ROS 2 graph through rclpy (imported here only, when a command needs it).

``open_graph(timeout)`` starts a probe node in a context of its own; ``Graph.snapshot(name)`` reads
one node: its publishers and subscriptions with their QoS (``get_*_info_by_topic``), services,
clients, action servers and clients, parameters with their descriptors (the node's parameter
services), whether it is a lifecycle node, and its Describe answer when it serves one. Every wait
is bounded by the timeout.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from .snapshot import (DESCRIBE_SERVICE, DESCRIBE_TYPE, LIFECYCLE_SERVICES, NamedEndpoint, NodeSnapshot, Param, Qos,
                       TopicEndpoint)

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


class Graph:
    """A probe node on the graph and the calls that read other nodes."""

    def __init__(self, timeout: float) -> None:
        import rclpy
        from rclpy.executors import SingleThreadedExecutor

        self.timeout = timeout
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node(f"_iface_probe_{os.getpid()}", context=self.context,
                                      start_parameter_services=False, enable_rosout=False)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)

    def close(self) -> None:
        """Stop the probe node and its context."""
        import rclpy

        self.executor.shutdown(timeout_sec=1.0)
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)

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
        except Exception:  # the node left the graph between the two calls
            return ()

    def wait_for(self, names: list[str], settle: float = 0.3) -> list[str]:
        """Wait until every name is on the graph and what each has stops changing; the names missing at the end."""
        deadline = time.monotonic() + self.timeout
        missing = list(names)
        while time.monotonic() < deadline:
            present = set(self.node_names())
            missing = [n for n in names if n not in present]
            if not missing:
                break
            time.sleep(0.05)
        if missing:
            return missing
        last = tuple(self._shape(n) for n in names)
        stable_since = time.monotonic()
        while time.monotonic() < deadline and time.monotonic() - stable_since < settle:
            time.sleep(0.05)
            now = tuple(self._shape(n) for n in names)
            if now != last:
                last, stable_since = now, time.monotonic()
        return []

    def wait_for_all(self, settle: float = 0.5) -> list[str]:
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

    # ---- reading a node ----------------------------------------------------------------------
    def snapshot(self, full: str) -> NodeSnapshot:
        """Everything the graph tells of the node ``full`` (``/ns/name``)."""
        from rclpy.action import graph as action_graph

        ns, _, name = full.rpartition("/")
        ns = ns or "/"
        n = self.node
        snap = NodeSnapshot(full)
        services = {s: tuple(t) for s, t in n.get_service_names_and_types_by_node(name, ns)}
        rels = {snap.relative(s): t for s, t in services.items()}
        snap.lifecycle = ("lifecycle_msgs/srv/GetState",) == rels.get("get_state") or all(
            r in rels for r in LIFECYCLE_SERVICES)
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
        if rels.get("list_parameters") == ("rcl_interfaces/srv/ListParameters",):
            self._parameters(snap)
        if rels.get(DESCRIBE_SERVICE) == (DESCRIBE_TYPE,):
            self._describe(snap)
        snap.topics.sort(key=lambda t: (t.topic, t.role))
        snap.endpoints.sort(key=lambda e: (e.kind, e.name, e.role))
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

    def _call(self, srv_type: Any, service: str, request: Any) -> Any:
        client = self.node.create_client(srv_type, service)
        try:
            left = self.timeout
            if not client.wait_for_service(timeout_sec=left):
                return None
            future = client.call_async(request)
            self.executor.spin_until_future_complete(future, timeout_sec=self.timeout)
            return future.result() if future.done() else None
        finally:
            self.node.destroy_client(client)

    def _parameters(self, snap: NodeSnapshot) -> None:
        from rcl_interfaces.srv import DescribeParameters, GetParameters, ListParameters

        listed = self._call(ListParameters, f"{snap.name}/list_parameters", ListParameters.Request())
        if listed is None:
            snap.notes.append("its parameter services did not answer: parameters not read")
            return
        names = sorted(listed.result.names)
        if not names:
            return
        described = self._call(DescribeParameters, f"{snap.name}/describe_parameters",
                               DescribeParameters.Request(names=names))
        got = self._call(GetParameters, f"{snap.name}/get_parameters", GetParameters.Request(names=names))
        if described is None or got is None:
            snap.notes.append("its parameter services did not answer: parameters not read")
            return
        overrides: dict[tuple[str, str], dict[str, Any]] = {}
        for d, v in zip(described.descriptors, got.values, strict=True):
            value = _value(v)
            if d.name.startswith(QOS_OVERRIDES):
                topic, _, rest = d.name[len(QOS_OVERRIDES):].rpartition(".")
                topic, _, role = topic.rpartition(".")
                overrides.setdefault((topic, role), {})[rest] = value
                continue
            kind = _KINDS.get(int(d.type)) or _KINDS.get(int(v.type)) or "string"
            low = high = None
            if d.integer_range:
                low, high = int(d.integer_range[0].from_value), int(d.integer_range[0].to_value)
            elif d.floating_point_range:
                low, high = float(d.floating_point_range[0].from_value), float(d.floating_point_range[0].to_value)
            snap.params.append(Param(d.name, kind, value, d.description, bool(d.read_only), low, high,
                                     d.additional_constraints))
        if overrides:
            role_of = {"publishes": "publisher", "subscribes": "subscription"}
            topics = []
            for t in snap.topics:
                o = overrides.get((t.topic, role_of[t.role]), {})
                if o:
                    q = t.qos
                    history = o.get("history")
                    depth = o.get("depth")
                    t = TopicEndpoint(t.role, t.topic, t.type, Qos(
                        q.reliability, q.durability, q.liveliness, q.deadline, q.lifespan, q.lease_duration,
                        str(history).lower() if history is not None else None,
                        int(depth) if isinstance(depth, int) else None))
                topics.append(t)
            snap.topics = topics

    def _describe(self, snap: NodeSnapshot) -> None:
        try:
            from iface_msgs.srv import Describe  # type: ignore[import-not-found]
        except ImportError:
            snap.notes.append(f"it serves {DESCRIBE_TYPE} but iface_msgs is not installed here: read from the graph")
            return
        answer = self._call(Describe, f"{snap.name}/{DESCRIBE_SERVICE}", Describe.Request())
        if answer is None:
            snap.notes.append("its Describe service did not answer: read from the graph")
            return
        snap.describe_json = str(answer.interface_json)
        snap.describe_hash = str(answer.interface_hash)


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
