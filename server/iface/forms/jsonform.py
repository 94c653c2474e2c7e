"""The JSON form of an interface, and back.

``to_json`` writes everything a compiled file says, in a fixed key order: the
header (component, includes, namespaces, externals), every item in source
order with its types, fields, defaults, annotations and docs, and the seven
derived sets I = M ∪ N ∪ S ∪ A ∪ P ∪ Σ ∪ Δ. Spans are left out. ``from_json``
rebuilds the items (the sets are derived again when the text is compiled), and
``canonical`` is the comparable form: two models are equal when their
canonical forms are.

The schema of the form is ``forms/iface.schema.json`` (draft 2020-12).
"""

from __future__ import annotations

from collections.abc import Iterable
from importlib.resources import files
from pathlib import Path
from typing import Any

from ..model import nodes as m
from ..model.normalize import flat_order, normalize_action, normalize_service
from ..model.source import Span

#: The version of the JSON form; bumped when its meaning changes.
FORMAT = "iface-json/1"


def schema_text() -> str:
    """The JSON Schema of the form, as shipped with the package."""
    return files(__package__ or "iface.forms").joinpath("iface.schema.json").read_text(encoding="utf-8")


class FormError(ValueError):
    """A JSON document that is not the iface JSON form; ``where`` is a JSON pointer."""

    def __init__(self, where: str, message: str) -> None:
        super().__init__(f"{where or '/'}: {message}")
        self.where = where


# ---------------------------------------------------------------------------
# model → JSON


def to_json(iface: m.Interface) -> dict[str, Any]:
    """The JSON form of a compiled interface (a plain dict, keys in a fixed order).

    The forms of the files it includes are embedded under ``included``, each with the
    include path as written, so that one document holds everything its types need.
    """
    return _form(iface, frozenset())


def _included(iface: m.Interface, seen: frozenset[str]) -> list[dict[str, Any]]:
    """The embedded forms of the files ``iface`` includes (each include once, cycles cut)."""
    by_path = {x.path: x for x in iface.included.values()}
    out: list[dict[str, Any]] = []
    written: set[str] = set()
    for inc in iface.includes:
        target = by_path.get(inc.resolved or "")
        if target is None or inc.path in written or target.path in seen:
            continue
        written.add(inc.path)
        out.append({"path": inc.path, "form": _form(target, seen | {iface.path})})
    return out


def _form(iface: m.Interface, seen: frozenset[str]) -> dict[str, Any]:
    return {
        "format": FORMAT,
        "file": Path(iface.path).name,
        "name": iface.name,
        "version": iface.version,
        "component": None if iface.component is None else _component(iface.component),
        "includes": [{"path": i.path, "cpp": i.cpp} for i in iface.includes],
        "namespaces": [{"scope": n.scope, "name": n.name} for n in iface.namespaces],
        "externals": [e.name for e in iface.externals],
        "items": [_item(x) for x in iface.items],
        "sets": _sets(iface),
        "included": _included(iface, seen),
    }


def canonical(iface: m.Interface) -> dict[str, Any]:
    """What two models must share to be equal: the JSON form without the file name."""
    out = to_json(iface)
    del out["file"]
    return out


def _component(c: m.ComponentDecl) -> dict[str, Any]:
    return {"name": c.name, "version": c.version, "annotations": _anns(c.annotations), "doc": c.doc}


def _anns(anns: Iterable[m.Annotation]) -> list[dict[str, Any]]:
    return [{"key": a.key, "value": None if a.value is None else _value(a.value)} for a in anns]


def _value(v: m.Value) -> dict[str, Any]:
    if v.kind == "list":
        inner: Any = [_value(x) for x in v.value]
    elif v.kind == "map":
        inner = [{"key": _value(k), "value": _value(x)} for k, x in v.value]
    else:
        inner = v.value
    out: dict[str, Any] = {"kind": v.kind, "value": inner}
    if v.kind not in ("list", "map"):
        out["text"] = v.text
    return out


def _type(t: m.TypeRef) -> dict[str, Any]:
    out: dict[str, Any]
    if isinstance(t, m.BaseType):
        out = {"kind": "base", "name": t.name, "spelling": t.spelling or t.name, "bound": t.bound}
    elif isinstance(t, m.NamedType):
        out = {"kind": "named", "name": t.name}
        if t.external is not None:
            out["external"] = t.external
        elif t.target is not None:
            out["refers_to"] = t.target.kind
    elif isinstance(t, m.ArrayType):
        out = {"kind": "array", "array": t.array, "size": t.size, "list": t.spelled_list,
               "element": _type(t.element)}
    elif isinstance(t, m.SetType):
        out = {"kind": "set", "element": _type(t.element)}
    else:
        out = {"kind": "map", "key": _type(t.key), "element": _type(t.element)}
    out["annotations"] = _anns(t.annotations)
    return out


def _field(f: m.Field) -> dict[str, Any]:
    return {
        "name": f.name,
        "id": f.id,
        "requiredness": f.requiredness,
        "type": _type(f.type),
        "reference": f.reference,
        "default": None if f.default is None else _value(f.default),
        "annotations": _anns(f.annotations),
        "doc": f.doc,
    }


def _const(c: m.Const) -> dict[str, Any]:
    return {"kind": "const", "name": c.name, "type": _type(c.type), "value": _value(c.value), "doc": c.doc}


def _body_consts(consts: list[m.Const], fields: list[m.Field]) -> list[dict[str, Any]]:
    """Constants of a body; one written after some fields says how many (``position``), so the order survives."""
    out = []
    for c in consts:
        item = _const(c)
        position = sum(1 for f in fields if f.span.start < c.span.start)
        if position:
            item["position"] = position
        out.append(item)
    return out


def _section(s: m.Section) -> dict[str, Any]:
    return {"name": s.name, "implicit": s.implicit, "doc": s.doc, "fields": [_field(f) for f in s.fields],
            "consts": _body_consts(s.consts, s.fields)}


def _function(fn: m.Function) -> dict[str, Any]:
    return {
        "name": fn.name,
        "oneway": fn.oneway,
        "returns": None if fn.returns is None else _type(fn.returns),
        "params": [_field(p) for p in fn.params],
        "throws": [_field(p) for p in fn.throws],
        "annotations": _anns(fn.annotations),
        "doc": fn.doc,
    }


def _parts(d: m.Service | m.Action) -> list[dict[str, Any]]:
    """Sections as written (explicit form) or as read from a flat body."""
    if d.form == "explicit":
        return [_section(s) for s in d.sections]
    names = ("request", "response") if isinstance(d, m.Service) else ("goal", "result", "feedback")
    return [_section(s) for s in (getattr(d, n) for n in names) if s is not None]


def _item(x: m.Item) -> dict[str, Any]:
    if isinstance(x, m.Include):
        return {"kind": "include", "path": x.path, "cpp": x.cpp}
    if isinstance(x, m.Namespace):
        return {"kind": "namespace", "scope": x.scope, "name": x.name, "annotations": _anns(x.annotations)}
    if isinstance(x, m.ComponentDecl):
        return {"kind": "component", **_component(x)}
    if isinstance(x, m.External):
        return {"kind": "external", "name": x.name}
    if isinstance(x, m.SystemDecl):
        return {"kind": "system", "name": x.name, "version": x.version, "annotations": _anns(x.annotations),
                "doc": x.doc}
    if isinstance(x, m.Instance):
        return {"kind": "instance", "name": x.name, "component": x.component, "annotations": _anns(x.annotations),
                "doc": x.doc}
    if isinstance(x, m.Wiring):
        return {"kind": "wiring", "direction": x.direction, "type": x.type.name, "topic": x.topic,
                "annotations": _anns(x.annotations), "doc": x.doc}
    if isinstance(x, m.Const):
        return _const(x)
    if isinstance(x, m.Typedef):
        return {"kind": "typedef", "name": x.name, "type": _type(x.type), "annotations": _anns(x.annotations),
                "doc": x.doc}
    if isinstance(x, m.Enum):
        return {"kind": "enum", "name": x.name,
                "values": [{"name": v.name, "value": v.value, "explicit": v.explicit,
                            "annotations": _anns(v.annotations), "doc": v.doc} for v in x.values],
                "annotations": _anns(x.annotations), "doc": x.doc}
    if isinstance(x, m.Senum):
        return {"kind": "senum", "name": x.name, "values": [_value(v) for v in x.values],
                "annotations": _anns(x.annotations), "doc": x.doc}
    if isinstance(x, m.Struct):
        return {"kind": x.kind, "name": x.name, "fields": [_field(f) for f in x.fields],
                "consts": _body_consts(x.consts, x.fields), "annotations": _anns(x.annotations), "doc": x.doc}
    if isinstance(x, m.Service):
        return {"kind": "service", "name": x.name, "form": x.form,
                "extends": None if x.extends is None else x.extends.name,
                "functions": [_function(fn) for fn in x.functions], "sections": _parts(x),
                "consts": [_const(c) for c in x.consts], "annotations": _anns(x.annotations), "doc": x.doc}
    return {"kind": "action", "name": x.name, "form": x.form, "sections": _parts(x),
            "consts": [_const(c) for c in x.consts], "annotations": _anns(x.annotations), "doc": x.doc}


def _endpoint(e: m.Endpoint) -> dict[str, Any]:
    return {"role": e.role, "name": e.name, "type": None if e.definition is None else e.definition.name,
            "wired": e.wiring is not None}


def _member_ref(owner: str, f: m.Field) -> dict[str, Any]:
    return {"owner": owner, "field": f.name}


def _sets(iface: m.Interface) -> dict[str, Any]:
    owners = {id(f): d.name for d in iface.definitions if isinstance(d, m.Struct) for f in d.fields}
    return {
        "subscribed": [_endpoint(e) for e in iface.subscribed],
        "published": [_endpoint(e) for e in iface.published],
        "services": [_endpoint(e) for e in iface.services],
        "actions": [_endpoint(e) for e in iface.actions],
        "parameters": [_member_ref(owners.get(id(f), ""), f) for f in iface.parameters],
        "state": [_member_ref(owners.get(id(f), ""), f) for f in iface.state],
        "diagnostics": [d.name for d in iface.diagnostics],
    }


# ---------------------------------------------------------------------------
# JSON → model


class _Reader:
    """Builds model items from the JSON form, reporting where a document is wrong."""

    def __init__(self) -> None:
        self.order = 0

    def span(self) -> Span:
        """A fresh span that orders members as they appear in the document."""
        self.order += 1
        return Span(self.order, self.order)

    @staticmethod
    def get(obj: Any, key: str, where: str, kinds: type | tuple[type, ...], *, optional: bool = False) -> Any:
        if not isinstance(obj, dict):
            raise FormError(where, "expected an object")
        if key not in obj or obj[key] is None:
            if optional:
                return None
            raise FormError(f"{where}/{key}", "missing")
        value = obj[key]
        if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in _as_tuple(kinds)):
            raise FormError(f"{where}/{key}", f"expected {_kind_names(kinds)}")
        return value

    def list_of(self, obj: Any, key: str, where: str) -> list[tuple[str, Any]]:
        items = self.get(obj, key, where, list, optional=True) or []
        return [(f"{where}/{key}/{i}", x) for i, x in enumerate(items)]

    # ---- values and types ------------------------------------------------------
    def value(self, obj: Any, where: str) -> m.Value:
        kind = self.get(obj, "kind", where, str)
        if kind == "list":
            items = [self.value(x, w) for w, x in self.list_of(obj, "value", where)]
            return m.Value("list", items, self.span())
        if kind == "map":
            pairs = [(self.value(self.get(x, "key", w, dict), f"{w}/key"),
                      self.value(self.get(x, "value", w, dict), f"{w}/value"))
                     for w, x in self.list_of(obj, "value", where)]
            return m.Value("map", pairs, self.span())
        expected: dict[str, type | tuple[type, ...]] = {"int": int, "double": (int, float), "string": str, "name": str}
        if kind not in expected:
            raise FormError(f"{where}/kind", f"unknown value kind '{kind}'")
        raw = self.get(obj, "value", where, expected[kind])
        if kind == "double":
            raw = float(raw)
        text = self.get(obj, "text", where, str, optional=True) or ""
        return m.Value(kind, raw, self.span(), text)

    def annotations(self, obj: Any, where: str) -> list[m.Annotation]:
        out = []
        for w, a in self.list_of(obj, "annotations", where):
            raw = a.get("value") if isinstance(a, dict) else None
            value = None if raw is None else self.value(raw, f"{w}/value")
            out.append(m.Annotation(self.get(a, "key", w, str), value, self.span()))
        return out

    def type(self, obj: Any, where: str) -> m.TypeRef:
        kind = self.get(obj, "kind", where, str)
        anns = self.annotations(obj, where)
        t: m.TypeRef
        if kind == "base":
            name = self.get(obj, "name", where, str)
            spelling = self.get(obj, "spelling", where, str, optional=True) or name
            if m.BASE_ALIASES.get(spelling) != name:
                raise FormError(f"{where}/spelling", f"'{spelling}' does not spell the base type '{name}'")
            t = m.BaseType(name, self.span(), spelling, self.get(obj, "bound", where, int, optional=True))
        elif kind == "named":
            t = m.NamedType(self.get(obj, "name", where, str), self.span())
        elif kind == "array":
            array = self.get(obj, "array", where, str)
            if array not in ("fixed", "bounded", "unbounded"):
                raise FormError(f"{where}/array", f"unknown array kind '{array}'")
            t = m.ArrayType(self.type(self.get(obj, "element", where, dict), f"{where}/element"), self.span(),
                            array, self.get(obj, "size", where, int, optional=True),
                            bool(self.get(obj, "list", where, bool, optional=True)))
        elif kind == "set":
            t = m.SetType(self.type(self.get(obj, "element", where, dict), f"{where}/element"), self.span())
        elif kind == "map":
            t = m.MapType(self.type(self.get(obj, "key", where, dict), f"{where}/key"),
                          self.type(self.get(obj, "element", where, dict), f"{where}/element"), self.span())
        else:
            raise FormError(f"{where}/kind", f"unknown type kind '{kind}'")
        t.annotations = anns
        return t

    # ---- members ---------------------------------------------------------------------
    def field(self, obj: Any, where: str) -> m.Field:
        default = self.get(obj, "default", where, dict, optional=True)
        req = self.get(obj, "requiredness", where, str, optional=True)
        if req not in (None, "required", "optional"):
            raise FormError(f"{where}/requiredness", f"unknown requiredness '{req}'")
        return m.Field(self.get(obj, "name", where, str), self.type(self.get(obj, "type", where, dict), f"{where}/type"),
                       self.span(), Span(0, 0), self.get(obj, "id", where, int, optional=True), None, req,
                       None if default is None else self.value(default, f"{where}/default"),
                       self.annotations(obj, where), self.get(obj, "doc", where, str, optional=True),
                       bool(self.get(obj, "reference", where, bool, optional=True)))

    def const(self, obj: Any, where: str) -> m.Const:
        return m.Const(self.get(obj, "name", where, str), self.type(self.get(obj, "type", where, dict), f"{where}/type"),
                       self.value(self.get(obj, "value", where, dict), f"{where}/value"), self.span(), Span(0, 0),
                       [], self.get(obj, "doc", where, str, optional=True))

    def members(self, obj: Any, where: str) -> tuple[list[m.Field], list[m.Const]]:
        """The fields and constants of a body, their spans in the order they were written."""
        placed = [(self.get(x, "position", w, int, optional=True) or 0, self.const(x, w))
                  for w, x in self.list_of(obj, "consts", where)]
        fields = [self.field(x, w) for w, x in self.list_of(obj, "fields", where)]
        self.order_members(fields, placed)
        return fields, [c for _, c in placed]

    def order_members(self, fields: list[m.Field], placed: list[tuple[int, m.Const]]) -> None:
        """Give fields and constants spans in written order (a constant after ``position`` fields)."""
        queue = sorted(range(len(placed)), key=lambda i: placed[i][0])
        q = 0
        for i, f in enumerate([*fields, None]):
            while q < len(queue) and (f is None or placed[queue[q]][0] <= i):
                placed[queue[q]][1].span = self.span()
                q += 1
            if f is not None:
                f.span = self.span()

    def section(self, obj: Any, where: str) -> m.Section:
        fields, consts = self.members(obj, where)
        return m.Section(self.get(obj, "name", where, str), self.span(), Span(0, 0), fields, consts,
                         bool(self.get(obj, "implicit", where, bool, optional=True)),
                         self.get(obj, "doc", where, str, optional=True))

    def function(self, obj: Any, where: str) -> m.Function:
        ret = self.get(obj, "returns", where, dict, optional=True)
        return m.Function(self.get(obj, "name", where, str), None if ret is None else self.type(ret, f"{where}/returns"),
                          self.span(), Span(0, 0), [self.field(x, w) for w, x in self.list_of(obj, "params", where)],
                          [self.field(x, w) for w, x in self.list_of(obj, "throws", where)],
                          bool(self.get(obj, "oneway", where, bool, optional=True)), self.annotations(obj, where),
                          self.get(obj, "doc", where, str, optional=True))

    # ---- items -----------------------------------------------------------------------
    def item(self, obj: Any, where: str) -> m.Item:
        kind = self.get(obj, "kind", where, str)
        name = (lambda: self.get(obj, "name", where, str))
        doc = self.get(obj, "doc", where, str, optional=True) if isinstance(obj, dict) else None
        if kind == "include":
            return m.Include(self.get(obj, "path", where, str), self.span(), Span(0, 0),
                             bool(self.get(obj, "cpp", where, bool, optional=True)))
        if kind == "namespace":
            return m.Namespace(self.get(obj, "scope", where, str), name(), self.span(), self.annotations(obj, where))
        if kind == "component":
            return m.ComponentDecl(name(), self.span(), Span(0, 0), self.get(obj, "version", where, str, optional=True),
                                   self.annotations(obj, where), doc)
        if kind == "external":
            return m.External(name(), self.span())
        if kind == "system":
            return m.SystemDecl(name(), self.span(), Span(0, 0), self.get(obj, "version", where, str, optional=True),
                                self.annotations(obj, where), doc)
        if kind == "instance":
            return m.Instance(name(), self.get(obj, "component", where, str), self.span(), Span(0, 0), Span(0, 0),
                              self.annotations(obj, where), doc)
        if kind == "wiring":
            direction = self.get(obj, "direction", where, str)
            if direction not in ("publishes", "subscribes", "provides", "calls"):
                raise FormError(f"{where}/direction", f"unknown direction '{direction}'")
            return m.Wiring(direction, m.NamedType(self.get(obj, "type", where, str), self.span()),
                            self.get(obj, "topic", where, str), self.span(), Span(0, 0),
                            self.annotations(obj, where), doc)
        if kind == "const":
            return self.const(obj, where)
        if kind == "typedef":
            return m.Typedef(name(), self.type(self.get(obj, "type", where, dict), f"{where}/type"), self.span(),
                             Span(0, 0), self.annotations(obj, where), doc)
        if kind == "enum":
            values = []
            for w, v in self.list_of(obj, "values", where):
                values.append(m.EnumValue(self.get(v, "name", w, str), self.get(v, "value", w, int), self.span(),
                                          Span(0, 0), bool(self.get(v, "explicit", w, bool, optional=True)),
                                          self.annotations(v, w), self.get(v, "doc", w, str, optional=True)))
            return m.Enum(name(), self.span(), Span(0, 0), values, self.annotations(obj, where), doc)
        if kind == "senum":
            strings = [self.value(v, w) for w, v in self.list_of(obj, "values", where)]
            return m.Senum(name(), self.span(), Span(0, 0), strings, self.annotations(obj, where), doc)
        if kind in ("struct", "union", "exception", "message", "configuration", "state"):
            fields, consts = self.members(obj, where)
            return m.Struct(kind, name(), self.span(), Span(0, 0), fields, consts,
                            self.annotations(obj, where), doc)
        if kind in ("service", "action"):
            return self.body(kind, obj, where, name(), doc)
        raise FormError(f"{where}/kind", f"unknown item kind '{kind}'")

    def body(self, kind: str, obj: Any, where: str, name: str, doc: str | None) -> m.Service | m.Action:
        form = self.get(obj, "form", where, str)
        if form not in ("explicit", "flat", "functions", "empty"):
            raise FormError(f"{where}/form", f"unknown form '{form}'")
        consts = [self.const(x, w) for w, x in self.list_of(obj, "consts", where)]
        sections = [self.section(x, w) for w, x in self.list_of(obj, "sections", where)]
        d: m.Service | m.Action
        reading: tuple[str, ...]
        if kind == "service":
            d = m.Service(name, self.span(), Span(0, 0), consts=consts, annotations=self.annotations(obj, where),
                          doc=doc)
            ext = self.get(obj, "extends", where, str, optional=True)
            d.extends = None if ext is None else m.NamedType(ext, self.span())
            d.functions = [self.function(x, w) for w, x in self.list_of(obj, "functions", where)]
        else:
            d = m.Action(name, self.span(), Span(0, 0), consts=consts, annotations=self.annotations(obj, where),
                         doc=doc)
        reading = flat_order(d)
        if form == "explicit":
            d.sections = sections
        elif form in ("flat", "empty"):
            by_name = {s.name: s for s in sections}
            d.flat_fields = [f for n in reading if n in by_name for f in by_name[n].fields]
            for f in d.flat_fields:  # a flat body is read by position: keep the reading order
                f.span = self.span()
        if isinstance(d, m.Service):
            normalize_service(d)
        else:
            normalize_action(d)
        return d


def _as_tuple(kinds: type | tuple[type, ...]) -> tuple[type, ...]:
    return kinds if isinstance(kinds, tuple) else (kinds,)


def _kind_names(kinds: type | tuple[type, ...]) -> str:
    names = {dict: "an object", list: "an array", str: "a string", int: "an integer", float: "a number",
             bool: "true or false"}
    return " or ".join(names.get(k, k.__name__) for k in _as_tuple(kinds))


def items_from_json(doc: Any) -> list[m.Item]:
    """The items of a JSON form, in order; a malformed document raises FormError."""
    if not isinstance(doc, dict):
        raise FormError("", "expected an object")
    fmt = doc.get("format")
    if fmt != FORMAT:
        raise FormError("/format", f"expected \"{FORMAT}\", not {fmt!r}")
    reader = _Reader()
    return [reader.item(x, w) for w, x in reader.list_of(doc, "items", "")]


def from_json(doc: Any) -> str:
    """The ``.iface`` text of a JSON form; a malformed document raises FormError."""
    from ..text.printer import print_items

    return print_items(items_from_json(doc))
