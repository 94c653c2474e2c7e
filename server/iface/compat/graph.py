"""The system graph: components as nodes; topics, services and actions as links
(publisher → subscriber, client → server), with checks of the wiring."""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass, field
from typing import Any, Callable

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Severity
from ..model.source import Source, Span
from ..semantics.compile import Compilation
from .canon import wire_form
from .system import Component, Port, System, qos_problems
from .view import endpoint_type

Display = Callable[[str], str]
GRAPH_ID = "iface-graph/1"
#: the graph checks: code -> (severity, summary)
CHECKS: dict[str, tuple[Severity, str]] = {
    "graph-unpublished-topic": (Severity.WARNING, "A subscribed topic that no component publishes."),
    "graph-unsubscribed-topic": (Severity.INFORMATION, "A published topic that no component subscribes."),
    "graph-topic-type-conflict": (Severity.ERROR, "One topic used with two message types."),
    "graph-qos-mismatch": (Severity.ERROR, "A publisher and a subscriber whose QoS cannot match."),
    "graph-unprovided-service": (Severity.WARNING, "A called service or action that no component provides."),
    "graph-service-type-conflict": (Severity.ERROR, "One service or action name with two types."),
    "graph-duplicate-provider": (Severity.WARNING, "A service or action provided by two components."),
}


@dataclass(frozen=True)
class Link:
    """One edge: from the sender of requests or messages to their receiver.

    ``kind`` is topic, service or action; ``set`` is the receiver's set (M, S, A or Δ for a
    monitor calling a component's diagnostics service); ``type`` is ``package/Name``.
    """

    kind: str
    name: str
    type: str
    source: Port
    target: Port
    qos: tuple[str, ...] = ()
    #: the endpoint is used with several types in the system (a graph-*-type-conflict check)
    type_conflict: bool = False

    @property
    def set(self) -> str:
        """The set of the receiving end."""
        return self.target.set

    @property
    def label_kind(self) -> str:
        """What the link is, in words: topic, service, action or diagnostics."""
        return "diagnostics" if self.target.delta else self.kind


@dataclass
class Graph:
    """Components, links, endpoints with no peer, and the checks."""

    components: list[Component]
    ids: dict[int, str]
    links: list[Link] = field(default_factory=list)
    open: list[Port] = field(default_factory=list)
    checks: list[Diagnostic] = field(default_factory=list)

    @property
    def has_errors(self) -> bool:
        """True when a check is an error."""
        return any(d.severity == Severity.ERROR for d in self.checks)


def wire_type(p: Port) -> str:
    """What a port's type is on the wire: its identity (``package/Name``) and a digest of its structure.

    Two components agree on a topic only when both match: the same name in another
    package, or the same package and name with other fields, are different types
    (ROS 2 matches by type hash). Types whose fields all carry ids are matched by
    identity only: readers may know a subset of the fields, which compat judges.
    """
    side = p.component.side
    d = p.endpoint.definition
    ident = endpoint_type(side, p.endpoint)
    if d is None:
        return ident
    if isinstance(d, m.Struct) and d.fields and all(f.id is not None for f in d.fields):
        return ident
    digest = hashlib.sha256(json.dumps(wire_form(side, d), sort_keys=True).encode()).hexdigest()[:8]
    return f"{ident}#{digest}"


def port_span(port: Port) -> Span:
    """Where a port is stated in its component's file: its wiring, else its definition's name."""
    w = port.endpoint.wiring
    span = w.span if w is not None else (port.endpoint.definition.name_span if port.endpoint.definition else None)
    return span or Span(0, 0)


def _check(code: str, port: Port, message: str) -> Diagnostic:
    data = {"instance": port.component.instance} if port.component.instance else {}
    return Diagnostic(code, message, port.component.side.source, port_span(port), CHECKS[code][0], data=data)


def _sender(p: Port) -> bool:
    return p.role in ("publishes", "calls")


def build(comps: list[Compilation], instances: list[tuple[str, Compilation]] | None = None) -> Graph:
    """The graph of a system of compiled components, or of a system file's ``instances`` (name, component)."""
    system = System.of(comps) if instances is None else System.of_instances(instances)
    ids: dict[int, str] = {}
    used: set[str] = set()
    for c in system.components:
        base = re.sub(r"[^A-Za-z0-9_]", "_", c.name) or "component"
        ident, n = base, 2
        while ident in used:
            ident, n = f"{base}_{n}", n + 1
        used.add(ident)
        ids[id(c)] = ident
    g = Graph(system.components, ids)
    for key in sorted(system.by_key):
        ports = system.by_key[key]
        kind, name = key.split(":", 1)
        senders = [p for p in ports if _sender(p)]
        receivers = [p for p in ports if not _sender(p)]
        types: dict[str, Port] = {}
        for p in ports:
            types.setdefault(wire_type(p), p)
        conflict = len(types) > 1
        if conflict:
            code = "graph-topic-type-conflict" if kind == "topic" else "graph-service-type-conflict"
            names = [t.partition("#")[0] for t in types]
            shown = ", ".join(
                f"{t.partition('#')[0]}{' (other fields)' if names.count(t.partition('#')[0]) > 1 else ''}"
                f" ({p.component.name})" for t, p in sorted(types.items()))
            for p in ports:
                g.checks.append(_check(code, p, f"{kind} '{name}' is used with several types: {shown}"))
        for s in senders:
            for r in receivers:
                problems = tuple(qos_problems(s, r))
                g.links.append(Link(kind, name, endpoint_type(s.component.side, s.endpoint), s, r, problems,
                                    conflict))
                if problems:
                    g.checks.append(_check("graph-qos-mismatch", r, f"QoS of '{name}' cannot match between "
                                           f"{s.component.name} and {r.component.name}: " + "; ".join(problems)))
        if kind == "topic":
            if not senders:
                for r in receivers:
                    g.open.append(r)
                    g.checks.append(_check("graph-unpublished-topic", r, f"{r.component.name} subscribes "
                                           f"'{name}', which no component of the system publishes"))
            if not receivers:
                for s in senders:
                    g.open.append(s)
                    g.checks.append(_check("graph-unsubscribed-topic", s, f"{s.component.name} publishes "
                                           f"'{name}', which no component of the system subscribes"))
        else:
            if not receivers:
                for s in senders:
                    g.open.append(s)
                    g.checks.append(_check("graph-unprovided-service", s, f"{s.component.name} calls {kind} "
                                           f"'{name}', which no component of the system provides"))
            if len(receivers) > 1:
                providers = ", ".join(r.component.name for r in receivers)
                for r in receivers:
                    g.checks.append(_check("graph-duplicate-provider", r, f"{kind} '{name}' is provided by "
                                           f"{len(receivers)} components: {providers}"))
    g.checks.sort(key=lambda d: (d.path, d.span.start, d.code, d.message))
    return g


def _dot_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _open_id(g: Graph, p: Port) -> str:
    return f"open_{g.ids[id(p.component)]}_{re.sub(r'[^A-Za-z0-9_]', '_', p.endpoint.name)}_{p.kind}"


def render_dot(g: Graph) -> str:
    """Graphviz DOT."""
    lines = ["digraph system {", "  rankdir=LR;", "  node [shape=box, fontname=\"Helvetica\"];",
             "  edge [fontname=\"Helvetica\", fontsize=10];"]
    for c in g.components:
        label = c.name + (f"\n{c.side.iface.version}" if c.side.iface.version else "")
        lines.append(f"  {_dot_string(g.ids[id(c)])} [label={_dot_string(label)}];")
    for p in g.open:
        lines.append(f"  {_dot_string(_open_id(g, p))} [label={_dot_string(p.endpoint.name)}, shape=plaintext];")
    for link in g.links:
        style = "solid" if link.kind == "topic" else "dashed"
        color = ", color=red" if link.qos or link.type_conflict else ""
        label = f"{link.name}\n{link.type}" + ("" if link.kind == "topic" else f" ({link.label_kind})")
        lines.append(f"  {_dot_string(g.ids[id(link.source.component)])} -> "
                     f"{_dot_string(g.ids[id(link.target.component)])} [label={_dot_string(label)}, "
                     f"style={style}{color}];")
    for p in g.open:
        a, b = g.ids[id(p.component)], _open_id(g, p)
        src, dst = (a, b) if _sender(p) else (b, a)
        lines.append(f"  {_dot_string(src)} -> {_dot_string(dst)} [style=dotted];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _mermaid_text(text: str) -> str:
    return text.replace('"', "#quot;").replace("\n", "<br/>")


def render_mermaid(g: Graph) -> str:
    """A Mermaid flowchart."""
    lines = ["flowchart LR"]
    for c in g.components:
        lines.append(f"  {g.ids[id(c)]}[\"{_mermaid_text(c.name)}\"]")
    for p in g.open:
        lines.append(f"  {_open_id(g, p)}([\"{_mermaid_text(p.endpoint.name)}\"])")
    for link in g.links:
        arrow = "-->" if link.kind == "topic" else "-.->"
        label = f"{link.name}: {link.type}" + ("" if link.kind == "topic" else f" ({link.label_kind})")
        lines.append(f"  {g.ids[id(link.source.component)]} {arrow}|\"{_mermaid_text(label)}\"| "
                     f"{g.ids[id(link.target.component)]}")
    for p in g.open:
        a, b = g.ids[id(p.component)], _open_id(g, p)
        src, dst = (a, b) if _sender(p) else (b, a)
        lines.append(f"  {src} -.- {dst}")
    return "\n".join(lines) + "\n"


def open_check(p: Port) -> str:
    """The check an endpoint without a peer gets."""
    if p.kind == "topic":
        return "graph-unsubscribed-topic" if _sender(p) else "graph-unpublished-topic"
    return "graph-unprovided-service"


def port_source(p: Port) -> Source:
    """The file a port is stated in: its component's, or an included one for an unwired definition."""
    side, ep = p.component.side, p.endpoint
    return side.where(ep.definition) if ep.wiring is None and ep.definition is not None else side.source


def graph_json(g: Graph, display: Display) -> dict[str, Any]:
    """The graph as JSON data; every element with the place an editor goes to when it is clicked
    (``at``, ``from_at``/``to_at``; ``definition``: where the type a link or open end carries is defined)."""
    def place(src: Source, span: Span) -> dict[str, Any]:
        line, col = src.position(span.start)
        return {"file": display(src.path), "line": line + 1, "column": col + 1}

    def at(p: Port) -> dict[str, Any]:
        return place(port_source(p), port_span(p))

    def definition(p: Port) -> dict[str, Any] | None:
        d = p.endpoint.definition
        return place(p.component.side.where(d), d.name_span) if d is not None else None

    def component_at(c: Component) -> dict[str, Any]:
        decl = c.side.iface.component
        return place(c.side.source, decl.name_span if decl is not None else Span(0, 0))

    def port(p: Port) -> dict[str, Any]:
        code = open_check(p)
        return {"component": g.ids[id(p.component)], "kind": p.kind, "set": p.set, "role": p.role,
                "name": p.endpoint.name, "type": endpoint_type(p.component.side, p.endpoint), "at": at(p),
                "check": code, "severity": CHECKS[code][0].label, "definition": definition(p)}
    return {
        "schema": GRAPH_ID,
        "components": [{"id": g.ids[id(c)], "name": c.name, "component": c.side.name, "version": c.side.iface.version,
                        "file": display(c.comp.path), "at": component_at(c)} for c in g.components],
        "links": [{"kind": lk.kind, "set": lk.set, "name": lk.name, "type": lk.type,
                   "to_type": endpoint_type(lk.target.component.side, lk.target.endpoint),
                   "from": g.ids[id(lk.source.component)],
                   "to": g.ids[id(lk.target.component)], "qos_mismatch": list(lk.qos),
                   "type_conflict": lk.type_conflict, "from_at": at(lk.source), "to_at": at(lk.target),
                   "definition": definition(lk.source)}
                  for lk in g.links],
        "open": [port(p) for p in g.open],
        "checks": [d.to_json(display(d.path)) for d in g.checks],
    }


def render_json(g: Graph, display: Display) -> str:
    """The graph as indented JSON."""
    return json.dumps(graph_json(g, display), indent=2, ensure_ascii=False) + "\n"
