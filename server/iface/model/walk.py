"""Iterate over the parts of a model: members of bodies, type references, values."""

from __future__ import annotations

from collections.abc import Iterator

from . import nodes as m


def bodies(defn: m.Definition) -> Iterator[tuple[str, list[m.Field], list[m.Const]]]:
    """(label, fields, consts) for every field list a definition holds."""
    if isinstance(defn, m.Struct):
        yield defn.name, defn.fields, defn.consts
        return
    if isinstance(defn, m.Service) and defn.form == "functions":
        for fn in defn.functions:
            yield f"{defn.name}.{fn.name}", fn.params, []
            if fn.throws:
                yield f"{defn.name}.{fn.name} throws", fn.throws, []
    elif isinstance(defn, (m.Service, m.Action)):
        if defn.form == "explicit":
            for sec in defn.sections:
                yield f"{defn.name}.{sec.name}", sec.fields, sec.consts
        else:
            yield defn.name, defn.flat_fields, []
    else:
        return
    if defn.consts:
        yield defn.name, [], defn.consts


def all_fields(defn: m.Definition) -> Iterator[m.Field]:
    """Every field inside a definition."""
    for _, fields, _ in bodies(defn):
        yield from fields


def all_consts(defn: m.Definition) -> Iterator[m.Const]:
    """Every constant inside a definition, the definition itself if it is one."""
    if isinstance(defn, m.Const):
        yield defn
    for _, _, consts in bodies(defn):
        yield from consts


def type_roots(item: m.Item) -> Iterator[m.TypeRef]:
    """The outermost type references an item holds."""
    if isinstance(item, m.Wiring):
        yield item.type
        return
    if isinstance(item, (m.Typedef, m.Const)):
        yield item.type
    if isinstance(item, m.Service):
        if item.extends is not None:
            yield item.extends
        for fn in item.functions:
            if fn.returns is not None:
                yield fn.returns
    if isinstance(item, (m.Struct, m.Service, m.Action)):
        for _, fields, consts in bodies(item):
            for f in fields:
                yield f.type
            for c in consts:
                yield c.type


def named_types(t: m.TypeRef) -> Iterator[m.NamedType]:
    """Every named type inside a type reference (iteratively: types may nest deeply)."""
    # hot (every reference is resolved through here): one read of the kind tag, which mypy cannot narrow through
    stack = [t]
    while stack:
        x = stack.pop()
        kind = x.kind
        if kind == "named":
            yield x  # type: ignore[misc]  # kind "named": a NamedType
        elif kind == "map":
            stack.append(x.key)  # type: ignore[union-attr]  # kind "map": a MapType
            stack.append(x.element)  # type: ignore[union-attr]  # kind "map": a MapType
        elif kind != "base":
            stack.append(x.element)  # type: ignore[union-attr]  # an ArrayType or a SetType


def type_text(t: m.TypeRef) -> str:
    """The type written back in iface syntax."""
    if isinstance(t, m.BaseType):
        name = t.spelling or t.name
        return f"{name}<={t.bound}" if t.bound is not None else name
    if isinstance(t, m.NamedType):
        return t.name
    if isinstance(t, m.MapType):
        return f"map<{type_text(t.key)}, {type_text(t.element)}>"
    if isinstance(t, m.SetType):
        return f"set<{type_text(t.element)}>"
    if t.spelled_list:
        return f"list<{type_text(t.element)}>"
    if t.array == "fixed":
        return f"{type_text(t.element)}[{t.size}]"
    if t.array == "bounded":
        return f"{type_text(t.element)}[<={t.size}]"
    return f"{type_text(t.element)}[]"


def resolve_typedefs(t: m.TypeRef) -> m.TypeRef:
    """Follow named types through typedefs to what they finally stand for (a cycle stops where it closes)."""
    if isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef) and t.target.final is not None:
        return t.target.final
    seen: set[int] = set()
    while isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef) and id(t.target) not in seen:
        seen.add(id(t.target))
        t = t.target.type
    return t


def typedef_chain(t: m.TypeRef) -> list[m.Typedef]:
    """The typedefs a named type goes through, in order (each once: a cycle stops where it closes)."""
    chain: list[m.Typedef] = []
    seen: set[int] = set()
    while isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef) and id(t.target) not in seen:
        seen.add(id(t.target))
        chain.append(t.target)
        t = t.target.type
    return chain
