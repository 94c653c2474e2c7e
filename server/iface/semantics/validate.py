"""Semantic checks: small rules that yield located diagnostics and never raise.

Each rule takes the resolved interface and yields diagnostics. Rules that only
matter for robot targets (ROS 2 names, recursion, topic names) run on `.iface`
files and on Thrift files that declare a ``ros2`` or ``px4`` namespace.
"""

from __future__ import annotations

import dataclasses
import math
import re
import struct
from collections.abc import Callable, Iterator

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, Severity, make
from ..model.naming import (
    is_ros_constant,
    is_ros_field,
    is_ros_type,
    ros_constant_name,
    ros_field_name,
    ros_type_name,
)
from ..model.normalize import ACTION_PARTS, SERVICE_PARTS, flat_reading
from ..model.qos import downgrade as qos_downgrade
from ..model.qos import problem as qos_problem
from ..model.source import Source
from ..model.walk import all_consts, bodies, resolve_typedefs, type_text
from ..syntax.transform import shorten
from .resolve import constant_value

Rule = Callable[[m.Interface], Iterator[Diagnostic]]
LocalRule = Callable[[Source, m.Definition], Iterator[Diagnostic]]
DefinitionRule = Callable[[m.Interface, m.Definition], Iterator[Diagnostic]]
WiringRule = Callable[[Source, m.Wiring], Iterator[Diagnostic]]
RULES: list[tuple[Rule, bool]] = []  # (rule, robot_only): rules over the whole file
LOCAL_RULES: list[tuple[LocalRule, bool]] = []  # rules over one definition, cached while it is unchanged
#: Rules over one resolved definition: they read what its names resolve to (run again when that changes).
DEFINITION_RULES: list[DefinitionRule] = []
#: Rules over one wiring statement alone (robot targets only).
WIRING_RULES: list[WiringRule] = []

_UUID = re.compile(r"^\{?[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}\}?$")
_TOPIC = re.compile(r"^~?/?[A-Za-z_{][A-Za-z0-9_{}]*(/[A-Za-z_{][A-Za-z0-9_{}]*)*$")


def rule(robot_only: bool = False) -> Callable[[Rule], Rule]:
    """Register a check over the whole resolved file."""
    def register(fn: Rule) -> Rule:
        RULES.append((fn, robot_only))
        return fn
    return register


def local_rule(robot_only: bool = False) -> Callable[[LocalRule], LocalRule]:
    """Register a check that reads one definition and nothing else (so it can be cached)."""
    def register(fn: LocalRule) -> LocalRule:
        LOCAL_RULES.append((fn, robot_only))
        return fn
    return register


def definition_rule(fn: DefinitionRule) -> DefinitionRule:
    """Register a check over one resolved definition."""
    DEFINITION_RULES.append(fn)
    return fn


def wiring_rule(fn: WiringRule) -> WiringRule:
    """Register a check over one wiring statement (robot targets only)."""
    WIRING_RULES.append(fn)
    return fn


def is_robot(iface: m.Interface) -> bool:
    """True when robot-target rules apply to the file."""
    return iface.source.path.endswith(".iface") or any(
        ns.scope in ("ros2", "px4") for ns in iface.namespaces)


def local_findings(src: Source, d: m.Definition, robot: bool) -> list[Diagnostic]:
    """What the local rules find in one definition (it alone decides)."""
    return [x for fn, robot_only in LOCAL_RULES if robot or not robot_only for x in fn(src, d)]


def definition_findings(iface: m.Interface, d: m.Definition) -> list[Diagnostic]:
    """What the rules over one resolved definition find in it."""
    return [x for fn in DEFINITION_RULES for x in fn(iface, d)]


def wiring_findings(src: Source, w: m.Wiring) -> list[Diagnostic]:
    """What the wiring rules find in one wiring statement."""
    return [x for fn in WIRING_RULES for x in fn(src, w)]


def rehome(d: Diagnostic, src: Source) -> Diagnostic:
    """A cached finding, attached to the newest version of its file."""
    if d.source is src:
        return d
    related = [Related(src, r.span, r.message) if r.source.path == src.path else r for r in d.related]
    return dataclasses.replace(d, source=src, related=related)


# ---------------------------------------------------------------------------
# duplicates and ids


@local_rule()
def duplicate_members(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Two fields or constants of one name, or two fields of one id, in a body."""
    for label, fields, consts in bodies(d):
        names: dict[str, m.Field | m.Const] = {}
        ids: dict[int, m.Field] = {}
        members: tuple[m.Field | m.Const, ...] = (*fields, *consts)
        for f in members:
            first = names.get(f.name)
            if first is not None:
                yield make("duplicate-field", f"'{f.name}' is already declared in '{label}'", src,
                           f.name_span, related=[Related(src, first.name_span, "first declared here")])
            else:
                names[f.name] = f
            if isinstance(f, m.Field) and f.id is not None:
                assert f.id_span is not None
                if (not -32768 <= f.id <= 32767 or f.id == 0) and m.INT_LITERAL[0] <= f.id <= m.INT_LITERAL[1]:
                    yield make("invalid-field-id", f"field id {f.id} is outside 1..32767", src, f.id_span)
                other = ids.get(f.id)
                if other is not None:
                    yield make("duplicate-field-id", f"field id {f.id} is already used by '{other.name}'",
                               src, f.id_span,
                               related=[Related(src, other.id_span or other.span, f"id {f.id} first used here")])
                else:
                    ids[f.id] = f


@local_rule()
def enum_values(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Enum names unique, values unique and within i32."""
    lo, hi = m.INT_RANGES["i32"]
    if not isinstance(d, m.Enum):
        return
    names: dict[str, m.EnumValue] = {}
    values: dict[int, m.EnumValue] = {}
    for v in d.values:
        if v.name in names:
            yield make("duplicate-enum-value", f"'{v.name}' is already a value of '{d.name}'", src,
                       v.name_span, related=[Related(src, names[v.name].name_span, "first declared here")])
        names.setdefault(v.name, v)
        if v.value in values:
            yield make("duplicate-enum-value",
                       f"'{v.name}' has the value {v.value} of '{values[v.value].name}'", src, v.span,
                       severity=Severity.WARNING)
        values.setdefault(v.value, v)
        if not lo <= v.value <= hi and m.INT_LITERAL[0] <= v.value <= m.INT_LITERAL[1]:
            yield make("int-out-of-range", f"enum value {v.value} does not fit in i32, the type of enums",
                       src, v.span, severity=Severity.WARNING)


# ---------------------------------------------------------------------------
# values


def check_value(iface: m.Interface, t: m.TypeRef, v: m.Value, what: str) -> Iterator[Diagnostic]:
    """A value against the type that must hold it."""
    src = iface.source
    t = resolve_typedefs(t)
    kind = t.kind
    if v.kind == "name" and not (isinstance(t, m.BaseType) and t.name == "bool" and v.value in ("true", "false")):
        if isinstance(t, m.NamedType) and isinstance(t.target, m.Enum):
            # Thrift reads `Other.VALUE` for an enum-typed value as VALUE of the field's own enum
            if t.target.named(str(v.value).rpartition(".")[2]) is not None:
                return
        ref = constant_value(iface, str(v.value))
        if ref is None:
            yield make("invalid-default", f"{what}: '{v.value}' names no constant or enum value", src, v.span)
        return
    if kind == "base":
        assert isinstance(t, m.BaseType)
        name = t.name
        if name in m.INT_RANGES:
            if v.kind != "int":
                yield make("invalid-default", f"{what}: {name} needs an integer, not {_show(v)}", src, v.span)
                return
            lo, hi = m.INT_RANGES[name]
            if not lo <= int(v.value) <= hi and _literal_fits(v):
                yield make("int-out-of-range", f"{what}: {shorten(v.text)} does not fit in {name} ({lo}..{hi})",
                           src, v.span)
        elif name in m.FLOAT_TYPES:
            if v.kind not in ("int", "double"):
                yield make("invalid-default", f"{what}: {name} needs a number, not {_show(v)}", src, v.span)
            elif name == "float32" and _literal_fits(v) and not _fits_float32(float(v.value)):
                yield make("number-out-of-range", f"{what}: {shorten(v.text)} is beyond float32 "
                           f"(at most ±{m.FLOAT32_MAX:.8g})", src, v.span)
        elif name == "bool":
            if not (v.kind == "int" and v.value in (0, 1)) and not (v.kind == "name" and v.value in ("true", "false")):
                yield make("invalid-default", f"{what}: bool needs true or false, not {_show(v)}", src, v.span)
        elif name in m.STRING_TYPES or name == "binary":
            if v.kind != "string":
                yield make("invalid-default", f"{what}: {name} needs a string, not {_show(v)}", src, v.span)
            elif t.bound is not None and len(str(v.value)) > t.bound:
                yield make("invalid-default",
                           f"{what}: the string has {len(str(v.value))} characters, more than its bound {t.bound}",
                           src, v.span)
        elif name == "uuid":
            if v.kind != "string" or not _UUID.match(str(v.value)):
                yield make("invalid-default", f"{what}: uuid needs a string like "
                           "'00000000-4444-cccc-ffff-0123456789ab'", src, v.span)
        return
    if kind in ("array", "set"):
        if v.kind == "map" and not v.value:
            return  # Thrift writes an empty collection as {}
        if v.kind != "list":
            yield make("invalid-default", f"{what}: a sequence needs a list like [1, 2], not {_show(v)}", src, v.span)
            return
        items: list[m.Value] = v.value
        if isinstance(t, m.ArrayType) and t.size is not None:
            if t.array == "fixed" and len(items) != t.size:
                yield make("invalid-default", f"{what}: the array holds exactly {t.size} elements, "
                           f"the list has {len(items)}", src, v.span)
            elif t.array == "bounded" and len(items) > t.size:
                yield make("invalid-default", f"{what}: the array holds at most {t.size} elements, "
                           f"the list has {len(items)}", src, v.span)
        assert isinstance(t, (m.ArrayType, m.SetType))
        for item in items:
            yield from check_value(iface, t.element, item, what)
        return
    if kind == "map":
        if v.kind != "map":
            yield make("invalid-default", f"{what}: a map needs {{key: value}}, not {_show(v)}", src, v.span)
            return
        assert isinstance(t, m.MapType)
        for key, val in v.value:
            yield from check_value(iface, t.key, key, what)
            yield from check_value(iface, t.element, val, what)
        return
    assert isinstance(t, m.NamedType)
    target = t.target
    if isinstance(target, m.Enum):
        if v.kind != "int":
            yield make("invalid-default", f"{what}: enum '{target.name}' needs one of its values", src, v.span)
        elif not target.has_number(v.value):
            yield make("invalid-default", f"{what}: {v.value} is not a value of enum '{target.name}'", src, v.span)
    elif isinstance(target, m.Struct):
        if v.kind != "map":
            yield make("invalid-default", f"{what}: '{target.name}' needs {{field: value}}, not {_show(v)}",
                       src, v.span)
    elif isinstance(target, m.Senum):
        if v.kind != "string":
            yield make("invalid-default", f"{what}: senum '{target.name}' needs a string", src, v.span)


def _literal_fits(v: m.Value) -> bool:
    """False for a number the parser already refused (beyond 64 bits or float64): no second finding."""
    if v.kind == "int":
        lo, hi = m.INT_LITERAL
        return lo <= v.value <= hi
    return v.kind != "double" or abs(v.value) < m.FLOAT64_MAX


def _non_finite(a: m.Annotation) -> bool:
    """True for a range, min or max string holding NaN or an infinity (numbers are checked when parsed)."""
    if a.value is None or a.value.kind != "string":
        return False
    for part in str(a.value.value).split(".."):
        try:
            if not math.isfinite(float(part)):
                return True
        except ValueError:
            continue
    return False


def _fits_float32(value: float) -> bool:
    """True when ``value`` rounds to a finite float32."""
    try:
        struct.pack("<f", value)
    except OverflowError:
        return False
    return True


def _show(v: m.Value) -> str:
    return {"int": "an integer", "double": "a number", "string": "a string", "name": "a name",
            "list": "a list", "map": "a map"}[v.kind]


@definition_rule
def values(iface: m.Interface, d: m.Definition) -> Iterator[Diagnostic]:
    """Defaults and constants fit their types."""
    for c in all_consts(d):
        yield from check_value(iface, c.type, c.value, f"constant '{c.name}'")
    for _, fields, _ in bodies(d):
        for f in fields:
            if f.default is not None:
                yield from check_value(iface, f.type, f.default, f"default of '{f.name}'")


@local_rule()
def bounds(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Bounds and sizes are positive; ROS arrays hold no arrays."""
    roots = [f.type for f in _fields(d)] + [c.type for c in all_consts(d)]
    if isinstance(d, m.Typedef):
        roots.append(d.type)
    for root in roots:
        stack: list[m.TypeRef] = [root]
        while stack:
            t = stack.pop()
            if isinstance(t, m.BaseType):
                if t.bound is not None and t.bound <= 0:
                    yield make("bounds-misuse", f"a string bound must be at least 1, not {t.bound}", src, t.span)
            elif isinstance(t, m.ArrayType):
                if t.size is not None and t.size <= 0:
                    yield make("bounds-misuse", f"an array size must be at least 1, not {t.size}", src, t.span)
                if not t.spelled_list and isinstance(t.element, m.ArrayType) and not t.element.spelled_list:
                    yield make("bounds-misuse", "an array of arrays cannot be written for ROS 2: "
                               "wrap the inner array in a message", src, t.span, severity=Severity.WARNING)
                stack.append(t.element)
            elif isinstance(t, m.SetType):
                stack.append(t.element)
            elif isinstance(t, m.MapType):
                stack.extend((t.key, t.element))


def _fields(d: m.Definition) -> Iterator[m.Field]:
    for _, fields, _ in bodies(d):
        yield from fields


# ---------------------------------------------------------------------------
# services, actions, functions


@local_rule()
def service_forms(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Service and action bodies are one form, with all their parts."""
    if isinstance(d, m.Service):
        kinds = [bool(d.functions), bool(d.flat_fields), bool(d.sections)]
        if sum(kinds) > 1:
            yield make("mixed-service-forms", f"service '{d.name}' mixes "
                       + " and ".join(w for w, k in zip(("functions", "plain fields", "sections"), kinds) if k)
                       + ": use one form", src, d.name_span)
            return
        yield from _parts(src, d, SERVICE_PARTS, "service")
    elif isinstance(d, m.Action):
        if d.flat_fields and d.sections:
            yield make("mixed-service-forms", f"action '{d.name}' mixes plain fields and sections",
                       src, d.name_span)
            return
        yield from _parts(src, d, ACTION_PARTS, "action")


def _parts(src: Source, d: m.Service | m.Action, parts: tuple[str, ...], word: str) -> Iterator[Diagnostic]:
    if d.form == "explicit":
        seen: dict[str, m.Section] = {}
        for sec in d.sections:
            if sec.name not in parts:
                yield make("unknown-section", f"a {word} has no part '{sec.name}'; its parts are "
                           + ", ".join(parts), src, sec.name_span)
            elif sec.name in seen:
                yield make("duplicate-field", f"'{sec.name}' is already given", src, sec.name_span,
                           related=[Related(src, seen[sec.name].name_span, "first given here")])
            seen.setdefault(sec.name, sec)
        missing = [p for p in parts if p not in seen]
        if missing:
            yield make("service-part-missing", f"{word} '{d.name}' has no {' and no '.join(missing)}"
                       f" (write `{missing[0]} {{}}` for an empty one)", src, d.name_span, missing=missing)
    elif d.form == "flat" and src.path.endswith(".iface"):
        code = "flat-service" if word == "service" else "flat-action"
        yield make(code, f"{word} '{d.name}' lists plain fields, read as {flat_reading(d)}; "
                   f"write the parts explicitly to say what is meant", src, d.name_span)


@definition_rule
def functions(iface: m.Interface, d: m.Definition) -> Iterator[Diagnostic]:
    """oneway functions return nothing; throws names exceptions; extends names a service."""
    src = iface.source
    if isinstance(d, m.Service):
        if d.extends is not None and d.extends.target is not None and not isinstance(d.extends.target, m.Service):
            yield make("wrong-kind", f"'{d.extends.name}' is not a service and cannot be extended", src, d.extends.span)
        for fn in d.functions:
            if fn.oneway and (fn.returns is not None or fn.throws):
                yield make("oneway-not-void", f"oneway function '{fn.name}' must return void and throw nothing",
                           src, fn.name_span)
            for t in fn.throws:
                target = resolve_typedefs(t.type)
                if isinstance(target, m.NamedType) and target.target is not None and not (
                        isinstance(target.target, m.Struct) and target.target.kind == "exception"):
                    yield make("throws-not-exception", f"'{type_text(t.type)}' is not an exception",
                               src, t.type.span)


@definition_rule
def field_kinds(iface: m.Interface, d: m.Definition) -> Iterator[Diagnostic]:
    """A field's type is a type: not a service, action or constant; unions have no required fields."""
    src = iface.source
    for f in _fields(d):
        t = f.type
        while isinstance(t, (m.ArrayType, m.SetType)):
            t = t.element
        if isinstance(t, m.NamedType) and isinstance(t.target, (m.Service, m.Action, m.Const)):
            yield make("wrong-kind", f"'{t.name}' is a {t.target.kind}, not a type", src, t.span)
    if isinstance(d, m.Struct) and d.kind == "union":
        for f in d.fields:
            if f.requiredness == "required":
                yield make("required-in-union", f"union field '{f.name}' cannot be required", src, f.span)


@rule()
def components(iface: m.Interface) -> Iterator[Diagnostic]:
    """At most one component declaration."""
    src = iface.source
    decls = iface.component_decls
    for extra in decls[1:]:
        yield make("duplicate-component", "the file already declares its component", src, extra.span,
                   related=[Related(src, decls[0].span, "component declared here")])


@local_rule()
def deprecated(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Syntax Thrift itself deprecates."""
    if isinstance(d, m.Senum):
        yield make("deprecated-syntax", "senum is deprecated in Thrift: use an enum or string constants",
                   src, d.name_span)


@local_rule()
def parameter_defaults(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """A parameter without a default must be given a value whenever the component starts."""
    if isinstance(d, m.Struct) and d.kind == "configuration":
        for f in d.fields:
            if f.default is None:
                yield make("missing-default", f"parameter '{f.name}' has no default: every launch must set it",
                           src, f.name_span, name=f.name)


@local_rule()
def parameter_ranges(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Configuration ranges are well formed and hold the default."""
    if not isinstance(d, m.Struct):
        return
    for f in d.fields:
        keys = [a for a in f.annotations if a.key in ("range", "min", "max")]
        if not keys:
            continue
        rng = f.range
        if rng is None:
            odd = next((a for a in keys if _non_finite(a)), None)
            if odd is not None:
                yield make("number-out-of-range", f"'{f.name}': a range bound must be a finite number, not "
                           f"'{shorten(odd.text)}'; leave a side empty for no bound (range = \"0..\")",
                           src, odd.span)
            elif not any(a.value is not None and not _literal_fits(a.value) for a in keys):
                yield make("param-range", f"'{f.name}': write the range as range = \"lo..hi\" "
                           "or min/max numbers", src, keys[0].span)
            continue
        lo, hi = rng
        if lo is not None and hi is not None and lo > hi:
            yield make("param-range", f"'{f.name}': the range {lo}..{hi} is empty", src, keys[0].span)
        elif f.default is not None and f.default.kind in ("int", "double"):
            val = float(f.default.value)
            if (lo is not None and val < lo) or (hi is not None and val > hi):
                yield make("param-range", f"'{f.name}': the default {f.default.text} lies outside its range",
                           src, f.default.span)


# ---------------------------------------------------------------------------
# robot targets


@local_rule(robot_only=True)
def ros_names(src: Source, d: m.Definition) -> Iterator[Diagnostic]:
    """Names ROS 2 cannot use as they are: converted with a warning, or refused."""
    if isinstance(d, (m.Struct, m.Service, m.Action)) and not (
            isinstance(d, m.Struct) and d.kind in ("configuration", "state")) and not (
            isinstance(d, m.Service) and d.is_diagnostics):
        if not is_ros_type(d.name):
            yield _ros_name(src, d.name, ros_type_name(d.name), d.name_span, "type")
    if isinstance(d, m.Struct) and d.kind == "configuration":
        return
    for _, fields, consts in bodies(d):
        for f in fields:
            if f.default is not None and is_ros_constant(f.name) and not is_ros_field(f.name):
                yield _constant_as_field(src, f)
            elif not is_ros_field(f.name):
                yield _ros_name(src, f.name, ros_field_name(f.name), f.name_span, "field")
        for c in consts:
            if not is_ros_constant(c.name):
                yield _ros_name(src, c.name, ros_constant_name(c.name), c.name_span, "constant")


def _constant_as_field(src: Source, f: m.Field) -> Diagnostic:
    """``uint8 LEVEL=1``: a ROS 2 constant, but in .iface a field with a default."""
    assert f.default is not None
    value = src.text[f.default.span.start:f.default.span.end] or f.default.text
    t = f.type
    spelled = (t.name + (f"<={t.bound}" if t.bound is not None else "")) if isinstance(t, m.BaseType) \
        else type_text(t)
    const = f"const {spelled} {f.name} = {value}"
    return make("ros-constant-as-field",
                f"'{f.name}' is a field with the default {value}, not a constant: ROS 2 writes a constant "
                f"`{src.text[f.type.span.start:f.type.span.end]} {f.name}={value}`, .iface writes `{const}`",
                src, f.name_span, name=f.name, replacement=const, start=f.span.start, end=f.span.end)


def _ros_name(src: m.Source, name: str, new: str | None, span: m.Span, what: str) -> Diagnostic:
    if new is None:
        return make("ros-name-invalid", f"{what} name '{name}' cannot be made a valid ROS 2 {what} name",
                    src, span, name=name)
    return make("ros-naming", f"{what} name '{name}' is not a ROS 2 {what} name; it becomes '{new}' in ROS 2",
                src, span, name=name, replacement=new)


@wiring_rule
def topic_names(src: Source, w: m.Wiring) -> Iterator[Diagnostic]:
    """Topic and service names follow ROS 2 rules."""
    t = w.topic
    if not _TOPIC.match(t) or "//" in t or t.endswith("/") or "__" in t:
        yield make("invalid-topic-name", f"'{t}' is not a valid ROS 2 name: use letters, digits, "
                       "'_' and '/' separators, not starting with a digit", src, w.topic_span)


@wiring_rule
def qos_settings(src: Source, w: m.Wiring) -> Iterator[Diagnostic]:
    """QoS annotations name ROS 2 policies with values they can take."""
    for a in w.annotations:
        if not a.key.startswith("qos."):
            continue
        found = qos_problem(a.key[4:], a.text)
        if found is not None:
            is_error, message = found
            yield make("invalid-qos", message, src, a.span,
                       severity=Severity.ERROR if is_error else Severity.WARNING)
            continue
        lacking = qos_downgrade(a.key[4:], a.text)
        if lacking is not None:
            yield make("qos-not-in-rmw", lacking, src, a.span)


def struct_members(s: m.Struct) -> Iterator[tuple[m.Field, m.Struct]]:
    """(field, struct) for every struct a field of ``s`` holds, through containers and typedefs."""
    for f in s.fields:
        if type(f.type) is m.BaseType:
            continue  # most fields: nothing to follow
        stack: list[m.TypeRef] = [f.type]
        seen: set[int] = set()  # each container once: a typedef cycle (cut, and reported) never loops here
        while stack:
            t = resolve_typedefs(stack.pop())
            if id(t) in seen:
                continue
            seen.add(id(t))
            if isinstance(t, m.NamedType):
                if isinstance(t.target, m.Struct):
                    yield f, t.target
            elif isinstance(t, m.MapType):
                stack.extend((t.key, t.element))
            elif not isinstance(t, m.BaseType):
                stack.append(t.element)


@rule(robot_only=True)
def recursion(iface: m.Interface) -> Iterator[Diagnostic]:
    """A type that contains itself (ROS 2 and PX4 messages cannot)."""
    yield from recursive_types(iface, [d for d in iface.definitions if isinstance(d, m.Struct)], set())


def recursive_types(iface: m.Interface, structs: list[m.Struct], involved: set[int]) -> Iterator[Diagnostic]:
    """``recursion`` over the file's ``structs`` (in order); ``involved`` gets the ids of the structs on a cycle."""
    src = iface.source
    state: dict[int, int] = {}  # id -> 1 visiting, 2 done
    reported: set[int] = set()
    local = {id(s) for s in structs}

    for root in structs:
        if state.get(id(root)):
            continue
        path: list[tuple[m.Struct, Iterator[tuple[m.Field, m.Struct]]]] = [(root, struct_members(root))]
        state[id(root)] = 1
        while path:
            node, it = path[-1]
            step = next(it, None)
            if step is None:
                state[id(node)] = 2
                path.pop()
                continue
            f, child = step
            mark = state.get(id(child))
            if mark == 1:
                at = next(i for i, (x, _) in enumerate(path) if x is child)
                involved.update(id(x) for x, _ in path[at:])
                if id(f) not in reported and id(node) in local:
                    reported.add(id(f))
                    yield make("recursive-type", f"'{node.name}' contains itself through '{f.name}': "
                               "ROS 2 and PX4 messages cannot be recursive", src, f.span)
            elif mark is None:
                state[id(child)] = 1
                path.append((child, struct_members(child)))
