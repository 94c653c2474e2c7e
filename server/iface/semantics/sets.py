"""Derive the seven sets I = M ∪ N ∪ S ∪ A ∪ P ∪ Σ ∪ Δ from a resolved interface."""

from __future__ import annotations

from collections.abc import Iterator

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, make
from ..model.walk import resolve_typedefs


def derive(iface: m.Interface) -> Iterator[Diagnostic]:
    """Fill the seven sets of ``iface``; report wiring that names the wrong kind of thing."""
    src = iface.source
    iface.subscribed, iface.published = [], []
    iface.services, iface.actions = [], []
    iface.parameters, iface.state, iface.diagnostics = [], [], []
    iface.diagnostics_endpoints = []
    wired_calls = False
    called: set[int] = set()
    for w in iface.wirings:
        target = w.type.target
        if isinstance(target, m.Typedef):
            real = resolve_typedefs(w.type)
            target = real.target if isinstance(real, m.NamedType) else target
        if w.direction in ("publishes", "subscribes"):
            if target is not None and not isinstance(target, m.Struct):
                done = "published" if w.direction == "publishes" else "subscribed to"
                yield make("wrong-kind", f"'{w.type.name}' is a {target.kind}, not a message: "
                           f"only messages are {done} on topics", src, w.type.span)
                continue
            ep = m.Endpoint(w.direction, w.topic, target, w)
            (iface.published if w.direction == "publishes" else iface.subscribed).append(ep)
            continue
        wired_calls = True
        if isinstance(target, m.Service) and target.is_diagnostics:
            if w.direction == "provides":  # the component's own Δ, under the wired name: not in S
                _add_delta(iface, m.Endpoint("provides", w.topic, target, w))
                continue
            called.add(id(target))  # another component's Δ, called: a service this one needs (S)
        if isinstance(target, m.Action):
            iface.actions.append(m.Endpoint(w.direction, w.topic, target, w))
        elif isinstance(target, m.Service) or target is None:
            iface.services.append(m.Endpoint(w.direction, w.topic, target, w))
        else:
            done = "provided" if w.direction == "provides" else "called"
            yield make("wrong-kind", f"'{w.type.name}' is a {getattr(target, 'kind', 'definition')}, "
                       f"not a service or action: only those are {done}", src, w.type.span)
    implicit: list[m.Definition] = []
    for d in iface.definitions:
        if isinstance(d, m.Struct):
            if d.kind == "configuration":
                iface.parameters.extend(d.fields)
            elif d.kind == "state":
                iface.state.extend(d.fields)
        elif isinstance(d, m.Service) and d.is_diagnostics:
            if id(d) not in called and all(e.definition is not d for e in iface.diagnostics_endpoints):
                _add_delta(iface, m.Endpoint("provides", d.name, d, None))
                yield _unwired_delta(iface, d)
        elif not wired_calls and iface.component is None and isinstance(d, (m.Service, m.Action)):
            implicit.append(d)
            ep = m.Endpoint("provides", d.name, d, None)
            (iface.actions if isinstance(d, m.Action) else iface.services).append(ep)
    if implicit and iface.source.path.endswith(".iface"):
        names = ", ".join(d.name for d in implicit)
        yield make("implicit-provides",
                   f"nothing is wired with provides/calls, so the component provides {names} "
                   "under their own names", src, implicit[0].name_span)
    yield from _wiring_checks(iface)


def interface_package(iface: m.Interface) -> bool:
    """A declared component that wires nothing: a package of types (as ``import --from ros2`` writes one).

    Its messages, services and actions are definitions only; nothing is read into M, N, S or A.
    """
    return iface.component is not None and not iface.wirings


def _add_delta(iface: m.Interface, ep: m.Endpoint) -> None:
    """Put a diagnostics service into Δ (once as a set member, once per name it is served under)."""
    iface.diagnostics_endpoints.append(ep)
    assert isinstance(ep.definition, m.Service)
    if all(d is not ep.definition for d in iface.diagnostics):
        iface.diagnostics.append(ep.definition)


def _unwired_delta(iface: m.Interface, d: m.Service) -> Diagnostic:
    """What an unwired diagnostics service is: Δ, served by the component under its own name."""
    why = "it is named 'diagnostics'" if d.name == "diagnostics" else "it is annotated (diagnostics)"
    return make("diagnostics-service",
                f"service '{d.name}' is the component's diagnostics and control service (the set Δ, kept apart "
                f"from its services S) because {why}: monitors call it to read the component's health and send "
                f"it commands. No `provides` names it, so it is served as '{d.name}' (add `provides {d.name} on "
                f"\"/name\"` to choose the name)", iface.source, d.name_span, name=d.name)


def _wiring_checks(iface: m.Interface) -> Iterator[Diagnostic]:
    src = iface.source
    by_topic: dict[tuple[str, str], m.Wiring] = {}
    seen: dict[tuple[str, str, str], m.Wiring] = {}
    for w in iface.wirings:
        key3 = (w.direction, w.type.name, w.topic)
        if key3 in seen:
            yield make("duplicate-wiring", f"'{w.direction} {w.type.name} on \"{w.topic}\"' is stated twice",
                       src, w.span, related=[Related(src, seen[key3].span, "first stated here")])
            continue
        seen[key3] = w
        channel = "topic" if w.direction in ("publishes", "subscribes") else "service"
        first = by_topic.get((channel, w.topic))
        if first is None:
            by_topic[(channel, w.topic)] = w
            continue
        a, b = first.type, w.type
        same = (a.target is not None and a.target is b.target) or a.name == b.name
        if not same:
            yield make("topic-type-conflict",
                       f"{channel} '{w.topic}' is used with '{b.name}' here and with '{a.name}' elsewhere",
                       src, w.topic_span,
                       related=[Related(src, first.topic_span, f"'{w.topic}' used with '{a.name}'")])
    wired = {e.definition for e in (*iface.published, *iface.subscribed)}
    if src.path.endswith(".iface") and not interface_package(iface):
        for d in iface.definitions:
            if isinstance(d, m.Struct) and d.kind == "message" and d not in wired:
                yield make("message-no-direction",
                           f"message '{d.name}' is neither published nor subscribed: it is a type "
                           f"definition (add `publishes {d.name} on \"/topic\"` to wire it)",
                           src, d.name_span, name=d.name)
