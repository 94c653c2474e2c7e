"""Markdown descriptions of model nodes for hover: no LSP types here."""

from __future__ import annotations

from typing import Any

from ..model import nodes as m
from ..model.naming import ros_field_name, ros_type_name
from ..model.normalize import flat_reading
from ..model.walk import resolve_typedefs, type_text, typedef_chain
from ..semantics.query import Hit, instance_component
from ..semantics.systems import ANNOTATIONS as INSTANCE_ANNOTATIONS
from ..semantics.systems import DEFAULT_RESTART, intra_process, runtime, standby, start_order

TARGETS = ("ros2", "px4", "idl", "json")
TARGET_TITLES = {"ros2": "ROS 2", "px4": "PX4", "idl": "IDL", "json": "JSON Schema"}

#: What the annotation keys iface reads mean.
ANNOTATIONS: dict[str, str] = {
    "unit": "Physical unit of a field, e.g. `m/s` (shown in generated docs and parameter descriptions).",
    "range": "Allowed values of a parameter, `\"lo..hi\"` (either end may be left out).",
    "min": "Smallest allowed value of a parameter.",
    "max": "Largest allowed value of a parameter.",
    "diagnostics": "Marks a service as the component's diagnostics (Δ).",
    "role": "`role = \"diagnostics\"` marks a service as the component's diagnostics (Δ).",
    "qos.depth": "ROS 2 QoS history depth of the topic.",
    "qos.reliability": "ROS 2 QoS reliability: `reliable` or `best_effort`.",
    "qos.durability": "ROS 2 QoS durability: `volatile` or `transient_local`.",
    "qos.history": "ROS 2 QoS history: `keep_last` or `keep_all`.",
    "qos.deadline": "ROS 2 QoS deadline (e.g. `100ms`).",
    "qos.lifespan": "ROS 2 QoS lifespan (e.g. `1s`).",
    "qos.liveliness": "ROS 2 QoS liveliness: `automatic` or `manual_by_topic`.",
    "rate": "Expected publishing rate, e.g. `\"10 Hz\"`.",
    "deprecated": "The element is deprecated.",
}


def _code(text: str) -> str:
    return f"`{text}`" if "`" not in text else f"``{text}``"


def _type_tables() -> Any:
    try:
        from ..emit import types as table
    except ImportError:
        return None
    return table


def _package(iface: m.Interface | None) -> str:
    if iface is None:
        return "pkg"
    return iface.namespace("ros2") or iface.name


def on_targets(t: m.TypeRef, iface: m.Interface | None) -> dict[str, str] | None:
    """How a type is written by each target; None when the type table is not installed."""
    table = _type_tables()
    if table is None:
        return None
    return {target: _on(table, t, target, iface) for target in TARGETS}


def _on(table: Any, t: m.TypeRef, target: str, iface: m.Interface | None) -> str:
    t = resolve_typedefs(t)
    col = "json_schema" if target == "json" else target
    none = "— (not representable)"
    if isinstance(t, m.BaseType):
        if t.bound is not None:
            if target == "json":
                return '{"type": "string", "maxLength": %d}' % t.bound
            out = table.container("bounded_string", target, t.name, t.bound)
            return out if out is not None else none
        row = table.BASE_TYPES.get(t.name)
        value = getattr(row, col) if row is not None else None
        if value is None:
            return none
        return value if isinstance(value, str) else _json(value)
    if isinstance(t, m.ArrayType):
        elem = _on(table, t.element, target, iface)
        if elem == none:
            return none
        if target == "json":
            size = f', "maxItems": {t.size}' if t.size is not None else ""
            return '{"type": "array", "items": %s%s}' % (elem, size)
        out = table.container(t.array, target, elem, t.size, name="Array")
        return out if out is not None else none
    if isinstance(t, (m.SetType, m.MapType)):
        kind = "set" if isinstance(t, m.SetType) else "map"
        if target != "json":
            out = table.container(kind, target, _on(table, t.element, target, iface))
            return out if out is not None else none
        return '{"type": "%s"}' % ("array" if kind == "set" else "object")
    assert isinstance(t, m.NamedType)
    d = t.target
    if t.external is not None:
        pkg, _, name = t.name.rpartition(".")
        return {"ros2": f"{pkg}/{name}", "px4": name, "idl": f"{pkg}::msg::{name}",
                "json": '{"$ref": "%s.json"}' % t.name}[target]
    if d is None:
        return none
    name = ros_type_name(d.name) or d.name
    pkg = _package(iface)
    if isinstance(d, m.Enum):
        return {"ros2": "int32 (enum values become constants)", "px4": "int32 (enum values become constants)",
                "idl": f"{pkg}::{name} (enum)", "json": '{"enum": [%s]}' % ", ".join(f'"{v.name}"' for v in d.values)
                }[target]
    folder = "srv" if isinstance(d, m.Service) else "action" if isinstance(d, m.Action) else "msg"
    return {"ros2": f"{pkg}/{folder}/{name}", "px4": name, "idl": f"{pkg}::{folder}::{name}",
            "json": '{"$ref": "#/$defs/%s"}' % d.name}[target]


def _json(value: dict[str, Any]) -> str:
    import json
    return json.dumps(value, sort_keys=False)


def _targets_block(t: m.TypeRef, iface: m.Interface | None) -> str:
    rows = on_targets(t, iface)
    if rows is None:
        return "_(the type table `iface.emit.types` is not installed: targets not shown)_"
    return "\n".join(f"- {TARGET_TITLES[k]}: {_code(v)}" for k, v in rows.items())


def membership(d: object, iface: m.Interface) -> str:
    """Which of the seven sets ``d`` belongs to, and its contract role."""
    lines: list[str] = []
    for key, sym, role in (("subscribed", "M", "assumption"), ("published", "N", "guarantee")):
        for ep in getattr(iface, key):
            if ep.definition is d:
                lines.append(f"{sym} ({key} on {_code(ep.name)}): {role}")
    for key, sym in (("services", "S"), ("actions", "A")):
        for ep in getattr(iface, key):
            if ep.definition is d:
                role = "guarantee (provided)" if ep.role == "provides" else "assumption (called)"
                lines.append(f"{sym} ({ep.role} {_code(ep.name)}): {role}")
    if isinstance(d, m.Struct) and d.kind == "configuration":
        lines.append("P (parameters): assumption")
    if isinstance(d, m.Struct) and d.kind == "state":
        lines.append("Σ (state): assumption and guarantee")
    for ep in iface.diagnostics_endpoints:
        if ep.definition is d:
            lines.append(f"Δ (diagnostics and control, served as {_code(ep.name)}; not in S): guarantee")
    if isinstance(d, m.Field):
        if any(p is d for p in iface.parameters):
            lines.append("P (parameter): assumption")
        if any(s is d for s in iface.state):
            lines.append("Σ (state): assumption and guarantee")
    return "\n".join(f"- {x}" for x in lines)


def _source_excerpt(d: m.Definition, text: str, limit: int = 14) -> str:
    body = text[d.span.start:d.span.end].split("\n")
    if len(body) > limit:
        body = body[:limit] + ["    …"]
    return "```iface\n" + "\n".join(body) + "\n```"


def definition(d: m.Definition, home: m.Interface, owner_text: str, here: m.Interface) -> str:
    """A definition: kind and name, doc, source, typedef chain, sets, targets."""
    parts = [f"**{d.kind}** {_code(d.name)}" + (f" — from `{home.source.path.rsplit('/', 1)[-1]}`"
                                                if home is not here else "")]
    if d.doc:
        parts.append(d.doc)
    parts.append(_source_excerpt(d, owner_text))
    if isinstance(d, (m.Service, m.Action)) and d.form == "flat":
        parts.append("Read as " + flat_reading(d))
    if isinstance(d, m.Typedef):
        chain = typedef_chain(m.NamedType(d.name, d.name_span, target=d))
        final = resolve_typedefs(d.type)
        parts.append("Typedef chain: " + " → ".join([_code(x.name) for x in chain] + [_code(type_text(final))]))
    sets = membership(d, home)
    parts.append("**Interface**\n" + sets if sets else
                 "**Interface**: a type definition (in none of the seven sets)")
    if not isinstance(d, m.Const):
        ref = m.NamedType(d.name, d.name_span, target=d)
        parts.append("**On the targets**\n" + _targets_block(ref, home))
    return "\n\n".join(parts)


def field(f: m.Field, owner: m.Definition | None, iface: m.Interface) -> str:
    """A field: type, default, range, unit, its ROS 2 name, sets, targets."""
    head = f"**field** {_code(f.name)}: {_code(type_text(f.type))}"
    if owner is not None:
        head += f" in {_code(owner.name)}"
    parts = [head]
    if f.doc:
        parts.append(f.doc)
    facts = []
    if f.default is not None:
        facts.append(f"default: {_code(f.default.text or str(f.default.value))}")
    if f.range is not None:
        lo, hi = f.range
        facts.append(f"range: {_num(lo)}..{_num(hi)}")
    if f.unit:
        facts.append(f"unit: {_code(f.unit)}")
    if f.requiredness:
        facts.append(f.requiredness)
    chain = typedef_chain(f.type)
    if chain:
        facts.append("typedefs: " + " → ".join([_code(x.name) for x in chain]
                                                + [_code(type_text(resolve_typedefs(f.type)))]))
    ros = ros_field_name(f.name)
    if ros and ros != f.name:
        facts.append(f"ROS 2 name: {_code(ros)}")
    if facts:
        parts.append("\n".join(f"- {x}" for x in facts))
    sets = membership(f, iface)
    if sets:
        parts.append("**Interface**\n" + sets)
    parts.append("**On the targets**\n" + _targets_block(f.type, iface))
    return "\n\n".join(parts)


def _num(x: float | None) -> str:
    if x is None:
        return ""
    return str(int(x)) if float(x).is_integer() else str(x)


def base_type(t: m.BaseType) -> str:
    """A builtin type and what it becomes on every target."""
    table = _type_tables()
    spelled = t.spelling or t.name
    if table is not None and t.bound is None:
        text = table.hover_markdown(spelled)
        if text:
            return text
    return f"**{spelled}** (builtin `{t.name}`)\n\n**On the targets**\n" + _targets_block(t, None)


def describe(hit: Hit, iface: m.Interface, text: str, interfaces: list[m.Interface]) -> str | None:
    """Hover Markdown for what is under the cursor, or None."""
    from ..semantics.query import defining_interface

    node, target = hit.node, hit.target
    if hit.kind in ("definition", "type") and target is not None and not isinstance(target, (m.Field,)):
        home = defining_interface([iface, *iface.included.values(), *interfaces], target) or iface
        d = target
        if isinstance(d, (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const)):
            extra = ""
            if hit.kind == "type" and isinstance(node, m.NamedType):
                chain = typedef_chain(node)
                if chain:
                    extra = "\n\nResolves through " + " → ".join(
                        [_code(x.name) for x in chain] + [_code(type_text(resolve_typedefs(node)))])
            return definition(d, home, home.source.text, iface) + extra
    if hit.kind == "type" and isinstance(node, m.NamedType):
        if node.external is not None:
            return (f"**external type** {_code(node.name)} from package {_code(node.external)}\n\n**On the targets**\n"
                    + _targets_block(node, iface))
        return f"unknown type {_code(node.name)}"
    if hit.kind == "base-type" and isinstance(node, m.BaseType):
        return base_type(node)
    if hit.kind == "field" and isinstance(node, m.Field):
        return field(node, hit.owner, iface)
    if hit.kind in ("const", "value") and isinstance(target, m.Const):
        return (f"**const** {_code(target.name)}: {_code(type_text(target.type))} = "
                f"{_code(target.value.text or str(target.value.value))}" + (f"\n\n{target.doc}" if target.doc else ""))
    if hit.kind in ("enum-value", "value") and isinstance(target, m.EnumValue):
        owner = hit.owner.name if hit.kind == "enum-value" and hit.owner is not None else ""
        name = f"{owner}.{target.name}" if owner else target.name
        return f"**enum value** {_code(name)} = {target.value}" + (f"\n\n{target.doc}" if target.doc else "")
    if hit.kind == "value" and isinstance(node, m.Value):
        return f"{_code(str(node.value))} names no constant or enum value"
    if hit.kind == "section" and isinstance(node, m.Section):
        fields = ", ".join(f"{_code(type_text(f.type))} {f.name}" for f in node.fields) or "nothing"
        return f"**{node.name}** of {_code(hit.owner.name if hit.owner else '?')}: {fields}"
    if hit.kind == "function" and isinstance(node, m.Function):
        params = ", ".join(f"{type_text(p.type)} {p.name}" for p in node.params)
        ret = type_text(node.returns) if node.returns is not None else "void"
        return f"**function** {_code(f'{ret} {node.name}({params})')}" + (f"\n\n{node.doc}" if node.doc else "")
    if hit.kind == "topic" and hit.wiring is not None:
        w = hit.wiring
        same = [x for x in iface.wirings if x.topic == w.topic]
        lines = [f"- {x.direction} {_code(x.type.name)}" for x in same]
        qos = ", ".join(f"{k} = {v}" for k, v in w.qos.items())
        return f"**topic** {_code(w.topic)}\n\n" + "\n".join(lines) + (f"\n\nQoS: {qos}" if qos else "")
    if hit.kind == "annotation" and isinstance(node, m.Annotation) and isinstance(hit.annotation_owner, m.Instance):
        meaning = INSTANCE_ANNOTATIONS.get(node.key, "an annotation an instance does not take")
        return f"**instance annotation** {_code(node.key)}: {meaning}"
    if hit.kind in ("system", "instance", "instance-component"):
        return _system_part(hit, iface)
    if hit.kind == "annotation" and isinstance(node, m.Annotation):
        meaning = ANNOTATIONS.get(node.key, "an annotation iface does not interpret (kept for Thrift)")
        return f"**annotation** {_code(node.key)}: {meaning}"
    if hit.kind == "include" and isinstance(node, m.Include):
        return f"**include** {_code(node.path)} → {_code(node.resolved or 'not found')}"
    if hit.kind == "component" and isinstance(node, m.ComponentDecl):
        return (f"**component** {_code(node.name)}" + (f" version {_code(node.version)}" if node.version else "")
                + f"\n\n{len(iface.subscribed)} subscribed, {len(iface.published)} published, "
                f"{len(iface.services)} services, {len(iface.actions)} actions, {len(iface.parameters)} parameters, "
                f"{len(iface.state)} state variables, {len(iface.diagnostics)} diagnostics")
    return None



def _system_part(hit: Hit, iface: m.Interface) -> str | None:
    """A system, an instance or the component an instance runs."""
    node = hit.node
    if hit.kind == "system" and isinstance(node, m.SystemDecl):
        order = " → ".join(i.name for i in start_order(iface.instances)) or "no instances"
        return (f"**system** {_code(node.name)}" + (f" version {_code(node.version)}" if node.version else "")
                + (f"\n\n{node.doc}" if node.doc else "") + f"\n\nstart order: {order}")
    inst = hit.target if isinstance(hit.target, m.Instance) else node if isinstance(node, m.Instance) else None
    if hit.kind == "instance" and inst is not None:
        after = ", ".join(a.text for a in inst.after) or "the instance declared before it"
        snapshot = inst.value("snapshot")
        parameters = inst.value("parameters")
        lines = [f"**instance** {_code(inst.name)} : {_code(inst.component)}",
                 f"- node: {_code('/' + inst.node)}",
                 f"- restart: {_code(inst.value('restart') or DEFAULT_RESTART)}",
                 f"- snapshot: {_code(snapshot) if snapshot else 'on deactivate and on request'}",
                 f"- starts after: {after}"]
        if parameters:
            lines.append(f"- parameters: {_code(parameters)}")
        box = inst.value("container")
        if box:
            lines.append(f"- container: {_code(box)} (shares its process; "
                         + ("intra-process where the QoS allows)" if intra_process(inst) else "no intra-process)"))
        lines.append(f"- runtime: {_code(runtime(inst))}")
        if standby(inst):
            lines.append("- standby: a spare " + ("container process" if box else "process")
                         + " started ahead, which becomes " + ("the container" if box else "the instance")
                         + " at a restart")
        return "\n".join(lines) + (f"\n\n{inst.doc}" if inst.doc else "")
    if hit.kind == "instance-component" and isinstance(node, m.Instance):
        comp = instance_component(iface, node)
        if comp is None:
            return f"no included file declares component {_code(node.component)}"
        decl = comp.component
        version = f" version {_code(comp.version)}" if comp.version else ""
        return (f"**component** {_code(comp.name)}" + version
                + f" from {_code(comp.source.path.rpartition('/')[2])}"
                + (f"\n\n{decl.doc}" if decl is not None and decl.doc else "")
                + f"\n\n{len(comp.subscribed)} subscribed, {len(comp.published)} published, "
                f"{len(comp.services)} services, {len(comp.actions)} actions, {len(comp.parameters)} parameters, "
                f"{len(comp.state)} state variables")
    return None
