"""The document view of an interface: the seven sets, the contract and every type, as rows of raw text."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

from ...model import nodes as m
from ...model.normalize import flat_reading
from ...model.walk import type_text


@dataclass(slots=True)
class Table:
    """A titled table: header cells and rows of raw (unescaped) cells, each ``(text, is_code)``."""

    title: str
    header: list[str]
    rows: list[list[tuple[str, bool]]] = field(default_factory=list)
    doc: str = ""
    note: str = ""


@dataclass(slots=True)
class Section:
    """A type's section: kind, name, doc and its tables."""

    kind: str
    name: str
    doc: str
    tables: list[Table] = field(default_factory=list)
    note: str = ""
    signature: str = ""


def value_text(v: m.Value | None) -> str:
    """A value as written in the interface (strings quoted)."""
    if v is None:
        return ""
    if v.kind == "string":
        return json.dumps(v.value, ensure_ascii=False)
    if v.kind == "list":
        return "[" + ", ".join(value_text(x) for x in v.value) + "]"
    if v.kind == "map":
        return "{" + ", ".join(f"{value_text(k)}: {value_text(x)}" for k, x in v.value) + "}"
    return v.text or str(v.value)


def range_text(f: m.Field) -> str:
    """``lo..hi`` from a field's range annotations."""
    rng = f.range
    if rng is None:
        return ""
    lo, hi = rng

    def show(x: float | None) -> str:
        return "" if x is None else (str(int(x)) if float(x).is_integer() else repr(x))
    return f"{show(lo)}..{show(hi)}"


def fields_table(title: str, fields: list[m.Field], consts: list[m.Const] | None = None) -> Table:
    """A table of fields (id, name, type, default, unit/range, doc)."""
    t = Table(title, ["Id", "Field", "Type", "Default", "Unit / range", "Description"])
    for f in fields:
        unit = " ".join(x for x in (f.unit or "", range_text(f)) if x)
        req = f"{f.requiredness} " if f.requiredness else ""
        t.rows.append([(str(f.id) if f.id is not None else "", False), (f.name, True),
                       (req + type_text(f.type), True), (value_text(f.default), True), (unit, False),
                       (f.doc or "", False)])
    for c in consts or []:
        t.rows.append([("const", False), (c.name, True), (type_text(c.type), True), (value_text(c.value), True),
                       ("", False), (c.doc or "", False)])
    return t


def part_table(title: str, sec: m.Section | None) -> Table:
    """The table of a service or action part (fields, then constants), with the part's own doc comment."""
    t = fields_table(title, sec.fields if sec else [], sec.consts if sec else [])
    t.doc = (sec.doc if sec else None) or ""
    return t


def parts_text(sec: m.Section | None) -> str:
    """The fields of a section as ``name: type, …``."""
    if sec is None or not sec.fields:
        return "—"
    return ", ".join(f"{f.name}: {type_text(f.type)}" for f in sec.fields)


def endpoint_rows(eps: list[m.Endpoint]) -> list[list[tuple[str, bool]]]:
    """Rows of topic endpoints: topic, type, QoS, doc."""
    rows = []
    for ep in eps:
        w = ep.wiring
        qos = ", ".join(f"{k}={v}" for k, v in sorted(w.qos.items())) if w else ""
        type_name = w.type.name if w else getattr(ep.definition, "name", "")
        rows.append([(ep.name, True), (type_name, True), (qos, False), ((w.doc if w else None) or "", False)])
    return rows


def call_rows(eps: list[m.Endpoint], parts: tuple[str, ...]) -> list[list[tuple[str, bool]]]:
    """Rows of services or actions: name, type, role, then each part's fields."""
    rows = []
    for ep in eps:
        d = ep.definition
        type_name = ep.wiring.type.name if ep.wiring else getattr(d, "name", "")
        cells: list[tuple[str, bool]] = [(ep.name, True), (type_name, True), (ep.role, False)]
        for p in parts:
            if isinstance(d, m.Service) and d.form == "functions":
                cells.append((", ".join(fn.name for fn in d.functions) if p == "request" else "—", False))
            else:
                cells.append((parts_text(getattr(d, p, None)), False))
        rows.append(cells)
    return rows


def contract_item(x: m.Endpoint | m.Field | m.Service) -> tuple[str, str]:
    """(what, name) of an element of the assumptions or guarantees."""
    if isinstance(x, m.Endpoint):
        type_name = x.wiring.type.name if x.wiring else getattr(x.definition, "name", "")
        return f"{x.role} {type_name} on", x.name
    if isinstance(x, m.Field):
        return f"parameter {type_text(x.type)}", x.name
    return "diagnostics service", x.name


def type_sections(iface: m.Interface) -> list[Section]:
    """A section per definition, in the order of the file."""
    out: list[Section] = []
    for d in iface.definitions:
        if isinstance(d, m.Struct):
            s = Section(d.kind, d.name, d.doc or "")
            s.tables.append(fields_table("", d.fields, d.consts))
            out.append(s)
        elif isinstance(d, m.Service):
            s = Section("service", d.name, d.doc or "")
            if d.form == "functions":
                for fn in d.functions:
                    ret = type_text(fn.returns) if fn.returns is not None else "void"
                    t = fields_table(f"{'oneway ' if fn.oneway else ''}{fn.name}() → {ret}", fn.params)
                    t.doc = fn.doc or ""
                    s.tables.append(t)
            else:
                s.tables.append(part_table("Request", d.request))
                s.tables.append(part_table("Response", d.response))
                if d.form == "flat":
                    s.note = "Written as plain fields, read as " + flat_reading(d) + "."
            if d.consts:
                s.tables.append(fields_table("Constants", [], d.consts))
            out.append(s)
        elif isinstance(d, m.Action):
            s = Section("action", d.name, d.doc or "")
            for part in ("goal", "result", "feedback"):
                s.tables.append(part_table(part.capitalize(), getattr(d, part)))
            if d.form == "flat":
                s.note = "Written as plain fields, read as " + flat_reading(d) + "."
            out.append(s)
        elif isinstance(d, m.Enum):
            s = Section("enum", d.name, d.doc or "")
            t = Table("", ["Name", "Value", "Description"])
            t.rows = [[(v.name, True), (str(v.value), False), (v.doc or "", False)] for v in d.values]
            s.tables.append(t)
            out.append(s)
        elif isinstance(d, m.Senum):
            s = Section("senum", d.name, d.doc or "")
            t = Table("", ["Value"])
            t.rows = [[(value_text(v), True)] for v in d.values]
            s.tables.append(t)
            out.append(s)
        elif isinstance(d, m.Typedef):
            out.append(Section("typedef", d.name, d.doc or "", signature=f"typedef {type_text(d.type)} {d.name}"))
        elif isinstance(d, m.Const):
            out.append(Section("const", d.name, d.doc or "",
                               signature=f"const {type_text(d.type)} {d.name} = {value_text(d.value)}"))
    return out
