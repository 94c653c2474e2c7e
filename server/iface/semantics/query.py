"""Questions editors ask of a compiled model: what is at an offset, where a name is used, the outline.

Everything here works on the model and its character offsets; no editor
protocol. The language server (``iface.lsp``) converts the answers.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from typing import Literal

from ..model import nodes as m
from ..model.source import Span
from ..model.walk import bodies, type_roots
from .resolve import constant_value

HitKind = Literal["definition", "field", "const", "enum-value", "section", "function", "type", "base-type",
                  "value", "topic", "include", "component", "annotation", "namespace", "system", "instance",
                  "instance-component"]

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

#: Words a name cannot be: keywords of the language and base type spellings.
RESERVED = frozenset({
    "include", "cpp_include", "namespace", "component", "external", "version", "publishes", "subscribes",
    "provides", "calls", "on", "const", "typedef", "enum", "senum", "struct", "union", "exception",
    "message", "configuration", "state", "service", "action", "extends", "oneway", "void", "throws",
    "required", "optional", "map", "set", "list", "cpp_type", "xsd_all", "true", "false", "system", "instance",
    *m.BASE_ALIASES,
})


@dataclass(slots=True, eq=False)
class Hit:
    """The named thing under an offset.

    ``span`` covers the name itself; ``target`` is what a reference points at
    (the definition of a type name, the constant of a value), or the node
    itself for a declaration.
    """

    kind: HitKind
    span: Span
    node: object
    owner: m.Definition | None = None
    target: object | None = None
    wiring: m.Wiring | None = None
    annotation_owner: object | None = None


def _touches(span: Span, offset: int) -> bool:
    return span.start <= offset <= span.end


# ---------------------------------------------------------------------------
# what is at an offset


def _start(item: m.Item) -> int:
    return item.span.start


def item_at(iface: m.Interface, offset: int) -> m.Item | None:
    """The top-level item whose span holds ``offset``."""
    items = iface.items
    k = bisect_right(items, offset, key=_start) - 1  # no list of every start: a hover costs the same in any file
    for j in (k, k - 1):
        if 0 <= j < len(items) and _touches(items[j].span, offset):
            return items[j]
    return None


def locate(iface: m.Interface, offset: int) -> Hit | None:
    """The innermost named thing at ``offset`` (a declaration or a reference), if any."""
    item = item_at(iface, offset)
    if item is None:
        return None
    if isinstance(item, m.Wiring):
        if _touches(item.type.span, offset):
            return Hit("type", item.type.span, item.type, None, item.type.target, item)
        if _touches(item.topic_span, offset):
            return Hit("topic", item.topic_span, item, None, None, item)
        return _annotations(item.annotations, offset, item, None)
    if isinstance(item, m.Include):
        return Hit("include", item.path_span, item) if _touches(item.path_span, offset) else None
    if isinstance(item, m.ComponentDecl):
        return Hit("component", item.name_span, item) if _touches(item.name_span, offset) else None
    if isinstance(item, (m.Namespace, m.External)):
        return Hit("namespace", item.span, item)
    if isinstance(item, m.SystemDecl):
        return Hit("system", item.name_span, item, None, item) if _touches(item.name_span, offset) else None
    if isinstance(item, m.Instance):
        return _in_instance(iface, item, offset)
    return _in_definition(iface, item, offset)


def instance_component(iface: m.Interface, inst: m.Instance) -> m.Interface | None:
    """The included interface whose component ``inst`` instantiates, if any."""
    return next((x for x in iface.included.values() if x.name == inst.component), None)


def _in_instance(iface: m.Interface, inst: m.Instance, offset: int) -> Hit | None:
    if _touches(inst.name_span, offset):
        return Hit("instance", inst.name_span, inst, None, inst)
    if _touches(inst.component_span, offset):
        comp = instance_component(iface, inst)
        return Hit("instance-component", inst.component_span, inst, None,
                   comp.component if comp is not None else None)
    for a in inst.annotations:
        if a.key == "after" and a.value is not None and _touches(a.value.span, offset):
            named = next((i for i in iface.instances if i.name == a.text), None)
            return Hit("instance", a.value.span, a.value, None, named)
    return _annotations(inst.annotations, offset, inst, None)


def _in_definition(iface: m.Interface, d: m.Definition, offset: int) -> Hit | None:
    if _touches(d.name_span, offset):
        return Hit("definition", d.name_span, d, d, d)
    if isinstance(d, m.Typedef):
        return _in_type(d.type, offset, d) or _annotations(d.annotations, offset, d, d)
    if isinstance(d, m.Const):
        return _in_type(d.type, offset, d) or _in_value(iface, d.value, offset, d)
    if isinstance(d, m.Enum):
        for v in d.values:
            if _touches(v.name_span, offset):
                return Hit("enum-value", v.name_span, v, d, v)
        return _annotations(d.annotations, offset, d, d)
    if isinstance(d, m.Service):
        if d.extends is not None and _touches(d.extends.span, offset):
            return Hit("type", d.extends.span, d.extends, d, d.extends.target)
        for fn in d.functions:
            if not _touches(fn.span, offset):
                continue
            if _touches(fn.name_span, offset):
                return Hit("function", fn.name_span, fn, d, fn)
            if fn.returns is not None and (hit := _in_type(fn.returns, offset, d)):
                return hit
            for f in (*fn.params, *fn.throws):
                if hit := _in_field(iface, f, offset, d):
                    return hit
    if isinstance(d, (m.Service, m.Action)):
        for sec in d.sections:
            if _touches(sec.name_span, offset) and sec.name_span.end > sec.name_span.start:
                return Hit("section", sec.name_span, sec, d, sec)
    for _, fields, consts in bodies(d):
        for f in fields:
            if _touches(f.span, offset) and (hit := _in_field(iface, f, offset, d)):
                return hit
        for c in consts:
            if _touches(c.span, offset) and (hit := _in_const(iface, c, offset, d)):
                return hit
    return _annotations(d.annotations, offset, d, d)


def _in_field(iface: m.Interface, f: m.Field, offset: int, owner: m.Definition) -> Hit | None:
    if _touches(f.name_span, offset):
        return Hit("field", f.name_span, f, owner, f)
    if hit := _in_type(f.type, offset, owner):
        return hit
    if f.default is not None and (hit := _in_value(iface, f.default, offset, owner)):
        return hit
    return _annotations(f.annotations, offset, f, owner)


def _in_const(iface: m.Interface, c: m.Const, offset: int, owner: m.Definition) -> Hit | None:
    if _touches(c.name_span, offset):
        return Hit("const", c.name_span, c, owner, c)
    return _in_type(c.type, offset, owner) or _in_value(iface, c.value, offset, owner)


def _in_type(t: m.TypeRef, offset: int, owner: m.Definition | None) -> Hit | None:
    stack = [t]
    while stack:
        x = stack.pop()
        if not _touches(x.span, offset):
            continue
        if isinstance(x, m.NamedType):
            return Hit("type", x.span, x, owner, x.target)
        if isinstance(x, m.BaseType):
            return Hit("base-type", x.span, x, owner, x)
        if isinstance(x, m.MapType):
            stack.extend((x.key, x.element))
        else:
            stack.append(x.element)
    return None


def _in_value(iface: m.Interface, v: m.Value, offset: int, owner: m.Definition) -> Hit | None:
    stack = [v]
    while stack:
        x = stack.pop()
        if not _touches(x.span, offset):
            continue
        if x.kind == "name":
            return Hit("value", x.span, x, owner, constant_value(iface, str(x.value)))
        if x.kind == "list":
            stack.extend(x.value)
        elif x.kind == "map":
            for k, val in x.value:
                stack.extend((k, val))
    return None


def _annotations(annotations: Iterable[m.Annotation], offset: int, node: object,
                 owner: m.Definition | None) -> Hit | None:
    for a in annotations:
        if _touches(a.span, offset):
            key = Span(a.span.start, a.span.start + len(a.key))
            return Hit("annotation", key, a, owner, None, None, node)
    return None


# ---------------------------------------------------------------------------
# where things are defined and used


def defining_interface(interfaces: Iterable[m.Interface], defn: object) -> m.Interface | None:
    """The interface whose top-level definitions (or their members) hold ``defn``."""
    interfaces = list(interfaces)
    if isinstance(defn, (m.ComponentDecl, m.SystemDecl, m.Instance)):
        return next((x for x in interfaces if defn is x.component or defn is x.system
                     or any(i is defn for i in x.instances)), None)
    for iface in interfaces:
        if any(d is defn for d in iface.definitions):
            return iface
    if not isinstance(defn, (m.Const, m.EnumValue)):
        return None  # only constants and enum values are members
    for iface in interfaces:
        for d in iface.definitions:
            if isinstance(d, m.Enum) and any(v is defn for v in d.values):
                return iface
            if any(c is defn for _, _, consts in bodies(d) for c in consts):
                return iface
    return None


def local_name_span(t: m.NamedType) -> Span:
    """The span of the last segment of a possibly qualified type name."""
    n = len(t.local_name)
    return Span(t.span.end - n, t.span.end)


@dataclass(slots=True, eq=False)
class Reference:
    """One use of a definition: the interface it is in and the span to rename."""

    interface: m.Interface
    span: Span
    declaration: bool = False


def named_references(iface: m.Interface) -> Iterator[m.NamedType]:
    """Every named type reference in a file."""
    for item in iface.items:
        for root in type_roots(item):
            stack = [root]
            while stack:
                x = stack.pop()
                if isinstance(x, m.NamedType):
                    yield x
                elif isinstance(x, m.MapType):
                    stack.extend((x.key, x.element))
                elif not isinstance(x, m.BaseType):
                    stack.append(x.element)


def value_references(iface: m.Interface) -> Iterator[m.Value]:
    """Every value written as a name (a constant or an enum value) in a file."""
    roots: list[m.Value] = []
    for d in iface.definitions:
        if isinstance(d, m.Const):
            roots.append(d.value)
        for _, fields, consts in bodies(d):
            roots.extend(f.default for f in fields if f.default is not None)
            roots.extend(c.value for c in consts)
    stack = roots
    while stack:
        v = stack.pop()
        if v.kind == "name":
            yield v
        elif v.kind == "list":
            stack.extend(v.value)
        elif v.kind == "map":
            for k, val in v.value:
                stack.extend((k, val))


def _same(a: object, b: object, a_iface: m.Interface | None, b_iface: m.Interface | None) -> bool:
    """True for one definition, also when two compilations of its file made two objects of it."""
    if a is b:
        return True
    if a_iface is None or b_iface is None or a_iface.path != b_iface.path:
        return False
    return type(a) is type(b) and getattr(a, "name", None) == getattr(b, "name", None) \
        and getattr(a, "name_span", None) == getattr(b, "name_span", None)


def _alike(a: object, b: object) -> bool:
    """What ``_same`` needs before it asks where each is defined (a linear search): same kind, same name."""
    return a is b or (type(a) is type(b) and getattr(a, "name", None) == getattr(b, "name", None))


def references(target: object, home: m.Interface, interfaces: Iterable[m.Interface],
               include_declaration: bool = True) -> list[Reference]:
    """Every use of ``target`` (defined in ``home``) in ``interfaces``, in order, each once."""
    out: list[Reference] = []
    seen: set[tuple[str, int, int]] = set()

    def add(iface: m.Interface, span: Span, decl: bool = False) -> None:
        key = (iface.path, span.start, span.end)
        if key not in seen:
            seen.add(key)
            out.append(Reference(iface, span, decl))

    if include_declaration and hasattr(target, "name_span"):
        add(home, target.name_span, True)
    if isinstance(target, (m.Instance, m.ComponentDecl)):
        for iface in interfaces:
            for inst in iface.instances:
                if isinstance(target, m.ComponentDecl):
                    comp = instance_component(iface, inst)
                    if inst.component == target.name and comp is not None and comp.path == home.path:
                        add(iface, inst.component_span)
                elif iface.path == home.path:
                    for a in inst.after:
                        if a.text == target.name and a.value is not None:
                            add(iface, Span(a.value.span.start + 1, a.value.span.end - 1))
        out.sort(key=lambda r: (r.interface.path != home.path, r.interface.path, r.span.start))
        return out
    for iface in interfaces:
        scopes = [home, *iface.included.values()] if iface.path != home.path else [home]
        if isinstance(target, (m.Const, m.EnumValue)):
            for v in value_references(iface):
                found = constant_value(iface, str(v.value))
                if found is not None and _alike(found, target) and any(
                        _same(found, target, defining_interface([s, iface], found), home) for s in scopes):
                    n = len(getattr(target, "name"))
                    add(iface, Span(v.span.end - n, v.span.end))
        if isinstance(target, (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const)):
            for t in named_references(iface):
                if t.target is None or not _alike(t.target, target):
                    continue
                where = defining_interface([iface, *iface.included.values()], t.target)
                if _same(t.target, target, where, home):
                    add(iface, local_name_span(t))
            if isinstance(target, m.Enum):
                for v in value_references(iface):
                    owner, _, _ = str(v.value).rpartition(".")
                    if owner.rpartition(".")[2] == target.name:
                        found = constant_value(iface, str(v.value))
                        if found is not None and found in target.values:
                            start = v.span.start + str(v.value).rfind(owner.rpartition(".")[2])
                            add(iface, Span(start, start + len(target.name)))
    out.sort(key=lambda r: (r.interface.path != home.path, r.interface.path, r.span.start))
    return out


def highlights(iface: m.Interface, hit: Hit) -> list[Span]:
    """Spans in this file naming the same thing as ``hit``."""
    target = hit.target
    if hit.kind == "topic":
        assert hit.wiring is not None
        return [w.topic_span for w in iface.wirings if w.topic == hit.wiring.topic]
    if target is None or hit.kind == "base-type":
        if hit.kind == "base-type" and isinstance(hit.node, m.BaseType):
            name = hit.node.name
            return [t.span for t in _base_types(iface) if t.name == name]
        return [hit.span]
    if hit.kind == "field" or hit.kind == "section" or hit.kind == "function":
        return [hit.span]
    home = defining_interface([iface, *iface.included.values()], target) or iface
    return [r.span for r in references(target, home, [iface]) if r.interface is iface]


def _base_types(iface: m.Interface) -> Iterator[m.BaseType]:
    for item in iface.items:
        for root in type_roots(item):
            stack = [root]
            while stack:
                x = stack.pop()
                if isinstance(x, m.BaseType):
                    yield x
                elif isinstance(x, m.MapType):
                    stack.extend((x.key, x.element))
                elif not isinstance(x, m.NamedType):
                    stack.append(x.element)


# ---------------------------------------------------------------------------
# renaming


def rename_problem(new_name: str, hit: Hit, iface: m.Interface) -> str | None:
    """Why ``new_name`` cannot replace the name under ``hit``; None when it can."""
    if not IDENTIFIER.fullmatch(new_name):
        return f"'{new_name}' is not a name: use letters, digits and '_', not starting with a digit"
    if new_name in RESERVED:
        return f"'{new_name}' is a keyword or a base type"
    target = hit.target
    if isinstance(target, (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const)) \
            and hit.kind in ("definition", "type", "value", "const") and target in iface.definitions:
        other = iface.symbols.get(new_name)
        if other is not None and other is not target:
            return f"'{new_name}' is already defined in this file"
        return None
    if isinstance(target, (m.Field, m.Const)) and hit.owner is not None:
        for _, fields, consts in bodies(hit.owner):
            members: list[m.Field | m.Const] = [*fields, *consts]
            if target in members and any(x.name == new_name and x is not target for x in members):
                return f"'{new_name}' is already a member of '{hit.owner.name}'"
        return None
    if isinstance(target, m.EnumValue) and isinstance(hit.owner, m.Enum):
        if any(v.name == new_name and v is not target for v in hit.owner.values):
            return f"'{new_name}' is already a value of '{hit.owner.name}'"
        return None
    return None


def renameable(hit: Hit) -> bool:
    """True when the thing under ``hit`` can be renamed (not a base type, not external)."""
    if hit.kind in ("definition", "field", "const", "enum-value"):
        return True
    if hit.kind in ("type", "value"):
        return hit.target is not None
    return False


# ---------------------------------------------------------------------------
# outline


SET_TITLES: dict[str, str] = {
    "subscribed": "M · subscribed", "published": "N · published", "services": "S · services",
    "actions": "A · actions", "parameters": "P · parameters", "state": "Σ · state",
    "diagnostics": "Δ · diagnostics", "types": "types",
}


@dataclass(slots=True, eq=False)
class Symbol:
    """One outline entry: a name, what it is, where it is, and what it holds."""

    name: str
    kind: str
    span: Span
    name_span: Span
    detail: str = ""
    children: list[Symbol] = field(default_factory=list)


def _member_symbols(d: m.Definition) -> list[Symbol]:
    out: list[Symbol] = []
    if isinstance(d, m.Enum):
        return [Symbol(v.name, "enum-value", v.span, v.name_span, str(v.value)) for v in d.values]
    if isinstance(d, (m.Service, m.Action)) and d.form == "explicit":
        for sec in d.sections:
            kids = [Symbol(f.name, "field", f.span, f.name_span, _type(f.type)) for f in sec.fields]
            kids += [Symbol(c.name, "const", c.span, c.name_span, _type(c.type)) for c in sec.consts]
            out.append(Symbol(sec.name, "section", sec.span, sec.name_span, "", kids))
        return out
    if isinstance(d, m.Service) and d.form == "functions":
        return [Symbol(fn.name, "function", fn.span, fn.name_span,
                       f"({', '.join(_type(p.type) for p in fn.params)})") for fn in d.functions]
    for _, fields, consts in bodies(d):
        out += [Symbol(f.name, "field", f.span, f.name_span, _type(f.type)) for f in fields]
        out += [Symbol(c.name, "const", c.span, c.name_span, _type(c.type)) for c in consts]
    return out


def _type(t: m.TypeRef) -> str:
    from ..model.walk import type_text
    return type_text(t)


def _definition_symbol(d: m.Definition, detail: str = "") -> Symbol:
    kind = d.kind
    return Symbol(d.name, kind, d.span, d.name_span, detail or kind, _member_symbols(d))


def outline(iface: m.Interface) -> list[Symbol]:
    """Top-level symbols grouped by the seven sets, then the remaining type definitions."""
    groups: dict[str, list[Symbol]] = {k: [] for k in SET_TITLES}
    placed: set[int] = set()
    for key, attr in (("subscribed", "subscribed"), ("published", "published"), ("services", "services"),
                      ("actions", "actions"), ("diagnostics", "diagnostics_endpoints")):
        for ep in getattr(iface, attr):
            w = ep.wiring
            if key == "diagnostics" and w is None:
                continue  # listed with its definition below
            d = ep.definition
            if w is not None:
                groups[key].append(Symbol(f"{w.type.name} on {ep.name}", w.direction, w.span, w.topic_span,
                                          w.direction))
            elif d is not None:
                groups[key].append(_definition_symbol(d, ep.role))
                placed.add(id(d))
    for d in iface.definitions:
        if isinstance(d, m.Struct) and d.kind == "configuration":
            groups["parameters"].append(_definition_symbol(d))
        elif isinstance(d, m.Struct) and d.kind == "state":
            groups["state"].append(_definition_symbol(d))
        elif isinstance(d, m.Service) and d in iface.diagnostics:
            groups["diagnostics"].append(_definition_symbol(d))
        elif id(d) not in placed:
            groups["types"].append(_definition_symbol(d))
    out: list[Symbol] = []
    if iface.instances:
        kids = [Symbol(i.name, "instance", i.span, i.name_span, i.component) for i in iface.instances]
        first = kids[0]
        out.append(Symbol("instances", "group", Span(first.span.start, kids[-1].span.end), first.name_span,
                          f"{len(kids)}", kids))
    for key, title in SET_TITLES.items():
        kids = groups[key]
        if not kids:
            continue
        start = min(k.span.start for k in kids)
        end = max(k.span.end for k in kids)
        first = min(kids, key=lambda k: k.span.start)
        out.append(Symbol(title, "group", Span(start, end), Span(first.name_span.start, first.name_span.end),
                          f"{len(kids)}", sorted(kids, key=lambda k: k.span.start)))
    return out


# ---------------------------------------------------------------------------
# folding and selection


def folding_spans(iface: m.Interface, text: str) -> list[tuple[Span, str]]:
    """(span, kind) of foldable regions: definitions, sections, block comments, runs of includes."""
    out: list[tuple[Span, str]] = []
    for d in iface.definitions:
        out.append((d.span, "region"))
        if isinstance(d, (m.Service, m.Action)):
            out.extend((s.span, "region") for s in d.sections if not s.implicit)
    for mt in re.finditer(r"/\*.*?(?:\*/|\Z)", text, re.S):
        out.append((Span(mt.start(), mt.end()), "comment"))
    run: list[m.Include] = []
    for item in [*iface.items, None]:
        if isinstance(item, m.Include):
            run.append(item)
            continue
        if len(run) > 1:
            out.append((Span(run[0].span.start, run[-1].span.end), "imports"))
        run = []
    return out


def selection_chain(iface: m.Interface, offset: int, text_length: int) -> list[Span]:
    """Spans around ``offset`` from the innermost name out to the whole file."""
    chain: list[Span] = []
    hit = locate(iface, offset)
    if hit is not None:
        chain.append(hit.span)
    item = item_at(iface, offset)
    if item is not None and not isinstance(item, (m.Wiring, m.Include, m.Namespace, m.External, m.ComponentDecl,
                                                  m.SystemDecl, m.Instance)):
        d = item
        if isinstance(d, (m.Service, m.Action)):
            for sec in d.sections:
                if _touches(sec.span, offset):
                    section_members: list[m.Field | m.Const] = [*sec.fields, *sec.consts]
                    for f in section_members:
                        if _touches(f.span, offset):
                            chain.append(f.span)
                    chain.append(sec.span)
        for _, fields, consts in bodies(d):
            members: tuple[m.Field | m.Const, ...] = (*fields, *consts)
            for f in members:
                if _touches(f.span, offset):
                    chain.append(f.span)
        if isinstance(d, m.Enum):
            chain.extend(v.span for v in d.values if _touches(v.span, offset))
    if item is not None:
        chain.append(item.span)
    chain.append(Span(0, text_length))
    out: list[Span] = []
    for s in chain:
        if out and (s.start > out[-1].start or s.end < out[-1].end):
            continue  # keep the chain strictly widening
        if out and s == out[-1]:
            continue
        out.append(s)
    return out
