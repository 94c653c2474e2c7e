"""The canonical form of an interface and its hash.

The canonical form holds what ``compare`` compares — names, types, structure,
ids, requiredness, defaults, constants, enum values, wiring with QoS, units and
ranges — and nothing else (no comments, layout, order of definitions, spelling
of aliases, component name or version). Two files hash alike exactly when
``compare`` finds them equivalent.
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

from ..model import nodes as m
from ..semantics.compile import Compilation
from .side import Side
from .values import value_key
from .parts import (
    definitions,
    diagnostics,
    endpoint_qos,
    endpoint_type,
    endpoints,
    namespaces,
    parameters,
    service_form,
    state,
)

HASH_PREFIX = "sha256:"


def _field(side: Side, f: m.Field) -> dict[str, Any]:
    return {"id": f.id, "name": f.name, "type": side.type_key(f.type), "req": f.requiredness or "default",
            "default": value_key(f.default), "unit": f.unit, "range": list(f.range) if f.range else None}


def _fields(side: Side, fields: list[m.Field]) -> list[dict[str, Any]]:
    keyed = bool(fields) and all(f.id is not None for f in fields)
    ordered = sorted(fields, key=lambda f: f.id or 0) if keyed else fields
    return [_field(side, f) for f in ordered]


def _consts(side: Side, consts: list[m.Const]) -> dict[str, Any]:
    return {c.name: [side.type_key(c.type), value_key(c.value)] for c in consts}


def _section(side: Side, sec: m.Section | None) -> list[dict[str, Any]]:
    return _fields(side, sec.fields) if sec is not None else []


def _definition(side: Side, d: m.Definition) -> dict[str, Any]:
    if isinstance(d, m.Struct):
        return {"kind": d.kind, "fields": _fields(side, d.fields), "consts": _consts(side, d.consts)}
    if isinstance(d, m.Enum):
        values: dict[int, str] = {}
        for v in d.values:
            values.setdefault(v.value, v.name)
        return {"kind": "enum", "values": [[k, values[k]] for k in sorted(values)]}
    if isinstance(d, m.Senum):
        return {"kind": "senum", "values": sorted({str(v.value) for v in d.values})}
    if isinstance(d, m.Typedef):
        return {"kind": "typedef", "type": side.type_key(d.type)}
    if isinstance(d, m.Const):
        return {"kind": "const", "type": side.type_key(d.type), "value": value_key(d.value)}
    if isinstance(d, m.Service):
        out: dict[str, Any] = {"kind": "service", "form": service_form(d),
                               "extends": side.type_key(d.extends) if d.extends is not None else None,
                               "consts": _consts(side, d.consts)}
        if d.form == "functions":
            out["functions"] = {
                fn.name: {"oneway": fn.oneway, "returns": side.type_key(fn.returns),
                          "args": _fields(side, fn.params), "throws": _fields(side, fn.throws)}
                for fn in d.functions}
        else:
            out["request"] = _section(side, d.request)
            out["response"] = _section(side, d.response)
        return out
    assert isinstance(d, m.Action)
    return {"kind": "action", "goal": _section(side, d.goal), "result": _section(side, d.result),
            "feedback": _section(side, d.feedback), "consts": _consts(side, d.consts)}


canonical_definition = _definition


def wire_form(side: Side, d: m.Definition) -> dict[str, Any]:
    """What a definition is on the wire, the same from every component that uses it: its canonical
    form and that of every definition it uses, keyed by identity (``package/Name``)."""
    from ..model.walk import named_types

    wire = side.wire()
    out: dict[str, Any] = {}
    stack = [d]
    while stack:
        x = stack.pop()
        key = side.identity(x)
        if key in out:
            continue
        if x is not d and isinstance(x, m.Struct) and x.fields and all(f.id is not None for f in x.fields):
            out[key] = {"kind": x.kind, "keyed": True}  # Thrift-style ids: readers may know a subset (compat)
            continue
        out[key] = _definition(wire, x)
        for t in _types_in(x):
            stack.extend(n.target for n in named_types(t) if n.target is not None)
    return out


def _types_in(d: m.Definition) -> list[m.TypeRef]:
    """Every type written in a definition (fields, parts, functions, typedef, extends)."""
    from ..model.walk import bodies

    out: list[m.TypeRef] = []
    if isinstance(d, (m.Typedef, m.Const)):
        out.append(d.type)
    if isinstance(d, m.Service):
        if d.extends is not None:
            out.append(d.extends)
        for fn in d.functions:
            out += [f.type for f in (*fn.params, *fn.throws)] + ([fn.returns] if fn.returns else [])
    for _, fields, consts in bodies(d):
        out += [f.type for f in fields] + [c.type for c in consts]
    return out


def _setting(side: Side, f: m.Field) -> dict[str, Any]:
    return {"type": side.type_key(f.type), "default": value_key(f.default), "unit": f.unit,
            "range": list(f.range) if f.range else None}


def canonical(comp: Compilation) -> dict[str, Any]:
    """The canonical form of a compiled interface, as plain JSON data."""
    side = Side(comp)
    eps = endpoints(side)
    return {
        "namespaces": {scope: ns.name for scope, ns in namespaces(side).items()},
        "endpoints": sorted([kind, role, name, endpoint_type(side, ep), endpoint_qos(ep)]
                            for (kind, role, name), ep in eps.items()),
        "parameters": {name: _setting(side, f) for name, f in parameters(side).items()},
        "state": {name: {"type": side.type_key(f.type), "default": value_key(f.default)}
                  for name, f in state(side).items()},
        "diagnostics": sorted([name, endpoint_type(side, ep)] for name, ep in diagnostics(side).items()),
        "definitions": {q: _definition(side, d) for q, (d, _) in definitions(side).items()},
    }


def canonical_text(comp: Compilation) -> str:
    """The canonical form as compact JSON with sorted keys."""
    return json.dumps(canonical(comp), sort_keys=True, separators=(",", ":"), ensure_ascii=False)


def interface_hash(comp: Compilation) -> str:
    """``sha256:<hex>`` of the canonical form."""
    return HASH_PREFIX + hashlib.sha256(canonical_text(comp).encode("utf-8")).hexdigest()


def first_difference(a: Any, b: Any, path: str = "") -> str | None:
    """The path of the first place two canonical forms differ (None when equal)."""
    if type(a) is not type(b):
        return path or "/"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}/{k}"
            found = first_difference(a[k], b[k], f"{path}/{k}")
            if found:
                return found
        return None
    if isinstance(a, list):
        for i, (x, y) in enumerate(zip(a, b)):
            found = first_difference(x, y, f"{path}/{i}")
            if found:
                return found
        return None if len(a) == len(b) else f"{path}/{min(len(a), len(b))}"
    return None if a == b else (path or "/")
