"""Compare running nodes with their declared interfaces: findings with stable codes.

``declared(comp)`` names the node a compiled interface stands for (``ros2.node = "/ns/name"`` on the
component, else ``/<component>``); ``verify(nodes, live)`` compares each with what the graph told
(``LiveGraph``) and returns ``Finding``s located at the declared line, naming the running node; every
other node that has a declared topic, service or action with another type is named too. Nothing here
imports ROS: ``graph`` fills the ``LiveGraph``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..compat import qos as qosrules
from ..compat.canon import interface_hash
from ..compat.parts import endpoint_type
from ..compat.side import Side
from ..model import nodes as m
from ..model.source import Source, Span
from ..semantics.compile import Compilation
from ..text.printer import type_text
from .filters import own_endpoints, own_params, own_topics
from .reading import NodeReading, Qos
from .to_iface import duration_text

if TYPE_CHECKING:  # reading the graph needs rclpy; comparing does not
    from .graph import Graph

#: code -> (severity, what it means); the codes are stable.
CODES: dict[str, tuple[str, str]] = {
    "live-node-missing": ("error", "A declared node is not running."),
    "live-endpoint-missing": ("error", "A declared topic, service or action the running node does not have."),
    "live-endpoint-undeclared": ("warning", "A topic, service or action of the running node its file does not declare."),
    "live-type-mismatch": ("error", ("A declared topic, service or action that a node, declared or not, has with "
                                     "another type (both named).")),
    "live-qos-incompatible": ("error", ("A publisher and a subscriber on one topic whose QoS cannot match: "
                                        "reliability, durability, deadline or liveliness (ROS 2 then delivers "
                                        "nothing).")),
    "live-param-missing": ("error", "A declared parameter the running node does not have."),
    "live-param-type": ("error", "A parameter the running node holds with another type than declared."),
    "live-param-out-of-range": ("error", "A parameter whose running value is outside its declared range."),
    "live-describe-hash": ("error", "A node whose Describe answer gives another interface hash than its file's."),
}


@dataclass(frozen=True, slots=True)
class Finding:
    """One finding: its code, message, the running node, and the declared place (path, 1-based line and column)."""

    code: str
    message: str
    node: str
    path: str = ""
    line: int = 0
    column: int = 0
    end_line: int = 0
    end_column: int = 0

    @property
    def severity(self) -> str:
        """``error`` or ``warning``."""
        return CODES[self.code][0]


@dataclass(frozen=True, slots=True)
class Peer:
    """A publisher or subscription on a topic, of any node on the graph."""

    node: str
    role: str
    type: str
    qos: Qos


@dataclass(frozen=True, slots=True)
class NamedPeer:
    """A server (``provides``) or client (``calls``) of a service or action, of any node on the graph."""

    node: str
    role: str
    type: str


@dataclass(slots=True)
class LiveGraph:
    """What the graph told: the running node names, readings of the declared ones, every publisher and
    subscription of their topics and of the declared ones, and every server and client of each declared
    service and action name the graph carries with another type than declared."""

    names: list[str] = field(default_factory=list)
    nodes: dict[str, NodeReading] = field(default_factory=dict)
    peers: dict[str, list[Peer]] = field(default_factory=dict)
    named: dict[str, list[NamedPeer]] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class Declared:
    """A running node as a file declares it: its full name, the component's compilation, and where a
    system file names it (the instance), if one does."""

    node: str
    comp: Compilation
    instance: tuple[Source, Span] | None = None


def node_name(comp: Compilation) -> str:
    """The full node name a compiled component stands for."""
    decl = comp.interface.component
    if decl is not None:
        for a in decl.annotations:
            if a.key == "ros2.node" and a.text:
                return a.text if a.text.startswith("/") else "/" + a.text
    return "/" + comp.interface.name


def declared(comp: Compilation) -> Declared:
    """The node a file declares."""
    return Declared(node_name(comp), comp)


def declared_all(comps: list[Compilation]) -> list[Declared]:
    """The nodes the files declare: one per component file, one per instance of a system file.

    An instance runs as ``/<node>`` (its ``node`` annotation), else as its component file's
    ``ros2.node``, else as ``/<instance name>``.
    """
    from ..compat.systemfile import instance_compilations

    out: list[Declared] = []
    for comp in comps:
        if comp.interface.system is not None:
            for inst, component in instance_compilations(comp):
                given = inst.value("node")
                own = node_name(component)
                node = "/" + given if given else own if own != "/" + component.interface.name else "/" + inst.name
                out.append(Declared(node, component, (comp.source, inst.name_span)))
    for comp in comps:
        if comp.interface.system is None and comp.interface.component is not None:
            out.append(declared(comp))
    seen: set[tuple[str, str]] = set()
    unique = []
    for d in out:  # a component file given beside a system that runs it: once, as the instance
        key = (d.node, d.comp.path)
        if key not in seen:
            seen.add(key)
            unique.append(d)
    return unique


def resolve_name(node: str, name: str) -> str:
    """A declared name on the graph: ``~/x`` inside the node, ``x`` in its namespace."""
    if name.startswith("~"):
        return node.rstrip("/") + "/" + name[1:].lstrip("/")
    if name.startswith("/"):
        return name
    ns = node.rsplit("/", 1)[0]
    return ns + "/" + name


def ros_identity(ros_type: str) -> str:
    """``pkg/msg/Name`` → ``pkg/Name`` (as compat names types)."""
    parts = ros_type.split("/")
    return f"{parts[0]}/{parts[-1]}"


def qos_dict(q: Qos) -> dict[str, str]:
    """A running endpoint's QoS as ``qos.*`` settings (for the matching rules)."""
    out = {"reliability": q.reliability, "durability": q.durability, "liveliness": q.liveliness}
    if q.deadline is not None:
        out["deadline"] = duration_text(q.deadline)
    if q.lease_duration is not None:
        out["liveliness_lease_duration"] = duration_text(q.lease_duration)
    return {k: v for k, v in out.items() if v not in ("unknown", "system_default")}


_KIND = {"bool": "bool", "string": "string", "wstring": "string", "float32": "double", "float64": "double"}


def param_kind(f: m.Field) -> str | None:
    """The ROS 2 parameter type a declared parameter is held as (None when iface cannot tell)."""
    t = f.type
    suffix = ""
    while isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef):
        t = t.target.type
    if isinstance(t, (m.ArrayType, m.SetType)):
        t, suffix = t.element, "_array"
    while isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef):
        t = t.target.type
    if isinstance(t, m.NamedType) and isinstance(t.target, m.Enum):
        return "integer" + suffix
    if isinstance(t, m.BaseType):
        name = t.name
        if name in ("binary", "uuid"):  # uint8[] and uint8[16] in ROS 2
            return "integer_array"
        if name.startswith(("i", "u")) or name in ("char", "octet"):
            return "integer" + suffix
        kind = _KIND.get(name.split("<")[0])
        return kind + suffix if kind else None
    return None


_DOES = {"publishes": "publishes", "subscribes": "subscribes", "provides": "serves", "calls": "calls"}


class _Checker:
    def __init__(self, d: Declared, snap: NodeReading) -> None:
        self.d = d
        self.snap = snap
        self.source: Source = d.comp.source
        self.iface = d.comp.interface
        self.out: list[Finding] = []

    def at(self, code: str, message: str, span: Span | None, node: str = "") -> None:
        line = col = eline = ecol = 0
        if span is not None:
            line, col = self.source.position(span.start)
            eline, ecol = self.source.position(span.end)
            line, col, eline, ecol = line + 1, col + 1, eline + 1, ecol + 1
        self.out.append(Finding(code, message, node or self.d.node, self.source.path, line, col, eline, ecol))

    def anchor(self) -> Span | None:
        decl = self.iface.component
        return decl.name_span if decl is not None else None

    def endpoints(self) -> None:
        side = Side(self.d.comp)
        topics = {(t.role, t.topic): t for t in own_topics(self.snap, everything=True)}
        named = {(e.role, e.name): e for e in own_endpoints(self.snap, everything=True)}
        seen_topics: set[tuple[str, str]] = set()
        seen_named: set[tuple[str, str]] = set()
        declared_eps = [(ep, "topic") for ep in [*self.iface.subscribed, *self.iface.published]]
        declared_eps += [(ep, "service/action") for ep in [*self.iface.services, *self.iface.actions,
                                                          *self.iface.diagnostics_endpoints]]
        for ep, kind in declared_eps:
            name = resolve_name(self.d.node, ep.name)
            want = endpoint_type(side, ep)
            span = ep.wiring.span if ep.wiring is not None else ep.span
            running = topics.get((ep.role, name)) if kind == "topic" else named.get((ep.role, name))
            what = {"publishes": "publisher", "subscribes": "subscription", "provides": "server",
                    "calls": "client"}[ep.role]
            if running is None:
                self.at("live-endpoint-missing", f"{self.d.node} has no {what} on '{name}' (declared {ep.role} "
                        f"{want})", span)
                continue
            (seen_topics if kind == "topic" else seen_named).add((ep.role, name))
            got = ros_identity(running.type)
            if got != want:
                self.at("live-type-mismatch", f"'{name}': declared {want}, {self.d.node} has {got}", span)
        for key, t in sorted(topics.items()):
            if key not in seen_topics and t in own_topics(self.snap):
                self.at("live-endpoint-undeclared", f"{self.d.node} {t.role} {ros_identity(t.type)} on "
                        f"'{t.topic}', which its file does not declare", self.anchor())
        for key, e in sorted(named.items()):
            if key not in seen_named and e in own_endpoints(self.snap):
                self.at("live-endpoint-undeclared", f"{self.d.node} {e.role} {e.kind} {ros_identity(e.type)} on "
                        f"'{e.name}', which its file does not declare", self.anchor())

    def others(self, live: LiveGraph) -> None:
        """Every other node on a declared topic, service or action with another type, at the declared line."""
        side = Side(self.d.comp)
        for ep in [*self.iface.subscribed, *self.iface.published, *self.iface.services, *self.iface.actions,
                   *self.iface.diagnostics_endpoints]:
            name = resolve_name(self.d.node, ep.name)
            want = endpoint_type(side, ep)
            span = ep.wiring.span if ep.wiring is not None else ep.span
            peers: list[Peer] | list[NamedPeer] = live.peers.get(name, []) if ep.role in ("publishes", "subscribes") \
                else live.named.get(name, [])
            for p in peers:
                got = ros_identity(p.type)
                if p.node != self.d.node and got != want:
                    self.at("live-type-mismatch", f"'{name}': declared {want}, {p.node} {_DOES[p.role]} {got}", span,
                            p.node)

    def parameters(self) -> None:
        running = {p.name: p for p in own_params(self.snap, everything=True)}
        if not running and self.snap.notes:
            return  # its parameters could not be read: the note says so
        for f in self.iface.parameters:
            p = running.get(f.name)
            if p is None:
                self.at("live-param-missing", f"{self.d.node} has no parameter '{f.name}'", f.name_span)
                continue
            kind = param_kind(f)
            if kind is not None and kind != p.kind and not (kind == "integer_array" and p.kind == "byte_array"):
                self.at("live-param-type", f"parameter '{f.name}': declared {type_text(f.type)} (a ROS 2 {kind}), "
                        f"{self.d.node} holds a {p.kind}", f.name_span)
                continue
            rng = f.range
            if rng is None or p.value is None:
                continue
            values = p.value if isinstance(p.value, tuple) else (p.value,)
            lo, hi = rng
            for v in values:
                if isinstance(v, bool) or not isinstance(v, (int, float)):
                    continue
                if (lo is not None and v < lo) or (hi is not None and v > hi):
                    shown = "..".join("" if x is None else format(x, "g") for x in rng)
                    self.at("live-param-out-of-range", f"parameter '{f.name}' is {v:g} on {self.d.node}, outside "
                            f"its declared range {shown}", f.name_span)
                    break

    def describe(self) -> None:
        if not self.snap.describe_hash:
            return
        mine = interface_hash(self.d.comp)
        if mine != self.snap.describe_hash:
            self.at("live-describe-hash", f"{self.d.node} describes itself with interface hash "
                    f"{self.snap.describe_hash}, its file has {mine}", self.anchor())


def _qos_pairs(decls: list[Declared], live: LiveGraph) -> list[Finding]:
    """Every publisher/subscriber pair on a topic of a declared node whose QoS cannot match, once each."""
    by_node = {d.node: d for d in decls}
    out: list[Finding] = []
    for topic in sorted(live.peers):
        peers = live.peers[topic]
        pubs = [p for p in peers if p.role == "publishes"]
        subs = [p for p in peers if p.role == "subscribes"]
        for pub in pubs:
            for sub in subs:
                if pub.node not in by_node and sub.node not in by_node:
                    continue
                why = qosrules.mismatches(qos_dict(pub.qos), qos_dict(sub.qos))
                if not why:
                    continue
                where = by_node.get(sub.node) or by_node[pub.node]
                checker = _Checker(where, live.nodes.get(where.node) or NodeReading(where.node))
                role = "subscribes" if where.node == sub.node else "publishes"
                span = next((ep.wiring.span for ep in [*where.comp.interface.subscribed,
                                                        *where.comp.interface.published]
                             if ep.role == role and ep.wiring is not None
                             and resolve_name(where.node, ep.name) == topic), None)
                checker.at("live-qos-incompatible", f"'{topic}': {pub.node} publishes and {sub.node} subscribes "
                           f"with QoS that cannot match: " + "; ".join(why), span or checker.anchor())
                out.extend(Finding(f.code, f.message, f"{pub.node} -> {sub.node}", f.path, f.line, f.column,
                                   f.end_line, f.end_column) for f in checker.out)
    return out


def verify(decls: list[Declared], live: LiveGraph) -> list[Finding]:
    """Every finding of the declared nodes against the graph, each once, in file and line order."""
    out: list[Finding] = []
    for d in decls:
        snap = live.nodes.get(d.node)
        if snap is None:
            c = _Checker(d, NodeReading(d.node))
            if d.instance is not None:
                c.source = d.instance[0]
            c.at("live-node-missing", f"{d.node} is not running (declared by component {d.comp.interface.name})",
                 d.instance[1] if d.instance is not None else c.anchor())
            c.source = d.comp.source
        else:
            c = _Checker(d, snap)
            c.endpoints()
            c.parameters()
            c.describe()
        c.others(live)
        out.extend(c.out)
    out.extend(_qos_pairs(decls, live))
    return sorted(set(out), key=lambda f: (f.path, f.line, f.column, f.code, f.message, f.node))


def expected_names(d: Declared) -> set[str]:
    """The topics and services the node ``d`` should have by its file (actions aside: their names are
    the action's hidden ones), and its ``list_parameters`` service when it declares parameters."""
    iface = d.comp.interface
    eps = [*iface.subscribed, *iface.published, *iface.services, *iface.diagnostics_endpoints]
    names = {resolve_name(d.node, ep.name) for ep in eps}
    if iface.parameters:
        names.add(d.node + "/list_parameters")
    return names


def declared_names(decls: list[Declared]) -> tuple[set[str], dict[str, dict[str, set[str]]]]:
    """The topics the files declare, and per kind (``service``, ``action``) each declared name with its types."""
    topics: set[str] = set()
    named: dict[str, dict[str, set[str]]] = {"service": {}, "action": {}}
    for d in decls:
        side = Side(d.comp)
        iface = d.comp.interface
        topics.update(resolve_name(d.node, ep.name) for ep in [*iface.subscribed, *iface.published])
        for ep in [*iface.services, *iface.diagnostics_endpoints]:
            named["service"].setdefault(resolve_name(d.node, ep.name), set()).add(endpoint_type(side, ep))
        for ep in iface.actions:
            named["action"].setdefault(resolve_name(d.node, ep.name), set()).add(endpoint_type(side, ep))
    return topics, named


def read_live(graph: Graph, decls: list[Declared]) -> LiveGraph:
    """Read the nodes of ``decls``, the publishers and subscriptions of their topics and of the declared ones,
    and the servers and clients of every declared service or action the graph carries with another type."""
    live = LiveGraph()
    nodes = sorted({d.node for d in decls})
    expect: dict[str, set[str]] = {}
    for d in decls:
        expect.setdefault(d.node, set()).update(expected_names(d))
    graph.wait_for(nodes, expect=expect, whole=True)
    live.names = graph.node_names()
    live.nodes = graph.read_nodes([n for n in nodes if n in live.names])
    declared_topics, named = declared_names(decls)
    topics = sorted(declared_topics | {t.topic for s in live.nodes.values() for t in own_topics(s)})
    for topic in topics:
        live.peers[topic] = [Peer(n, r, t, q) for n, r, t, q in graph.peers(topic)]
    for kind, wanted in named.items():
        # the graph's own list of names and types (servers' and clients') first: only a name it carries with a
        # type no file declares for it is looked for node by node
        carried = graph.names_and_types(kind)
        odd = {name for name, types in wanted.items() if len({ros_identity(t) for t in carried.get(name, ())} | types) > 1}
        for name, peers in graph.named_peers(kind, odd).items():
            live.named[name] = [NamedPeer(n, r, t) for n, r, t in peers]
    return live
