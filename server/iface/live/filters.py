"""Which of a node's endpoints are its own interface, and which belong to ROS 2 or to iface's component protocol."""

from __future__ import annotations

from ..nodes.protocol import CONTROL, DIAGNOSTICS_TOPIC, RESTORE_STATE, SAVE_STATE, SERVICE_TYPES
from .reading import NamedEndpoint, NodeReading, TopicEndpoint

#: ROS 2's own parameters (every node declares them).
ROS_PARAMETERS = ("use_sim_time", "start_type_description_service")
_PROTOCOL = {s[2:] for s in (SAVE_STATE, RESTORE_STATE, CONTROL)}


def serves_protocol(snap: NodeReading) -> bool:
    """True when the node serves iface's component protocol (``~/save_state``, ``~/restore_state``, ``~/control``)."""
    found = {snap.relative(e.name) for e in snap.endpoints
             if e.role == "provides" and e.type.rsplit("/", 1)[-1] in SERVICE_TYPES}
    return _PROTOCOL <= found


def is_protocol(snap: NodeReading, ep: NamedEndpoint | TopicEndpoint) -> bool:
    """An endpoint of iface's component protocol (when the node serves it): its three services and /diagnostics."""
    if not serves_protocol(snap):
        return False
    if isinstance(ep, TopicEndpoint):
        return ep.role == "publishes" and ep.topic == DIAGNOSTICS_TOPIC and ep.type.endswith("/DiagnosticArray")
    return ep.role == "provides" and snap.relative(ep.name) in _PROTOCOL and \
        ep.type.rsplit("/", 1)[-1] in SERVICE_TYPES


def own_topics(snap: NodeReading, everything: bool = False) -> list[TopicEndpoint]:
    """The node's topics; ROS 2's and the protocol's left out unless ``everything``."""
    return [t for t in snap.topics
            if everything or not (snap.is_ros_own(t.topic, "topic") or is_protocol(snap, t))]


def own_endpoints(snap: NodeReading, everything: bool = False) -> list[NamedEndpoint]:
    """The node's services and actions; ROS 2's and the protocol's left out unless ``everything``."""
    return [e for e in snap.endpoints
            if everything or not (snap.is_ros_own(e.name, "service") or is_protocol(snap, e))]


def own_params(snap: NodeReading, everything: bool = False) -> list:
    """The node's parameters; ROS 2's own (``use_sim_time``…) left out unless ``everything``."""
    return [p for p in snap.params if everything or p.name not in ROS_PARAMETERS]
