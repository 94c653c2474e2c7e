"""Definitions compared by name: structs and messages, enums, typedefs, constants, services, actions."""

from __future__ import annotations

from collections.abc import Iterable

from ..model import nodes as m
from ..model.diagnostics import Severity
from ..model.source import Source, Span
from .context import Context, by_direction
from .fields import Body, compare_fields
from .findings import Location
from .side import BOTH, SEND, Side, flip
from .values import value_key, value_text
from .parts import definitions, service_form

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION
_SAME_KIND = {"struct", "message"}


def _kind(d: m.Definition) -> str:
    return d.kind  # every definition class has ``kind``


def flow(old: Side, new: Side, o: m.Definition | None, n: m.Definition | None) -> set[str]:
    """Directions a matched pair of definitions flows in, as seen by the component."""
    dirs: set[str] = set()
    for side, d in ((old, o), (new, n)):
        if d is not None and side.dirs.get(id(d)):
            dirs |= side.dirs[id(d)]
    return dirs or set(BOTH)


def usage_of(old: Side, new: Side, o: m.Definition | None, n: m.Definition | None) -> set[str]:
    """Usage keys of a matched pair (endpoint keys, else ``type:Name``)."""
    keys: set[str] = set()
    for side, d in ((old, o), (new, n)):
        if d is not None:
            keys |= side.keys.get(id(d), set())
    if not keys:
        d = o if o is not None else n
        assert d is not None
        keys.add(f"type:{(old if o is not None else new).qualname(d)}")
    return keys


def compare_definitions(ctx: Context, skip_removed: set[int]) -> None:
    """Match every definition of OLD and NEW by qualified name and compare each pair."""
    old_defs, new_defs = definitions(ctx.old), definitions(ctx.new)
    for q in sorted(set(old_defs) | set(new_defs)):
        o, n = old_defs.get(q), new_defs.get(q)
        if o is not None and n is not None:
            compare_definition(ctx, q, o[0], o[1], n[0], n[1],
                               flow(ctx.old, ctx.new, o[0], n[0]), usage_of(ctx.old, ctx.new, o[0], n[0]))
        elif o is not None:
            if id(o[0]) not in skip_removed:
                _removed(ctx, q, o[0], o[1], list(old_defs), new_defs)
        elif n is not None:
            d = n[0]
            code = "const-added" if isinstance(d, m.Const) else "definition-added"
            ctx.add(code, q, f"new {_kind(d)} '{q}'", ctx.old.anchor(), Location(n[1], d.name_span),
                    usage=usage_of(ctx.old, ctx.new, None, d))


def _nearest(q: str, order: list[str], new_defs: dict[str, tuple[m.Definition, Source]]) -> m.Definition | None:
    """The definition of NEW nearest (before, else after) to where ``q`` stood in OLD."""
    i = order.index(q)
    for name in reversed(order[:i]):
        if name in new_defs:
            return new_defs[name][0]
    for name in order[i + 1:]:
        if name in new_defs:
            return new_defs[name][0]
    return None


def _removed(ctx: Context, q: str, d: m.Definition, src: Source, order: list[str],
             new_defs: dict[str, tuple[m.Definition, Source]]) -> None:
    near = _nearest(q, order, new_defs)
    nloc = Location(ctx.new.where(near), near.name_span) if near is not None else ctx.new.anchor()
    oloc = Location(src, d.name_span)
    text = src.text[d.span.start:d.span.end]
    fix = None
    if near is not None and ctx.new.where(near) is ctx.new.source:
        fix = {"kind": "restore", "text": text,
               "edits": [{"start": near.span.end, "end": near.span.end, "text": "\n\n" + text}]}
    usage = usage_of(ctx.old, ctx.new, d, None)
    kind = _kind(d)
    if isinstance(d, m.Enum) or isinstance(d, m.Senum):
        ctx.add("enum-removed", q, f"enum '{q}' was removed", oloc, nloc, usage=usage, fix=fix)
    elif isinstance(d, m.Typedef):
        ctx.add("typedef-removed", q, f"typedef '{q}' was removed", oloc, nloc, usage=usage, fix=fix)
    elif isinstance(d, m.Const):
        ctx.add("const-removed", q, f"constant '{q}' was removed", oloc, nloc, usage=usage, fix=fix)
    else:
        ctx.add("definition-removed", q, f"{kind} '{q}' was removed", oloc, nloc, usage=usage, fix=fix,
                breaks=f"peers built against OLD use '{q}'")


def compare_definition(ctx: Context, q: str, o: m.Definition, osrc: Source, n: m.Definition, nsrc: Source,
                       dirs: set[str], usage: set[str]) -> None:
    """Compare two definitions of one name."""
    oloc, nloc = Location(osrc, o.name_span), Location(nsrc, n.name_span)
    ko, kn = _kind(o), _kind(n)
    if isinstance(o, m.Struct) and isinstance(n, m.Struct):
        ko, kn = o.kind, n.kind
    if ko != kn:
        sev = I if {ko, kn} <= _SAME_KIND else E
        ctx.add("definition-kind-changed", q, f"'{q}' changed from {ko} to {kn}", oloc, nloc, severity=sev,
                usage=usage, breaks="peers built against OLD expect a " + ko if sev == E else "")
        if type(o) is not type(n):
            return
    if isinstance(o, m.Struct):
        assert isinstance(n, m.Struct)
        compare_fields(ctx, q, Body(o.fields, osrc, o.name_span, o.span), Body(n.fields, nsrc, n.name_span, n.span),
                       dirs, usage)
        compare_consts(ctx, q, o.consts, osrc, n.consts, nsrc, n.name_span, usage)
    elif isinstance(o, m.Enum):
        assert isinstance(n, m.Enum)
        _enum(ctx, q, o, osrc, n, nsrc, dirs, usage)
    elif isinstance(o, m.Senum):
        assert isinstance(n, m.Senum)
        _senum(ctx, q, o, osrc, n, nsrc, dirs, usage)
    elif isinstance(o, m.Typedef):
        assert isinstance(n, m.Typedef)
        to, tn = ctx.old.type_key(o.type), ctx.new.type_key(n.type)
        if to != tn:
            ctx.add("typedef-changed", q, f"typedef '{q}' now stands for {tn} instead of {to}", oloc, nloc,
                    usage=usage, breaks="every field of this type changes its wire type")
    elif isinstance(o, m.Const):
        assert isinstance(n, m.Const)
        _const(ctx, q, o, osrc, n, nsrc, usage)
    elif isinstance(o, m.Service):
        assert isinstance(n, m.Service)
        _service(ctx, q, o, osrc, n, nsrc, dirs, usage)
    elif isinstance(o, m.Action):
        assert isinstance(n, m.Action)
        flipped = {flip(x) for x in dirs}
        for part, pdirs in (("goal", dirs), ("result", flipped), ("feedback", flipped)):
            _section(ctx, f"{q}.{part}", getattr(o, part), osrc, o, getattr(n, part), nsrc, n, pdirs, usage)
        compare_consts(ctx, q, o.consts, osrc, n.consts, nsrc, n.name_span, usage)


def compare_consts(ctx: Context, label: str, old: Iterable[m.Const], osrc: Source, new: Iterable[m.Const],
                   nsrc: Source, anchor: Span, usage: set[str]) -> None:
    """Constants inside a body, by name."""
    by_old = {c.name: c for c in old}
    by_new = {c.name: c for c in new}
    for name in sorted(set(by_old) | set(by_new)):
        o, n = by_old.get(name), by_new.get(name)
        q = f"{label}.{name}"
        if o is not None and n is not None:
            _const(ctx, q, o, osrc, n, nsrc, usage)
        elif o is not None:
            ctx.add("const-removed", q, f"constant '{q}' was removed", Location(osrc, o.name_span),
                    Location(nsrc, anchor), usage=usage)
        elif n is not None:
            ctx.add("const-added", q, f"new constant '{q}'", Location(osrc, anchor), Location(nsrc, n.name_span),
                    usage=usage)


def _const(ctx: Context, q: str, o: m.Const, osrc: Source, n: m.Const, nsrc: Source, usage: set[str]) -> None:
    oloc, nloc = Location(osrc, o.name_span), Location(nsrc, n.name_span)
    to, tn = ctx.old.type_key(o.type), ctx.new.type_key(n.type)
    if to != tn:
        ctx.add("const-type-changed", q, f"constant '{q}' changed type {to} → {tn}", oloc, nloc, usage=usage)
    elif value_key(o.value) != value_key(n.value):
        ctx.add("const-value-changed", q, f"constant '{q}' changed value {value_text(o.value)} → "
                f"{value_text(n.value)}", oloc, nloc, usage=usage)


def _enum(ctx: Context, q: str, o: m.Enum, osrc: Source, n: m.Enum, nsrc: Source, dirs: set[str],
          usage: set[str]) -> None:
    by_new: dict[int, m.EnumValue] = {}
    for v in n.values:
        by_new.setdefault(v.value, v)
    by_old: dict[int, m.EnumValue] = {}
    for v in o.values:
        by_old.setdefault(v.value, v)
    for num in sorted(set(by_old) | set(by_new)):
        a, b = by_old.get(num), by_new.get(num)
        if a is not None and b is not None:
            if a.name != b.name:
                ctx.add("enum-value-renamed", f"{q}.{a.name}", f"value {num} of enum '{q}' renamed "
                        f"'{a.name}' → '{b.name}'", Location(osrc, a.span), Location(nsrc, b.span), usage=usage)
        elif a is not None:
            sev = by_direction(dirs, send=I, receive=E)
            text = osrc.text[a.span.start:a.span.end]
            ctx.add("enum-value-removed", f"{q}.{a.name}", f"value {num} ('{a.name}') of enum '{q}' was removed",
                    Location(osrc, a.span), Location(nsrc, n.name_span), severity=sev, usage=usage,
                    breaks="senders built against OLD may still send it" if sev == E else "",
                    fix=_restore_member(nsrc, n.span, text))
        elif b is not None:
            sev = W if dirs == {SEND} else I
            ctx.add("enum-value-added", f"{q}.{b.name}", f"new value {num} ('{b.name}') of enum '{q}'",
                    Location(osrc, o.name_span), Location(nsrc, b.span), severity=sev, usage=usage,
                    breaks="receivers built against OLD may not know it" if sev == W else "")


def _senum(ctx: Context, q: str, o: m.Senum, osrc: Source, n: m.Senum, nsrc: Source, dirs: set[str],
           usage: set[str]) -> None:
    new_values = {str(v.value): v for v in n.values}
    old_values = {str(v.value): v for v in o.values}
    for text, v in old_values.items():
        if text not in new_values:
            sev = by_direction(dirs, send=I, receive=E)
            ctx.add("enum-value-removed", f"{q}.{text}", f"value \"{text}\" of senum '{q}' was removed",
                    Location(osrc, v.span), Location(nsrc, n.name_span), severity=sev, usage=usage)
    for text, v in new_values.items():
        if text not in old_values:
            ctx.add("enum-value-added", f"{q}.{text}", f"new value \"{text}\" of senum '{q}'",
                    Location(osrc, o.name_span), Location(nsrc, v.span), usage=usage)


def _restore_member(src: Source, container: Span, text: str) -> dict | None:
    close = src.text.rfind("}", container.start, container.end)
    if close < 0:
        return None
    return {"kind": "restore", "text": text, "edits": [{"start": close, "end": close, "text": f"  {text}\n"}]}


def _section(ctx: Context, label: str, o: m.Section | None, osrc: Source, odef: m.Definition,
             n: m.Section | None, nsrc: Source, ndef: m.Definition, dirs: set[str], usage: set[str]) -> None:
    ob = Body(o.fields if o else [], osrc, o.span if o and not o.implicit else odef.name_span)
    nb = Body(n.fields if n else [], nsrc, n.span if n and not n.implicit else ndef.name_span,
              n.span if n is not None and not n.implicit else None)
    compare_fields(ctx, label, ob, nb, dirs, usage)


def _service(ctx: Context, q: str, o: m.Service, osrc: Source, n: m.Service, nsrc: Source, dirs: set[str],
             usage: set[str]) -> None:
    oloc, nloc = Location(osrc, o.name_span), Location(nsrc, n.name_span)
    fo, fn_ = service_form(o), service_form(n)
    if "empty" not in (fo, fn_) and fo != fn_:
        ctx.add("service-form-changed", q, f"service '{q}' changed from {fo} to {fn_}", oloc, nloc, usage=usage,
                breaks="peers built against OLD use the other form")
        return
    eo = ctx.old.type_key(o.extends) if o.extends is not None else None
    en = ctx.new.type_key(n.extends) if n.extends is not None else None
    if eo is not None and eo != en:
        ctx.add("extends-changed", q, f"service '{q}' extends {en or 'nothing'} instead of {eo}", oloc, nloc,
                usage=usage, breaks="callers of the inherited functions")
    elif eo is None and en is not None:
        ctx.add("extends-added", q, f"service '{q}' now extends {en}", oloc, nloc, usage=usage)
    if "functions" in (fo, fn_):
        _functions(ctx, q, o, osrc, n, nsrc, dirs, usage)
    else:
        flipped = {flip(x) for x in dirs}
        _section(ctx, f"{q}.request", o.request, osrc, o, n.request, nsrc, n, dirs, usage)
        _section(ctx, f"{q}.response", o.response, osrc, o, n.response, nsrc, n, flipped, usage)
    compare_consts(ctx, q, o.consts, osrc, n.consts, nsrc, n.name_span, usage)


def _functions(ctx: Context, q: str, o: m.Service, osrc: Source, n: m.Service, nsrc: Source, dirs: set[str],
               usage: set[str]) -> None:
    by_new = {f.name: f for f in n.functions}
    by_old = {f.name: f for f in o.functions}
    flipped = {flip(x) for x in dirs}
    for name in sorted(set(by_old) | set(by_new)):
        a, b = by_old.get(name), by_new.get(name)
        subject = f"{q}.{name}"
        if a is not None and b is not None:
            oloc, nloc = Location(osrc, a.name_span), Location(nsrc, b.name_span)
            if a.oneway != b.oneway:
                ctx.add("oneway-changed", subject, f"function '{subject}' {'became' if b.oneway else 'is no longer'} "
                        "oneway", oloc, nloc, usage=usage, breaks="callers built against OLD wait for a reply "
                        "that never comes, or never read one that is sent")
            ro, rn = ctx.old.type_key(a.returns), ctx.new.type_key(b.returns)
            if ro != rn:
                ctx.add("return-type-changed", subject, f"function '{subject}' returns {rn} instead of {ro}",
                        oloc, nloc, usage=usage, breaks="callers built against OLD decode the old type")
            compare_fields(ctx, f"{subject}(args)", Body(a.params, osrc, a.name_span),
                           Body(b.params, nsrc, b.name_span), dirs, usage, what="argument")
            compare_fields(ctx, f"{subject}(throws)", Body(a.throws, osrc, a.name_span),
                           Body(b.throws, nsrc, b.name_span), flipped, usage, what="exception")
        elif a is not None:
            sev = by_direction(dirs, send=I, receive=E)
            text = osrc.text[a.span.start:a.span.end]
            ctx.add("function-removed", subject, f"function '{subject}' was removed", Location(osrc, a.name_span),
                    Location(nsrc, n.name_span), severity=sev, usage=usage,
                    breaks="callers built against OLD call it" if sev == E else "",
                    fix=_restore_member(nsrc, n.span, text))
        elif b is not None:
            sev = W if dirs == {SEND} else I
            ctx.add("function-added", subject, f"new function '{subject}'", Location(osrc, o.name_span),
                    Location(nsrc, b.name_span), severity=sev, usage=usage,
                    breaks="servers built against OLD do not provide it" if sev == W else "")


