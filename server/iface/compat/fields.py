"""Field lists: struct bodies, service and action sections, arguments and exceptions.

Bodies whose fields all carry ids are matched by id (Thrift); others by name and
position (ROS 2), where any change of order, type, name or count changes the
wire format and the ROS 2 type hash.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

from ..model import nodes as m
from ..model.diagnostics import Severity
from ..model.source import Source, Span
from ..model.walk import type_text
from .context import Context, by_direction
from .findings import Location
from .side import RECEIVE, SEND
from .values import value_key, value_text

E, W, I = Severity.ERROR, Severity.WARNING, Severity.INFORMATION


@dataclass
class Body:
    """A field list on one side: its fields, where it is, and the span a restored field goes in."""

    fields: list[m.Field]
    source: Source
    anchor: Span
    container: Span | None = None


def _req(f: m.Field) -> bool:
    return f.requiredness == "required"


def _restore_fix(f: m.Field, old_src: Source, body: Body) -> dict | None:
    """A fix that puts the removed field back before the closing brace of NEW's body."""
    if body.container is None:
        return None
    text = body.source.text
    close = text.rfind("}", body.container.start, body.container.end)
    if close < 0:
        return None
    line_start = text.rfind("\n", 0, close) + 1
    indent = "    " if text[line_start:close].strip() == "" else ""
    field_text = old_src.text[f.span.start:f.span.end]
    insert = f"{indent}{field_text}\n" if indent else f" {field_text} "
    at = line_start if indent else close
    return {"kind": "restore", "field": f.name, "text": field_text,
            "edits": [{"start": at, "end": at, "text": insert}]}


def _make_optional_fix(f: m.Field, src: Source) -> dict | None:
    """Replace ``required`` by ``optional`` in NEW's field."""
    text = src.text[f.span.start:f.span.end]
    i = text.find("required")
    if i < 0:
        return None
    at = f.span.start + i
    return {"kind": "make-optional", "field": f.name,
            "edits": [{"start": at, "end": at + len("required"), "text": "optional"}]}


def compare_fields(ctx: Context, label: str, old: Body, new: Body, dirs: set[str], usage: set[str],
                   what: str = "field") -> None:
    """Compare two field lists of one body flowing in ``dirs``."""
    keyed_old = bool(old.fields) and all(f.id is not None for f in old.fields)
    keyed_new = bool(new.fields) and all(f.id is not None for f in new.fields)
    if old.fields and new.fields and keyed_old != keyed_new:
        ctx.add("field-keying-changed", label,
                f"'{label}' {'lost' if keyed_old else 'gained'} its field ids: the wire format changes",
                Location(old.source, old.anchor), Location(new.source, new.anchor), usage=usage,
                breaks="peers built against OLD decode the body differently")
        _positional(ctx, label, old, new, dirs, usage, what)
        return
    if keyed_old or keyed_new:
        _keyed(ctx, label, old, new, dirs, usage, what)
    else:
        _positional(ctx, label, old, new, dirs, usage, what)


def _keyed(ctx: Context, label: str, old: Body, new: Body, dirs: set[str], usage: set[str], what: str) -> None:
    by_old = {f.id: f for f in old.fields}
    by_new = {f.id: f for f in new.fields}
    top = max((i for i in by_old if i is not None), default=None)
    for fid in sorted(set(by_old) | set(by_new), key=lambda x: x or 0):
        o, n = by_old.get(fid), by_new.get(fid)
        if o is not None and n is not None:
            compare_field(ctx, label, o, n, old.source, new.source, dirs, usage, positional=False, what=what)
        elif o is not None:
            _removed(ctx, label, o, old, new, dirs, usage, what, positional=False)
        elif n is not None:
            subject = f"{label}.{n.name}"
            oloc = Location(old.source, old.anchor)
            nloc = Location(new.source, n.span)
            if top is not None and fid is not None and fid < top:
                ctx.add("field-id-inserted", subject,
                        f"{what} '{n.name}' takes id {fid}, below the highest old id {top} of '{label}'"
                        " (added in the middle: the id may have meant something else before)",
                        oloc, nloc, usage=usage, breaks="peers that still use the old meaning of the id")
            elif _req(n):
                sev = by_direction(dirs, send=I, receive=E)
                ctx.add("required-field-added", subject,
                        f"new required {what} '{n.name}' (id {fid}) in '{label}'", oloc, nloc, severity=sev,
                        usage=usage, breaks="senders built against OLD do not fill it" if sev == E else "",
                        fix=_make_optional_fix(n, new.source) if sev == E else None)
            else:
                ctx.add("field-added", subject, f"new optional {what} '{n.name}' (id {fid}) in '{label}'",
                        oloc, nloc, usage=usage)


def _removed(ctx: Context, label: str, o: m.Field, old: Body, new: Body, dirs: set[str], usage: set[str],
             what: str, positional: bool) -> None:
    subject = f"{label}.{o.name}"
    ident = f" (id {o.id})" if o.id is not None else ""
    oloc, nloc = Location(old.source, o.span), Location(new.source, new.anchor)
    if positional:
        sev, breaks = E, "the wire layout and the ROS 2 type hash change: peers built against OLD no longer match"
    elif dirs == {SEND}:
        sev = E if _req(o) else W
        breaks = "receivers built against OLD rely on it" if sev == E else "receivers no longer get it (it was optional)"
    elif dirs == {RECEIVE}:
        sev, breaks = I, ""
    else:
        sev, breaks = E, "peers built against OLD send or read it"
    ctx.add("field-removed", subject, f"{what} '{o.name}'{ident} of '{label}' was removed", oloc, nloc,
            severity=sev, usage=usage, breaks=breaks, fix=_restore_fix(o, old.source, new))


def _lis(seq: list[int]) -> set[int]:
    """Indices (into ``seq``) of one longest increasing subsequence."""
    tails: list[int] = []
    prev = [-1] * len(seq)
    tails_idx: list[int] = []
    for i, x in enumerate(seq):
        j = bisect.bisect_left(tails, x)
        if j == len(tails):
            tails.append(x)
            tails_idx.append(i)
        else:
            tails[j] = x
            tails_idx[j] = i
        prev[i] = tails_idx[j - 1] if j > 0 else -1
    out: set[int] = set()
    k = tails_idx[-1] if tails_idx else -1
    while k >= 0:
        out.add(k)
        k = prev[k]
    return out


def _positional(ctx: Context, label: str, old: Body, new: Body, dirs: set[str], usage: set[str], what: str) -> None:
    onames = [f.name for f in old.fields]
    nnames = [f.name for f in new.fields]
    renamed: dict[str, str] = {}
    if len(onames) == len(nnames):
        for a, b in zip(onames, nnames):
            if a != b and a not in nnames and b not in onames:
                renamed[a] = b
    by_new = {f.name: f for f in new.fields}
    common_old = [f for f in old.fields if f.name in by_new or f.name in renamed]
    for o in old.fields:
        if o.name not in by_new and o.name not in renamed:
            _removed(ctx, label, o, old, new, dirs, usage, what, positional=True)
    matched = {renamed.get(f.name, f.name) for f in common_old}
    for n in new.fields:
        if n.name not in matched:
            ctx.add("field-added", f"{label}.{n.name}",
                    f"new {what} '{n.name}' in '{label}', which has no field ids: the wire layout changes",
                    Location(old.source, old.anchor), Location(new.source, n.span), severity=E, usage=usage,
                    breaks="peers built against OLD no longer match (ROS 2 needs equal types)")
    order = [nnames.index(renamed.get(f.name, f.name)) for f in common_old]
    keep = _lis(order)
    for i, o in enumerate(common_old):
        n = by_new[renamed.get(o.name, o.name)]
        if i not in keep:
            ctx.add("field-moved", f"{label}.{o.name}",
                    f"{what} '{o.name}' of '{label}' moved from position {onames.index(o.name) + 1} "
                    f"to {nnames.index(n.name) + 1}: the wire layout changes",
                    Location(old.source, o.span), Location(new.source, n.span), usage=usage,
                    breaks="peers built against OLD read the fields in the old order")
        compare_field(ctx, label, o, n, old.source, new.source, dirs, usage, positional=True, what=what)


def compare_field(ctx: Context, label: str, o: m.Field, n: m.Field, osrc: Source, nsrc: Source,
                  dirs: set[str], usage: set[str], *, positional: bool, what: str = "field") -> None:
    """Compare one field matched on both sides."""
    subject = f"{label}.{o.name}"
    oloc, nloc = Location(osrc, o.span), Location(nsrc, n.span)
    ident = f" (id {o.id})" if o.id is not None and not positional else ""
    if o.name != n.name:
        if positional:
            ctx.add("field-renamed", subject, f"{what} '{o.name}' of '{label}' is now '{n.name}': "
                    "the ROS 2 type hash changes", oloc, nloc, severity=E, usage=usage,
                    breaks="ROS 2 peers built against OLD no longer match")
        else:
            ctx.add("field-renamed", subject, f"{what}{ident} of '{label}' renamed '{o.name}' → '{n.name}'",
                    oloc, nloc, usage=usage)
    ot, nt = ctx.old.type_key(o.type), ctx.new.type_key(n.type)
    if ot != nt:
        ctx.add("field-type-changed", subject,
                f"{what} '{o.name}'{ident} of '{label}' changed type {type_text(o.type)} → {type_text(n.type)}",
                oloc, nloc, usage=usage, breaks="peers built against OLD encode or decode it as the old type")
    _requiredness(ctx, label, subject, o, n, nsrc, oloc, nloc, dirs, usage, what)
    if value_key(o.default) != value_key(n.default):
        ctx.add("default-changed", subject, f"default of {what} '{o.name}' of '{label}' changed "
                f"{value_text(o.default)} → {value_text(n.default)}", oloc, nloc, usage=usage)
    compare_unit_range(ctx, subject, f"{what} '{o.name}' of '{label}'", o, n, oloc, nloc, dirs, usage)


def _requiredness(ctx: Context, label: str, subject: str, o: m.Field, n: m.Field, nsrc: Source,
                  oloc: Location, nloc: Location, dirs: set[str], usage: set[str], what: str) -> None:
    if _req(o) == _req(n):
        if o.requiredness != n.requiredness:
            ctx.add("field-optionality-changed", subject, f"{what} '{o.name}' of '{label}' changed from "
                    f"{o.requiredness or 'default'} to {n.requiredness or 'default'} requiredness",
                    oloc, nloc, usage=usage)
        return
    if _req(n):
        sev = by_direction(dirs, send=I, receive=E)
        ctx.add("field-requiredness-changed", subject, f"{what} '{o.name}' of '{label}' became required",
                oloc, nloc, severity=sev, usage=usage,
                breaks="senders built against OLD may leave it out" if sev == E else "",
                fix=_make_optional_fix(n, nsrc) if sev == E else None)
    else:
        sev = by_direction(dirs, send=E, receive=I)
        ctx.add("field-requiredness-changed", subject, f"{what} '{o.name}' of '{label}' is no longer required",
                oloc, nloc, severity=sev, usage=usage,
                breaks="receivers built against OLD rely on it being set" if sev == E else "")


def compare_unit_range(ctx: Context, subject: str, what: str, o: m.Field, n: m.Field, oloc: Location,
                       nloc: Location, dirs: set[str], usage: set[str]) -> None:
    """Unit and range annotations: a unit must not change; a range may widen where data is received."""
    if o.unit != n.unit:
        sev = E if o.unit and n.unit else W
        ctx.add("unit-changed", subject, f"unit of {what} changed {o.unit or 'none'} → {n.unit or 'none'}",
                oloc, nloc, severity=sev, usage=usage,
                breaks="peers built against OLD use the old unit" if sev == E else "")
    ro, rn = o.range, n.range
    if ro == rn:
        return
    lo_o, hi_o = ro or (None, None)
    lo_n, hi_n = rn or (None, None)
    inf = float("inf")
    narrowed = (lo_n if lo_n is not None else -inf) > (lo_o if lo_o is not None else -inf) or \
               (hi_n if hi_n is not None else inf) < (hi_o if hi_o is not None else inf)
    widened = (lo_n if lo_n is not None else -inf) < (lo_o if lo_o is not None else -inf) or \
              (hi_n if hi_n is not None else inf) > (hi_o if hi_o is not None else inf)
    show = f"{_range(ro)} → {_range(rn)}"
    if narrowed:
        sev = by_direction(dirs, send=I, receive=E)
        ctx.add("range-narrowed", subject, f"range of {what} narrowed {show}", oloc, nloc, severity=sev,
                usage=usage, breaks="values valid before are now rejected" if sev == E else "")
    if widened:
        sev = by_direction(dirs, send=E, receive=I)
        ctx.add("range-widened", subject, f"range of {what} widened {show}", oloc, nloc, severity=sev,
                usage=usage, breaks="receivers built against OLD may get values outside the old range"
                if sev == E else "")


def _range(r: tuple[float | None, float | None] | None) -> str:
    if r is None:
        return "none"
    lo, hi = r
    return f"{'' if lo is None else f'{lo:g}'}..{'' if hi is None else f'{hi:g}'}"
