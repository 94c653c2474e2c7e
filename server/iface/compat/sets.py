"""The seven sets compared element by element: M, N, S, A (endpoints), P, Σ, Δ, and namespaces."""

from __future__ import annotations

from ..model import nodes as m
from ..model.diagnostics import Severity
from ..model.walk import type_text
from .context import Context
from .fields import compare_unit_range
from .findings import Handover, Location, StateVar
from .qos import weakened
from .side import RECEIVE, Side
from .values import value_key, value_text, widens_type
from .parts import (
    diagnostics,
    endpoint_qos,
    endpoint_type,
    endpoints,
    namespaces,
    parameters,
    state,
)

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION

_REMOVED = {("topic", "publishes"): "published-removed", ("topic", "subscribes"): "subscribed-removed",
            ("service", "provides"): "service-removed", ("service", "calls"): "service-call-removed",
            ("action", "provides"): "action-removed", ("action", "calls"): "action-call-removed"}
_ADDED = {("topic", "publishes"): "published-added", ("topic", "subscribes"): "subscribed-added",
          ("service", "provides"): "service-added", ("service", "calls"): "service-call-added",
          ("action", "provides"): "action-added", ("action", "calls"): "action-call-added"}
_TYPE_CHANGED = {"topic": "topic-type-changed", "service": "service-type-changed", "action": "action-type-changed"}
_PEERS = {"publishes": "subscribers", "subscribes": "publishers", "provides": "callers", "calls": "servers"}


def endpoint_loc(side: Side, ep: m.Endpoint) -> Location:
    """Where an endpoint is stated: its wiring, else its definition's name."""
    if ep.wiring is not None:
        return side.loc(ep.wiring.span)
    assert ep.definition is not None
    return Location(side.where(ep.definition), ep.definition.name_span)


def _phrase(kind: str, role: str, name: str) -> str:
    return f"{role} {kind} '{name}'" if kind != "topic" else f"{role} '{name}'"


def compare_endpoints(ctx: Context) -> set[int]:
    """M, N, S and A; returns the ids of OLD definitions whose removal an endpoint finding already reports."""
    old, new = endpoints(ctx.old), endpoints(ctx.new)
    reported: set[int] = set()
    for key in sorted(set(old) | set(new)):
        kind, role, name = key
        usage = {f"{kind}:{name}"}
        o, n = old.get(key), new.get(key)
        if o is not None and n is not None:
            oloc, nloc = endpoint_loc(ctx.old, o), endpoint_loc(ctx.new, n)
            to, tn = endpoint_type(ctx.old, o), endpoint_type(ctx.new, n)
            if to != tn:
                ctx.add(_TYPE_CHANGED[kind], f"{kind} {name}", f"{_phrase(kind, role, name)} now carries {tn} "
                        f"instead of {to}", oloc, nloc, usage=usage,
                        breaks=f"its {_PEERS[role]} expect {to}")
            _qos(ctx, kind, role, name, o, n, oloc, nloc, usage)
        elif o is not None:
            code = _REMOVED[(kind, role)]
            fix = _restore_wiring(ctx.new, o, ctx.old)
            f = ctx.add(code, f"{kind} {name}", f"NEW no longer {_phrase(kind, role, name)}",
                        endpoint_loc(ctx.old, o), ctx.new.wiring_anchor(), usage=usage, fix=fix,
                        breaks=f"its {_PEERS[role]} lose it" if code in ("published-removed", "service-removed",
                                                                          "action-removed") else "")
            if f.severity == E and o.definition is not None and kind in ("service", "action"):
                reported.add(id(o.definition))
        elif n is not None:
            code = _ADDED[(kind, role)]
            requires = role in ("subscribes", "calls")
            ctx.add(code, f"{kind} {name}", f"NEW {_phrase(kind, role, name)}, OLD did not",
                    ctx.old.wiring_anchor(), endpoint_loc(ctx.new, n), usage=usage, requires=requires,
                    breaks=f"it needs {_PEERS[role][:-1]}s of '{name}' that OLD did not need" if requires else "")
    return reported


def _restore_wiring(new: Side, ep: m.Endpoint, old: Side) -> dict | None:
    if ep.wiring is None:
        return None
    text = old.source.text[ep.wiring.span.start:ep.wiring.span.end]
    at = new.iface.wirings[-1].span.end if new.iface.wirings else len(new.source.text)
    return {"kind": "restore", "text": text, "edits": [{"start": at, "end": at, "text": "\n" + text}]}


def _qos(ctx: Context, kind: str, role: str, name: str, o: m.Endpoint, n: m.Endpoint, oloc: Location,
         nloc: Location, usage: set[str]) -> None:
    qo, qn = endpoint_qos(o), endpoint_qos(n)
    if qo == qn:
        return
    lost = weakened(qo, qn, role) if kind == "topic" else []
    if lost:
        ctx.add("qos-incompatible", f"{kind} {name}", f"QoS of {_phrase(kind, role, name)}: " + "; ".join(lost),
                oloc, nloc, usage=usage, breaks=f"{_PEERS[role]} that matched OLD may no longer match")
    else:
        ctx.add("qos-changed", f"{kind} {name}", f"QoS of {_phrase(kind, role, name)} changed "
                f"{_show_qos(qo)} → {_show_qos(qn)}", oloc, nloc, usage=usage)


def _show_qos(q: dict[str, str]) -> str:
    return "(" + ", ".join(f"{k}={v}" for k, v in q.items()) + ")" if q else "(defaults)"


def _settings_anchor(side: Side, kind: str) -> Location:
    for d in side.iface.definitions:
        if isinstance(d, m.Struct) and d.kind == kind:
            return Location(side.source, d.name_span)
    return side.anchor()


def zero_value(side: Side, t: m.TypeRef) -> str | None:
    """A default that type ``t`` accepts, for the add-default fix (None for structs)."""
    from ..model.walk import resolve_typedefs
    t = resolve_typedefs(t)
    if isinstance(t, m.BaseType):
        if t.name == "bool":
            return "false"
        if t.name in m.FLOAT_TYPES:
            return "0.0"
        if t.name in m.STRING_TYPES or t.name == "binary":
            return '""'
        if t.name == "uuid":
            return '"00000000-0000-0000-0000-000000000000"'
        return "0"
    if isinstance(t, (m.ArrayType, m.SetType)):
        return "[]" if not (isinstance(t, m.ArrayType) and t.array == "fixed") else None
    if isinstance(t, m.MapType):
        return "{}"
    if isinstance(t, m.NamedType) and isinstance(t.target, m.Enum) and t.target.values:
        return f"{t.name}.{t.target.values[0].name}"
    return None


def _add_default_fix(side: Side, f: m.Field) -> dict | None:
    value = zero_value(side, f.type)
    if value is None:
        return None
    at = f.name_span.end
    return {"kind": "add-default", "field": f.name, "value": value,
            "edits": [{"start": at, "end": at, "text": f" = {value}"}]}


def _by_id(side: Side, names: set[str]) -> dict[tuple[str, int], m.Field]:
    """Parameters among ``names`` that carry a field id, by (configuration block, id)."""
    out: dict[tuple[str, int], m.Field] = {}
    for d in side.iface.definitions:
        if isinstance(d, m.Struct) and d.kind == "configuration":
            for f in d.fields:
                if f.id is not None and f.name in names:
                    out.setdefault((d.name, f.id), f)
    return out


def _renamed(ctx: Context, old: dict[str, m.Field], new: dict[str, m.Field]) -> dict[str, str]:
    """Parameters whose field id stayed while the name changed: old name -> new name (reported as errors).

    Parameters are matched by name because ROS 2, PX4 and ArduPilot set them by name
    (launch files, YAML, module.yaml, ground stations): keeping the id does not keep the name
    a deployment sets.
    """
    gone, came = _by_id(ctx.old, set(old) - set(new)), _by_id(ctx.new, set(new) - set(old))
    pairs: dict[str, str] = {}
    for key in sorted(set(gone) & set(came)):
        o, n = gone[key], came[key]
        pairs[o.name] = n.name
        ctx.add("parameter-renamed", f"parameter {o.name}",
                f"parameter '{o.name}' (id {key[1]} of '{key[0]}') is now named '{n.name}': parameters are set by "
                f"name, so a configuration that sets '{o.name}' no longer reaches it",
                ctx.old.loc(o.span), ctx.new.loc(n.span), usage={f"parameter:{o.name}"},
                breaks=f"launch files and parameter files that set '{o.name}'",
                fix={"kind": "restore", "text": o.name,
                     "edits": [{"start": n.name_span.start, "end": n.name_span.end, "text": o.name}]})
    return pairs


def compare_parameters(ctx: Context) -> None:
    """P: by name; NEW may need fewer parameters and accept wider values; a rename is an error."""
    old, new = parameters(ctx.old), parameters(ctx.new)
    renamed = _renamed(ctx, old, new)
    for name in sorted(set(old) | set(new)):
        if name in renamed.values():
            continue
        o, n = old.get(name), new.get(renamed.get(name, name))
        usage = {f"parameter:{name}"}
        subject = f"parameter {name}"
        if o is not None and n is not None:
            oloc, nloc = ctx.old.loc(o.span), ctx.new.loc(n.span)
            to, tn = ctx.old.type_key(o.type), ctx.new.type_key(n.type)
            if to != tn:
                if widens_type(o.type, n.type):
                    ctx.add("parameter-type-widened", subject, f"parameter '{name}' widened {to} → {tn}",
                            oloc, nloc, usage=usage)
                else:
                    ctx.add("parameter-type-changed", subject, f"parameter '{name}' changed type {to} → {tn}",
                            oloc, nloc, usage=usage, breaks="configurations written for OLD may not load")
            if o.default is not None and n.default is None:
                ctx.add("parameter-default-removed", subject, f"parameter '{name}' no longer has a default "
                        f"(was {value_text(o.default)})", oloc, nloc, usage=usage, fix=_add_default_fix(ctx.new, n),
                        breaks="deployments configured for OLD do not set it")
            elif value_key(o.default) != value_key(n.default):
                ctx.add("default-changed", subject, f"default of parameter '{name}' changed "
                        f"{value_text(o.default)} → {value_text(n.default)}", oloc, nloc, usage=usage)
            compare_unit_range(ctx, subject, f"parameter '{name}'", o, n, oloc, nloc, {RECEIVE}, usage)
        elif o is not None:
            ctx.add("parameter-removed", subject, f"NEW no longer reads parameter '{name}'", ctx.old.loc(o.span),
                    _settings_anchor(ctx.new, "configuration"), usage=usage)
        elif n is not None:
            oloc, nloc = _settings_anchor(ctx.old, "configuration"), ctx.new.loc(n.span)
            if n.default is None:
                ctx.add("parameter-added-required", subject, f"new parameter '{name}' has no default",
                        oloc, nloc, usage=usage, fix=_add_default_fix(ctx.new, n),
                        breaks="deployments configured for OLD do not set it")
            else:
                ctx.add("parameter-added", subject, f"new parameter '{name}' (default {value_text(n.default)})",
                        oloc, nloc, usage=usage)


def compare_state(ctx: Context) -> Handover:
    """Σ by name: what carries over, what is new, what is lost."""
    old, new = state(ctx.old), state(ctx.new)
    hand = Handover()
    for name in sorted(set(old) | set(new)):
        o, n = old.get(name), new.get(name)
        usage = {f"state:{name}"}
        subject = f"state {name}"
        if o is not None and n is not None:
            oloc, nloc = ctx.old.loc(o.span), ctx.new.loc(n.span)
            to, tn = ctx.old.type_key(o.type), ctx.new.type_key(n.type)
            if to == tn:
                hand.carried.append(StateVar(name, type_text(o.type)))
            elif widens_type(o.type, n.type):
                hand.carried.append(StateVar(name, type_text(o.type), new_type=type_text(n.type)))
                ctx.add("state-type-widened", subject, f"state '{name}' widened {to} → {tn}: its value carries "
                        "over", oloc, nloc, usage=usage)
            else:
                hand.lost.append(StateVar(name, type_text(o.type)))
                hand.new.append(StateVar(name, type_text(n.type), _initial(n)))
                ctx.add("state-type-changed", subject, f"state '{name}' changed type {to} → {tn}: its value "
                        "cannot be carried over", oloc, nloc, usage=usage, breaks="the running value is lost")
            if value_key(o.default) != value_key(n.default):
                ctx.add("default-changed", subject, f"initial value of state '{name}' changed "
                        f"{value_text(o.default)} → {value_text(n.default)}", oloc, nloc, usage=usage)
        elif o is not None:
            hand.lost.append(StateVar(name, type_text(o.type)))
            ctx.add("state-lost", subject, f"state '{name}' is not in NEW: its value is lost on hand-over",
                    ctx.old.loc(o.span), _settings_anchor(ctx.new, "state"), usage=usage,
                    breaks="the running value of the replaced component")
        elif n is not None:
            hand.new.append(StateVar(name, type_text(n.type), _initial(n)))
            oloc, nloc = _settings_anchor(ctx.old, "state"), ctx.new.loc(n.span)
            if n.default is None:
                ctx.add("state-needs-initial", subject, f"new state '{name}' has no default: the hand-over must "
                        "give it an initial value", oloc, nloc, usage=usage, fix=_add_default_fix(ctx.new, n))
            else:
                ctx.add("state-added", subject, f"new state '{name}' starts at {value_text(n.default)}",
                        oloc, nloc, usage=usage)
    return hand


def _initial(f: m.Field) -> str | None:
    return value_text(f.default) if f.default is not None else None


def compare_diagnostics(ctx: Context) -> set[int]:
    """Δ by served name (bodies are compared with the definitions); returns removed definitions already reported."""
    old, new = diagnostics(ctx.old), diagnostics(ctx.new)
    reported: set[int] = set()
    for name in sorted(set(old) | set(new)):
        o, n = old.get(name), new.get(name)
        usage = {f"service:{name}"}
        subject = f"diagnostics {name}"
        if o is not None and n is not None:
            to, tn = endpoint_type(ctx.old, o), endpoint_type(ctx.new, n)
            if to != tn:
                ctx.add("diagnostics-type-changed", subject, f"diagnostics '{name}' is now served by {tn} instead "
                        f"of {to}", endpoint_loc(ctx.old, o), endpoint_loc(ctx.new, n), usage=usage,
                        breaks=f"monitors that call it expect {to}")
        elif o is not None:
            ctx.add("diagnostics-removed", subject, f"NEW no longer provides diagnostics '{name}'",
                    endpoint_loc(ctx.old, o), ctx.new.anchor(), usage=usage, breaks="monitors that read it")
            if o.definition is not None:
                reported.add(id(o.definition))
        elif n is not None:
            ctx.add("diagnostics-added", subject, f"NEW provides diagnostics '{name}'",
                    ctx.old.anchor(), endpoint_loc(ctx.new, n), usage=usage)
    return reported


def compare_namespaces(ctx: Context) -> None:
    """Namespaces by scope: Thrift's audit warns when one is removed or renamed."""
    old, new = namespaces(ctx.old), namespaces(ctx.new)
    for scope in sorted(set(old) | set(new)):
        o, n = old.get(scope), new.get(scope)
        if o is not None and n is not None:
            if o.name != n.name:
                ctx.add("namespace-changed", f"namespace {scope}", f"namespace {scope} changed {o.name} → {n.name}",
                        ctx.old.loc(o.span), ctx.new.loc(n.span))
        elif o is not None:
            text = ctx.old.source.text[o.span.start:o.span.end]
            ctx.add("namespace-removed", f"namespace {scope}", f"namespace {scope} ({o.name}) was removed",
                    ctx.old.loc(o.span), ctx.new.anchor(),
                    fix={"kind": "restore", "text": text, "edits": [{"start": 0, "end": 0, "text": text + "\n"}]})
        elif n is not None:
            ctx.add("namespace-added", f"namespace {scope}", f"new namespace {scope} {n.name}",
                    ctx.old.anchor(), ctx.new.loc(n.span))
