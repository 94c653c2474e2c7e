"""Lower a compiled interface to a ROS 2 interface package (shared by the ``ros2`` and ``idl`` targets).

What becomes what (see docs/targets.md):
- ``message``, ``struct`` and ``exception`` → a message; ``union`` and ``senum`` → an error;
- a flat or sectioned ``service`` → one service; a Thrift function ``f`` of service ``S`` →
  the service ``SF`` (request: the arguments; response: ``result`` unless void; ``throws`` → error);
- ``action`` → an action; the state Σ → ``<Component>State``; top-level constants →
  ``<Component>Constants`` (constants only); configuration P → parameters;
- a field of an enum type → ``int32`` plus the enum's values as ``<ENUM>_<VALUE>`` constants in
  the same message; typedefs are followed; ``binary`` → ``uint8[]``; ``uuid`` → ``uint8[16]``.
Values are decoded to Python values here; each target checks and writes them its own way.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field, replace

from ... import model as m
from ...compile import Compilation
from ...diagnostics import Diagnostic, make
from ...naming import (is_ros_constant, is_ros_field, is_ros_type, ros_constant_name, ros_field_name,
                       ros_type_name)
from ...resolve import constant_value
from ...source import Source, Span
from ...walk import resolve_typedefs, type_text
from .. import types
from ..base import sort_diagnostics
from ..support import Owners, component_span
from ..text import doc_lines, header_name
from .codes import diag

Scalar = bool | int | float | str
PyValue = Scalar | list[Scalar]

_INT_PRIMITIVES = frozenset({"int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
                             "byte", "char"})
_FLOAT_PRIMITIVES = frozenset({"float32", "float64"})
_STRING_PRIMITIVES = frozenset({"string", "wstring"})
_PACKAGE_CHARS = re.compile(r"^[A-Za-z0-9_.\-]+$")
_EMAIL = re.compile(r"^[-a-zA-Z0-9_%+]+(\.[-a-zA-Z0-9_%+]+)*@[-a-zA-Z0-9%]+(\.[-a-zA-Z0-9%]+)*\.[a-zA-Z]{2,}$")
_NODE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_VERSION = re.compile(r"^[0-9]+(\.[0-9]+){0,2}$")
#: The integer type an enum field gets (Thrift enums are 32-bit).
ENUM_PRIMITIVE = "int32"


@dataclass(frozen=True, slots=True)
class RosType:
    """A ROS 2 field type: a primitive or a named message, maybe bounded, maybe an array."""

    primitive: str | None = None
    package: str | None = None
    name: str | None = None
    string_bound: int | None = None
    array: str | None = None
    size: int | None = None

    @property
    def element(self) -> RosType:
        """The type without its array suffix."""
        return replace(self, array=None, size=None)

    def core(self, package: str) -> str:
        """The element type as written in a .msg file of ``package``."""
        if self.primitive is not None:
            return self.primitive + (f"<={self.string_bound}" if self.string_bound is not None else "")
        return self.name if self.package == package else f"{self.package}/{self.name}"  # type: ignore[return-value]

    def msg(self, package: str) -> str:
        """The type as written in a .msg file of ``package``."""
        core = self.core(package)
        if self.array == "fixed":
            return f"{core}[{self.size}]"
        if self.array == "bounded":
            return f"{core}[<={self.size}]"
        if self.array == "unbounded":
            return f"{core}[]"
        return core


@dataclass(slots=True)
class RosField:
    """A field with its ROS name, type, decoded default and comment lines."""

    name: str
    type: RosType
    default: PyValue | None
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosConst:
    """A constant: primitive type, ROS name, decoded value."""

    name: str
    primitive: str
    value: Scalar
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosSection:
    """One part of an interface: the body of a message, a request, a goal…

    ``comments`` are the lines of the part's own doc comment (``/** … */ response { … }``).
    """

    name: str
    fields: list[RosField] = field(default_factory=list)
    consts: list[RosConst] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)


@dataclass(slots=True)
class RosInterface:
    """One interface file: ``msg`` (one section), ``srv`` (two) or ``action`` (three)."""

    kind: str
    name: str
    sections: list[RosSection]
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosParam:
    """A parameter of the node: name as written, type, default (None: no default, for the reason in ``note``)."""

    name: str
    type: RosType
    value: PyValue | None
    comments: list[str]
    note: str = "no default; set it at launch"


@dataclass(slots=True)
class RosPackage:
    """Everything a ROS 2 interface package holds."""

    name: str
    component: str
    node: str
    version: str
    description: str
    maintainer: str
    maintainer_email: str
    license: str
    source_name: str
    #: Where the package name is stated (its ``namespace ros2``, else the start of the file).
    name_source: Source
    name_span: Span
    interfaces: list[RosInterface] = field(default_factory=list)
    depends: list[str] = field(default_factory=list)
    params: list[RosParam] = field(default_factory=list)
    #: Where the component (hence the node) is named, in ``name_source``.
    node_span: Span = field(default_factory=lambda: Span(0, 0))

    def of_kind(self, kind: str) -> list[RosInterface]:
        """The interfaces of one kind, by name."""
        return sorted((i for i in self.interfaces if i.kind == kind), key=lambda i: i.name)

    def identifiers(self) -> Iterator[tuple[str, str, Source, Span]]:
        """(what, name, source, span) of every identifier generated code declares from the model.

        The package, each message, and every field and constant; service and action
        types carry a suffix (``_Request``, ``_Goal``…) and are left out.
        """
        yield f"package '{self.name}'", self.name, self.name_source, self.name_span
        for ri in self.interfaces:
            if ri.kind == "msg":
                yield f"message '{ri.name}'", ri.name, ri.source, ri.span
            for sec in ri.sections:
                for f in sec.fields:
                    yield f"field '{f.name}' of {ri.kind}/{ri.name}", f.name, f.source, f.span
                for c in sec.consts:
                    yield f"constant '{c.name}' of {ri.kind}/{ri.name}", c.name, c.source, c.span


def _field_comments(f: m.Field) -> list[str]:
    lines = doc_lines(f.doc)
    extra = []
    if f.unit:
        extra.append(f"unit: {f.unit}")
    rng = f.range
    if rng is not None:
        lo, hi = ("" if x is None else format(x, "g") for x in rng)
        extra.append(f"range: {lo}..{hi}")
    if extra:
        lines.append(", ".join(extra))
    return doc_lines("\n".join(lines))


def _namespace_name_span(source: Source, ns: m.Namespace) -> Span:
    """Where the name of ``namespace ros2 NAME`` stands (the whole statement if it cannot be found)."""
    text = source.text
    after_scope = text.find(ns.scope, ns.span.start, ns.span.end)
    start = text.find(ns.name, after_scope + len(ns.scope), ns.span.end) if after_scope >= 0 else -1
    return Span(start, start + len(ns.name)) if start >= 0 else ns.span


class _Lowering:
    """One lowering run: collects diagnostics while it builds the package."""

    def __init__(self, comp: Compilation) -> None:
        self.comp = comp
        self.iface = comp.interface
        self.diags: list[Diagnostic] = []
        self.owners = Owners(comp)
        self.interfaces: list[m.Interface] = [c.interface for c in comp.closure()]
        self._packages: dict[int, str | None] = {}
        self._package_spans: dict[int, Span] = {}
        self._type_names: dict[int, str | None] = {}
        self.depends: set[str] = set()

    # ---- diagnostics -----------------------------------------------------------
    def error(self, code: str, message: str, source: Source, span: Span) -> None:
        self.diags.append(diag(code, message, source, span))

    def renamed(self, what: str, name: str, new: str | None, source: Source, span: Span) -> str | None:
        """Report a converted (warning) or unconvertible (error) name; return the ROS name."""
        if new is None:
            self.diags.append(make("ros-name-invalid", f"{what} name '{name}' cannot be made a valid "
                                   f"ROS 2 {what} name", source, span, name=name))
        elif new != name:
            self.diags.append(make("ros-naming", f"{what} name '{name}' is not a ROS 2 {what} name; "
                                   f"it becomes '{new}' in ROS 2", source, span, name=name, replacement=new))
        return new

    # ---- names -------------------------------------------------------------------
    def package_of(self, iface: m.Interface) -> str | None:
        """The ROS package of a file: its ``ros2`` namespace, else its file stem."""
        key = id(iface)
        if key in self._packages:
            return self._packages[key]
        ns = next((n for n in iface.namespaces if n.scope == "ros2"), None)
        raw = ns.name if ns is not None else iface.source.path.replace("\\", "/").rpartition("/")[2].rsplit(".", 1)[0]
        span = _namespace_name_span(iface.source, ns) if ns is not None else Span(0, 0)
        self._package_spans[key] = span
        new = ros_field_name(raw) if _PACKAGE_CHARS.match(raw) else None
        if new is None:
            self.error("ros-name-invalid", f"package name '{raw}' cannot be made a valid ROS 2 package name "
                       "(lower-case letters, digits and single underscores)", iface.source, span)
        elif new != raw:
            self.diags.append(make("ros-naming", f"package name '{raw}' is not a ROS 2 package name; it becomes "
                                   f"'{new}' in ROS 2", iface.source, span, name=raw, replacement=new))
        self._packages[key] = new
        return new

    def type_name(self, d: m.Definition, *, suffix: str = "") -> str | None:
        """The ROS name of a definition, reported once when it changes.

        The diagnostics service Δ is named by the language (``service diagnostics``),
        so its conversion (``Diagnostics``) is silent, as in the core checks.
        """
        key = id(d)
        if key not in self._type_names:
            owner = self.owners.of(d)
            new = ros_type_name(d.name)
            if isinstance(d, m.Service) and d.is_diagnostics and new is not None:
                self._type_names[key] = new
            else:
                self._type_names[key] = self.renamed("type", d.name, new, owner.source, d.name_span)
        base = self._type_names[key]
        return None if base is None else base + suffix

    def field_name(self, name: str, source: Source, span: Span) -> str | None:
        return self.renamed("field", name, name if is_ros_field(name) else ros_field_name(name), source, span)

    def const_name(self, name: str, source: Source, span: Span) -> str | None:
        return self.renamed("constant", name, name if is_ros_constant(name) else ros_constant_name(name),
                            source, span)

    # ---- types -------------------------------------------------------------------
    def ros_type(self, t: m.TypeRef, owner: m.Interface, enums: list[m.Enum]) -> RosType | None:
        """The ROS type of ``t``; enums it uses are appended to ``enums``; None after an error."""
        src = owner.source
        t = resolve_typedefs(t)
        if isinstance(t, m.BaseType):
            if t.name == "binary":
                return RosType(primitive="uint8", array="unbounded")
            if t.name == "uuid":
                return RosType(primitive="uint8", array="fixed", size=16)
            return RosType(primitive=types.ros2_base(t.name), string_bound=t.bound)
        if isinstance(t, m.ArrayType):
            element = self.ros_type(t.element, owner, enums)
            if element is None:
                return None
            if element.array is not None:
                self.error("ros2-unsupported", "an array of arrays has no ROS 2 equivalent (binary and uuid "
                           "are arrays too): wrap the inner array in a message", src, t.span)
                return None
            return replace(element, array=t.array, size=t.size)
        if isinstance(t, (m.SetType, m.MapType)):
            hint = ("use an array T[] (ROS 2 keeps duplicates)" if isinstance(t, m.SetType)
                    else "use an array of key/value messages")
            what = "set<…>" if isinstance(t, m.SetType) else "map<…>"
            self.error("ros2-unsupported", f"a {what} has no ROS 2 equivalent: {hint}", src, t.span)
            return None
        assert isinstance(t, m.NamedType)
        if t.external is not None:
            local = t.local_name
            if not is_ros_type(local):
                self.error("ros-name-invalid", f"'{t.name}' is not a ROS 2 type name", src, t.span)
                return None
            if not is_ros_field(t.external):  # rosidl's package names follow the field name pattern
                self.error("ros-name-invalid", f"'{t.external}' is not a ROS 2 package name (lower-case letters, "
                           f"digits and single underscores): rosidl refuses '{t.external}/{local}'", src, t.span)
                return None
            self.depends.add(t.external)
            return RosType(package=t.external, name=local)
        target = t.target
        if target is None:
            return None  # reported by the checks as unknown-type
        if isinstance(target, m.Enum):
            if target not in enums:
                enums.append(target)
            return RosType(primitive=ENUM_PRIMITIVE)
        if isinstance(target, m.Struct) and target.kind in ("message", "struct", "exception"):
            defining = self.owners.of(target, owner)
            package = self.package_of(defining)
            name = self.type_name(target)
            if package is None or name is None:
                return None
            if package != self.package_of(self.iface):
                self.depends.add(package)
            return RosType(package=package, name=name)
        kind = getattr(target, "kind", "definition")
        self.error("ros2-unsupported", f"'{t.name}' is a {kind}, which a ROS 2 field cannot hold", src, t.span)
        return None

    # ---- values ------------------------------------------------------------------
    def scalar(self, v: m.Value, primitive: str, enum: m.Enum | None, owner: m.Interface,
               depth: int = 0) -> Scalar | None:
        """A single value decoded for ``primitive``; None after an error."""
        src = owner.source
        if v.kind == "name" and depth < 16:
            name = str(v.value)
            if primitive == "bool" and name.lower() in ("true", "false"):
                return name.lower() == "true"
            if enum is not None:
                local = name.rpartition(".")[2]
                for ev in enum.values:
                    if ev.name == local and (name == local or name.rpartition(".")[0].endswith(enum.name)):
                        return ev.value
            ref = constant_value(owner, name)
            if isinstance(ref, m.EnumValue):
                return self._check_int(ref.value, primitive, v, src)
            if isinstance(ref, m.Const):
                return self.scalar(ref.value, primitive, None, self.owners.of(ref, owner), depth + 1)
            self.error("ros2-unsupported-default", f"'{name}' names no constant or enum value", src, v.span)
            return None
        if primitive == "bool":
            if v.kind == "int" and v.value in (0, 1):
                return bool(v.value)
        elif primitive in _INT_PRIMITIVES:
            if v.kind == "int":
                return self._check_int(int(v.value), primitive, v, src)
        elif primitive in _FLOAT_PRIMITIVES:
            if v.kind in ("int", "double"):
                return float(v.value)
        elif primitive in _STRING_PRIMITIVES:
            if v.kind == "string":
                return str(v.value)
        self.error("ros2-unsupported-default", f"{v.text or v.kind} is not a {primitive} value", src, v.span)
        return None

    def _check_int(self, value: int, primitive: str, v: m.Value, src: Source) -> int | None:
        lo, hi = _INT_RANGE[primitive]
        if lo <= value <= hi:
            return value
        self.error("ros2-unsupported-default", f"{value} does not fit {primitive} ({lo}..{hi})", src, v.span)
        return None

    def value(self, v: m.Value, rt: RosType, enum: m.Enum | None, owner: m.Interface) -> PyValue | None:
        """A default decoded for ``rt``; None after an error."""
        src = owner.source
        if rt.primitive is None:
            self.error("ros2-unsupported-default", "ROS 2 cannot give a default to a field of a message type",
                       src, v.span)
            return None
        if rt.array is None:
            out = self.scalar(v, rt.primitive, enum, owner)
            if isinstance(out, str) and rt.string_bound is not None and len(out) > rt.string_bound:
                self.error("ros2-unsupported-default", f"the default is {len(out)} characters long, more than "
                           f"the bound {rt.string_bound}", src, v.span)
                return None
            return out
        if v.kind != "list":
            self.error("ros2-unsupported-default", f"the default of an array must be a list [a, b, …], "
                       f"not {v.text or v.kind}", src, v.span)
            return None
        items: list[m.Value] = list(v.value)
        if rt.array == "fixed" and len(items) != rt.size:
            self.error("ros2-unsupported-default", f"a default for a [{rt.size}] array must list exactly "
                       f"{rt.size} values, not {len(items)}", src, v.span)
            return None
        if rt.array == "bounded" and rt.size is not None and len(items) > rt.size:
            self.error("ros2-unsupported-default", f"a default for a [<={rt.size}] array may list at most "
                       f"{rt.size} values, not {len(items)}", src, v.span)
            return None
        decoded = [self.scalar(x, rt.primitive, enum, owner) for x in items]
        values = [x for x in decoded if x is not None]
        return values if len(values) == len(decoded) else None

    # ---- members -----------------------------------------------------------------
    def section(self, name: str, fields: list[m.Field], consts: list[m.Const], owner: m.Interface,
                doc: str | None = None) -> RosSection:
        """A section from fields, constants and a doc comment; enum values used by the fields become constants."""
        sec = RosSection(name, comments=doc_lines(doc))
        enums: list[m.Enum] = []
        src = owner.source
        for c in consts:
            rc = self.const(c, owner)
            if rc is not None:
                sec.consts.append(rc)
        for f in fields:
            fname = self.field_name(f.name, src, f.name_span)
            used: list[m.Enum] = []
            rt = self.ros_type(f.type, owner, used)
            for e in used:
                if e not in enums:
                    enums.append(e)
            if fname is None or rt is None:
                continue
            default = None
            if f.default is not None:
                default = self.value(f.default, rt, used[0] if used else None, owner)
            sec.fields.append(RosField(fname, rt, default, _field_comments(f), src, f.name_span))
        for e in enums:
            sec.consts.extend(self.enum_consts(e))
        self._clashes([(f.name, f.source, f.span) for f in sec.fields], "field")
        self._clashes([(c.name, c.source, c.span) for c in sec.consts], "constant")
        return sec

    def const(self, c: m.Const, owner: m.Interface) -> RosConst | None:
        """A body or top-level constant; only primitive, non-array constants exist in ROS 2."""
        src = owner.source
        name = self.const_name(c.name, src, c.name_span)
        enums: list[m.Enum] = []
        rt = self.ros_type(c.type, owner, enums)
        if name is None or rt is None:
            return None
        if rt.primitive is None or rt.array is not None:
            self.error("ros2-unsupported", f"constant '{c.name}': ROS 2 constants are single values of a "
                       "primitive type", src, c.name_span)
            return None
        value = self.scalar(c.value, rt.primitive, enums[0] if enums else None, owner)
        if value is None:
            return None
        return RosConst(name, rt.primitive, value, doc_lines(c.doc), src, c.name_span)

    def enum_consts(self, e: m.Enum) -> list[RosConst]:
        """``<ENUM>_<VALUE>`` constants of ENUM_PRIMITIVE for the values of an enum."""
        owner = self.owners.of(e)
        prefix = ros_constant_name(e.name)
        out = []
        for ev in e.values:
            local = ros_constant_name(ev.name)
            if prefix is None or local is None:
                self.error("ros-name-invalid", f"enum value '{e.name}.{ev.name}' cannot be made a ROS 2 "
                           "constant name", owner.source, ev.name_span)
                continue
            name = local if local.startswith(prefix + "_") else f"{prefix}_{local}"
            comments = doc_lines(ev.doc) or ([f"{e.name}.{ev.name}"] if name != ev.name else [])
            out.append(RosConst(name, ENUM_PRIMITIVE, ev.value, comments, owner.source, ev.name_span))
        return out

    def _clashes(self, names: list[tuple[str, Source, Span]], what: str) -> None:
        seen: dict[str, str] = {}
        for name, src, span in names:
            written = src.text[span.start:span.end]
            if name in seen:
                self.error("ros2-name-clash", f"{what} '{written}' becomes '{name}' in ROS 2, like "
                           f"'{seen[name]}' before it", src, span)
            else:
                seen[name] = written

    # ---- definitions -------------------------------------------------------------------
    def interfaces_of(self, d: m.Definition, owner: m.Interface) -> list[RosInterface]:
        """The ROS interfaces a definition becomes (none for enums, typedefs and constants)."""
        src = owner.source
        doc = doc_lines(getattr(d, "doc", None))
        if isinstance(d, m.Struct):
            if d.kind in ("message", "struct", "exception"):
                name = self.type_name(d)
                sec = self.section("message", d.fields, d.consts, owner)
                return [] if name is None else [RosInterface("msg", name, [sec], doc, src, d.name_span)]
            if d.kind == "union":
                self.error("ros2-unsupported", f"union '{d.name}' has no ROS 2 equivalent (a message holds all "
                           "its fields): use a message with a kind field", src, d.name_span)
            return []
        if isinstance(d, m.Senum):
            self.error("ros2-unsupported", f"senum '{d.name}' has no ROS 2 equivalent: use an enum or string "
                       "constants", src, d.name_span)
            return []
        if isinstance(d, m.Service):
            return self.service(d, owner, doc)
        if isinstance(d, m.Action):
            name = self.type_name(d)
            extra = list(d.consts)
            secs = []
            for part, part_sec in (("goal", d.goal), ("result", d.result), ("feedback", d.feedback)):
                fields = part_sec.fields if part_sec else []
                consts = (part_sec.consts if part_sec else []) + (extra if part == "goal" else [])
                secs.append(self.section(part, fields, consts, owner, part_sec.doc if part_sec else None))
            return [] if name is None else [RosInterface("action", name, secs, doc, src, d.name_span)]
        return []

    def service(self, d: m.Service, owner: m.Interface, doc: list[str]) -> list[RosInterface]:
        src = owner.source
        if d.form != "functions":
            name = self.type_name(d)
            req = self.section("request", d.request.fields if d.request else [],
                               (d.request.consts if d.request else []) + list(d.consts), owner,
                               d.request.doc if d.request else None)
            res = self.section("response", d.response.fields if d.response else [],
                               d.response.consts if d.response else [], owner,
                               d.response.doc if d.response else None)
            return [] if name is None else [RosInterface("srv", name, [req, res], doc, src, d.name_span)]
        out = []
        base = self.type_name(d)
        for fn in d.functions:
            fname = ros_type_name(fn.name)
            if fname is None:
                self.error("ros-name-invalid", f"function name '{fn.name}' cannot be part of a ROS 2 type name",
                           src, fn.name_span)
                continue
            if fn.throws:
                self.error("ros2-unsupported", f"'{d.name}.{fn.name}' throws exceptions, which ROS 2 services "
                           "cannot: return an error field in the response instead", src, fn.throws[0].span)
            req = self.section("request", fn.params, [], owner)
            result: list[m.Field] = []
            if fn.returns is not None:
                result = [m.Field("result", fn.returns, fn.returns.span, fn.returns.span)]
            res = self.section("response", result, [], owner)
            if base is not None:
                comments = doc_lines(fn.doc) or doc
                out.append(RosInterface("srv", base + fname, [req, res], comments, src, fn.name_span))
        if d.consts and out:
            out[0].sections[0].consts.extend(c for c in (self.const(c, owner) for c in d.consts) if c)
        return out

    # ---- the package ---------------------------------------------------------------------
    def package(self) -> RosPackage | None:
        iface = self.iface
        src = iface.source
        name = self.package_of(iface)
        component = iface.name
        comp_type = ros_type_name(component)
        if comp_type is None:
            self.error("ros-name-invalid", f"component name '{component}' cannot be made a ROS 2 type name",
                       src, component_span(iface))
        node = self.node_name(component)
        if name is None or node is None:
            return None
        pkg = RosPackage(name=name, component=component, node=node, version=self.version(),
                         description=self.annotation("description") or (
                             (doc_lines(iface.component.doc) if iface.component else []) or
                             [f"ROS 2 interfaces of the {component} component."])[0],
                         maintainer=self.annotation("maintainer") or "unknown",
                         maintainer_email=self.email(),
                         license=self.annotation("license") or "TODO",
                         source_name=header_name(src.path), name_source=src,
                         name_span=self._package_spans[id(iface)], node_span=component_span(iface))
        for other in self.interfaces:
            if other is not iface and self.package_of(other) != name:
                continue
            for d in other.definitions:
                if isinstance(d, m.Struct) and d.kind in ("configuration", "state") and other is not iface:
                    continue
                pkg.interfaces.extend(self.interfaces_of(d, other))
        consts = [(d, other) for other in self.interfaces if other is iface or self.package_of(other) == name
                  for d in other.definitions if isinstance(d, m.Const)]
        if consts and comp_type is not None:
            sec = RosSection("message", [], [c for c in (self.const(c, o) for c, o in consts) if c])
            self._clashes([(c.name, c.source, c.span) for c in sec.consts], "constant")
            pkg.interfaces.append(RosInterface("msg", comp_type + "Constants", [sec],
                                               [f"Constants of {component}."], consts[0][1].source,
                                               consts[0][0].name_span))
        if iface.state and comp_type is not None:
            states = [d for d in iface.definitions if isinstance(d, m.Struct) and d.kind == "state"]
            sec = self.section("message", iface.state, [c for s in states for c in s.consts], iface)
            doc = next((doc_lines(s.doc) for s in states if s.doc), [f"The state of {component}."])
            pkg.interfaces.append(RosInterface("msg", comp_type + "State", [sec], doc, src, states[0].name_span))
        pkg.params = self.params()
        seen: dict[tuple[str, str], RosInterface] = {}
        for ri in pkg.interfaces:
            key = (ri.kind, ri.name)
            if key in seen:
                self.error("ros2-name-clash", f"two definitions become {ri.kind}/{ri.name} in ROS 2",
                           ri.source, ri.span)
            seen[key] = ri
        if pkg.of_kind("action"):
            self.depends.add("action_msgs")
        self.depends.discard(name)
        pkg.depends = sorted(self.depends)
        return pkg

    def params(self) -> list[RosParam]:
        """The parameters P with their decoded defaults, refusing what a ROS 2 parameter cannot hold.

        ROS 2 parameters are bool, int64, double, string, byte[] and arrays of bool,
        int64, double or string; a YAML file cannot state an empty array (its type
        is unknown), nor an integer outside int64.
        """
        out = []
        src = self.iface.source
        for f in self.iface.parameters:
            problem = _param_type_problem(f.type)
            if problem is not None:
                self.error("ros2-param-type", f"parameter '{f.name}' is {type_text(f.type)}: {problem}; a ROS 2 "
                           "parameter is a bool, integer (int64), double, string, or an array of one of those",
                           src, f.type.span)
                continue
            enums: list[m.Enum] = []
            rt = self.ros_type(f.type, self.iface, enums)
            if rt is None:
                continue
            if rt.primitive == "uint64":
                self.error("ros2-param-uint64", f"parameter '{f.name}' is {type_text(f.type)}: ROS 2 integer "
                           "parameters are int64, so values above 9223372036854775807 cannot be set",
                           src, f.type.span)
            param = RosParam(f.name, rt, None, _field_comments(f))
            if f.default is not None:
                value = self.value(f.default, rt, enums[0] if enums else None, self.iface)
                param.value = self._param_value(f, value)
                if value == []:
                    param.note = ("no default: ROS 2 cannot load an empty list from YAML (its type is unknown); "
                                  "the node's own default applies")
            out.append(param)
        return out

    def _param_value(self, f: m.Field, value: PyValue | None) -> PyValue | None:
        """``value`` when a ROS 2 parameter file can state it; None (reported) when not."""
        assert f.default is not None
        src = self.iface.source
        if value == []:
            self.error("ros2-param-empty-list", f"parameter '{f.name}': ROS 2 cannot load an empty list from a "
                       "parameter file (it cannot tell its type); the default is written as a comment instead",
                       src, f.default.span)
            return None
        items = value if isinstance(value, list) else [value]
        lo, hi = _INT64
        if any(isinstance(x, int) and not isinstance(x, bool) and not lo <= x <= hi for x in items):
            self.error("ros2-param-value", f"parameter '{f.name}': the default {f.default.text or value} does not fit "
                       f"int64 ({lo}..{hi}), the type of every ROS 2 integer parameter", src, f.default.span)
            return None
        return value

    def node_name(self, component: str) -> str | None:
        """The node the parameters belong to: the component name, converted if ROS 2 refuses it."""
        if _NODE.match(component):
            return component
        return self.renamed("node", component, ros_field_name(component), self.iface.source,
                            component_span(self.iface))

    def annotation(self, key: str) -> str | None:
        comp = self.iface.component
        if comp is None:
            return None
        a = m.annotation(comp.annotations, key)
        return a.text if a is not None and a.text else None

    def email(self) -> str:
        email = self.annotation("maintainer_email")
        if email is None:
            return "unknown@example.com"
        if not _EMAIL.match(email):
            comp = self.iface.component
            assert comp is not None
            self.error("ros2-package-metadata", f"'{email}' is not an e-mail address package.xml accepts: "
                       "unknown@example.com is written instead", self.iface.source, comp.span)
            return "unknown@example.com"
        return email

    def version(self) -> str:
        comp = self.iface.component
        if comp is None or comp.version is None:
            return "0.0.0"
        if not _VERSION.match(comp.version):
            self.error("ros2-package-metadata", f"version '{comp.version}' is not MAJOR[.MINOR[.PATCH]]: package.xml "
                       "gets 0.0.0", self.iface.source, comp.span)
            return "0.0.0"
        parts = comp.version.split(".")
        return ".".join(str(int(p)) for p in parts + ["0"] * (3 - len(parts)))


_INT64 = m.INT_RANGES["i64"]


def _param_type_problem(t: m.TypeRef) -> str | None:
    """Why a ROS 2 parameter cannot have type ``t`` (typedefs followed), None when it can."""
    r = resolve_typedefs(t)
    if isinstance(r, m.MapType):
        return "ROS 2 parameters have no maps (use one parameter per key, or two arrays)"
    if isinstance(r, m.SetType):
        return "ROS 2 parameters have no sets (use an array)"
    element: m.TypeRef = r
    if isinstance(r, m.ArrayType):
        element = resolve_typedefs(r.element)
        nested = isinstance(element, (m.ArrayType, m.SetType, m.MapType)) or (
            isinstance(element, m.BaseType) and element.name in ("binary", "uuid"))
        if nested:
            return "ROS 2 parameters have no arrays of arrays"
    if isinstance(element, m.NamedType) and not isinstance(element.target, m.Enum):
        what = "arrays of messages" if element is not r else "message types"
        return f"ROS 2 parameters have no {what}"
    return None


_INT_RANGE: dict[str, tuple[int, int]] = {
    types_name: m.INT_RANGES[canonical]
    for canonical, row in types.BASE_TYPES.items()
    if canonical in m.INT_RANGES and (types_name := row.ros2) is not None
}


def lower(comp: Compilation) -> tuple[RosPackage | None, list[Diagnostic]]:
    """The ROS 2 package of a compilation and the diagnostics found on the way."""
    run = _Lowering(comp)
    pkg = run.package()
    return pkg, run.diags


#: A check of a lowered package: what a target's output syntax cannot hold.
PackageCheck = Callable[[RosPackage], Iterable[Diagnostic]]


def lower_checked(comp: Compilation, *checks: PackageCheck) -> tuple[RosPackage | None, list[Diagnostic]]:
    """``lower``, then every check over the package; the diagnostics sorted."""
    pkg, diagnostics = lower(comp)
    if pkg is not None:
        for check in checks:
            diagnostics.extend(check(pkg))
    return pkg, sort_diagnostics(diagnostics)
