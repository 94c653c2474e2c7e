"""The parts of an interface that compatibility compares, keyed as the comparison matches them.

``canon`` and the comparison both read an interface through these functions, so
that two interfaces hash alike exactly when the comparison finds no difference.
"""

from __future__ import annotations

from ..model import nodes as m
from ..model.source import Source
from .side import Side, external_identity

#: (set letter, endpoint kind, attribute of Interface)
ENDPOINT_SETS = (("M", "topic", "subscribed"), ("N", "topic", "published"),
                 ("S", "service", "services"), ("A", "action", "actions"))


def endpoints(side: Side) -> dict[tuple[str, str, str], m.Endpoint]:
    """(kind, role, name) -> endpoint, first one wins."""
    out: dict[tuple[str, str, str], m.Endpoint] = {}
    for _, kind, attr in ENDPOINT_SETS:
        for ep in getattr(side.iface, attr):
            out.setdefault((kind, ep.role, ep.name), ep)
    return out


def endpoint_type(side: Side, ep: m.Endpoint) -> str:
    """The type of an endpoint as every component names it: ``package/Name`` (see ``Side.identity``)."""
    if ep.definition is not None:
        return side.identity(ep.definition)
    if ep.wiring is not None:
        return external_identity(ep.wiring.type)
    return "?"


def endpoint_qos(ep: m.Endpoint) -> dict[str, str]:
    """The QoS annotations of an endpoint."""
    return dict(sorted(ep.wiring.qos.items())) if ep.wiring is not None else {}


def _by_name(fields: list[m.Field]) -> dict[str, m.Field]:
    out: dict[str, m.Field] = {}
    for f in fields:
        out.setdefault(f.name, f)
    return out


def parameters(side: Side) -> dict[str, m.Field]:
    """P by name."""
    return _by_name(side.iface.parameters)


def state(side: Side) -> dict[str, m.Field]:
    """Σ by name."""
    return _by_name(side.iface.state)


def diagnostics(side: Side) -> dict[str, m.Endpoint]:
    """Δ by the name each diagnostics service is served under (its wiring, else its own name)."""
    out: dict[str, m.Endpoint] = {}
    for ep in side.iface.diagnostics_endpoints:
        out.setdefault(ep.name, ep)
    return out


def namespaces(side: Side) -> dict[str, m.Namespace]:
    """Namespaces by scope (the last declaration of a scope wins, as in Thrift)."""
    return {ns.scope: ns for ns in side.iface.namespaces}


def is_settings(d: m.Definition) -> bool:
    """configuration and state bodies: compared as P and Σ, by name, not as types."""
    return isinstance(d, m.Struct) and d.kind in ("configuration", "state")


def definitions(side: Side) -> dict[str, tuple[m.Definition, Source]]:
    """Definitions by qualified name, without configuration and state bodies."""
    return {q: v for q, v in side.defs.items() if not is_settings(v[0])}


def service_form(d: m.Service) -> str:
    """functions, sections or empty."""
    if d.form == "functions":
        return "functions"
    if d.form == "empty" and not d.sections:
        return "empty"
    return "sections"
