"""The interface model: what every consumer of a compiled `.iface` file reads.

Nodes are plain slotted dataclasses; every node keeps its source ``span``
(character offsets into its file) and named nodes a ``name_span``.
Cross references (``NamedType.target``) are filled in by ``resolve``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar, Literal, TypeVar, Union

from .source import Source, Span, SpanTable

# ---------------------------------------------------------------------------
# Spans kept in a table


@dataclass(slots=True, eq=False)
class Node:
    """What every node with spans shares: the table its spans are kept in, when the parser made it.

    A node made by the parser keeps the index of its first span in its ``span`` slot and its chunk's
    ``SpanTable`` here; its other spans (``name_span`` and the like) follow at the next indices. Reading
    ``node.span`` then makes a span relative to the table, which moves with its chunk. A node made any other
    way holds its spans itself and ``_t`` is None; so does a parsed node once one of its spans is set.
    """

    _t: SpanTable | None = field(default=None, kw_only=True, repr=False, metadata={"derived": True})
    #: The raw slot of ``span`` (set on each class by ``spanned``): a parsed node's index in its table.
    _k: ClassVar[Any]


_T = TypeVar("_T")
_TABLE: Any = Node.__dict__["_t"]


def spanned(*names: str) -> Callable[[type[_T]], type[_T]]:
    """Make the span fields ``names`` (``span`` first) of a node class read from its table when it has one."""

    def wrap(cls: type[_T]) -> type[_T]:
        raws = [cls.__dict__[n] for n in names]
        first = raws[0]
        get_table, get_first = _TABLE.__get__, first.__get__

        def detach(node: Any) -> None:
            spans = [getattr(node, n) for n in names]
            _TABLE.__set__(node, None)
            for raw, span in zip(raws, spans):
                raw.__set__(node, span)

        def make(i: int, raw: Any) -> property:
            get_raw, set_raw = raw.__get__, raw.__set__

            def fget(node: Any) -> Span:
                table = get_table(node)
                if table is None:
                    return get_raw(node)
                return table.at(get_first(node) + i)

            def fset(node: Any, value: Any) -> None:
                if value.__class__ is not int and get_table(node) is not None:
                    detach(node)
                set_raw(node, value)

            return property(fget, fset, doc=f"The node's {names[i]}.")

        for i, (n, raw) in enumerate(zip(names, raws)):
            setattr(cls, n, make(i, raw))
        setattr(cls, "_k", first)
        setattr(cls, "__init__", _raw_init(cls, dict(zip(names, raws))))
        return cls

    return wrap


_FACTORY = object()


def _raw_init(cls: type, raws: dict[str, Any]) -> Callable[..., None]:
    """The dataclass ``__init__`` of ``cls``, but storing its spans in their slots directly: the parser makes
    some 40,000 nodes at 10k lines, and the spans' properties are for reading."""
    params: list[str] = []
    kw_only: list[str] = []
    body: list[str] = []
    names: dict[str, Any] = {"_FACTORY": _FACTORY}
    for f in dataclasses.fields(cls):
        assert f.init, f"{cls.__name__}.{f.name}: a field that __init__ does not take"  # none has one
        if f.default is not dataclasses.MISSING:
            names[f"_d_{f.name}"] = f.default
            default = f"=_d_{f.name}"
        elif f.default_factory is not dataclasses.MISSING:
            names[f"_f_{f.name}"] = f.default_factory
            default = "=_FACTORY"
        else:
            default = ""
        value = f.name
        if default == "=_FACTORY":
            value = f"_f_{f.name}() if {f.name} is _FACTORY else {f.name}"
        (kw_only if f.kw_only else params).append(f"{f.name}{default}")
        if f.name in raws:
            names[f"_s_{f.name}"] = raws[f.name].__set__
            body.append(f"    _s_{f.name}(self, {value})")
        else:
            body.append(f"    self.{f.name} = {value}")
    signature = ", ".join(["self", *params, *(["*", *kw_only] if kw_only else [])])
    exec(f"def __init__({signature}) -> None:\n" + "\n".join(body), names)  # noqa: S102
    init = names["__init__"]
    init.__qualname__ = f"{cls.__qualname__}.__init__"
    init.__doc__ = cls.__dict__["__init__"].__doc__
    return init

# ---------------------------------------------------------------------------
# Types

#: Canonical names of the base types, with their aliases.
BASE_ALIASES: dict[str, str] = {
    "bool": "bool",
    "byte": "i8", "i8": "i8", "int8": "i8",
    "i16": "i16", "int16": "i16",
    "i32": "i32", "int32": "i32",
    "i64": "i64", "int64": "i64",
    "u8": "u8", "uint8": "u8",
    "u16": "u16", "uint16": "u16",
    "u32": "u32", "uint32": "u32",
    "u64": "u64", "uint64": "u64",
    "float": "float32", "float32": "float32",
    "double": "float64", "float64": "float64",
    "string": "string", "wstring": "wstring",
    "binary": "binary", "uuid": "uuid",
    "char": "char", "wchar": "wchar", "octet": "octet",
}

#: Inclusive ranges of the integer base types (char and octet are 8-bit unsigned, wchar 16-bit as in rosidl).
INT_RANGES: dict[str, tuple[int, int]] = {
    "i8": (-(2**7), 2**7 - 1), "i16": (-(2**15), 2**15 - 1),
    "i32": (-(2**31), 2**31 - 1), "i64": (-(2**63), 2**63 - 1),
    "u8": (0, 2**8 - 1), "u16": (0, 2**16 - 1),
    "u32": (0, 2**32 - 1), "u64": (0, 2**64 - 1),
    "char": (0, 255), "wchar": (0, 2**16 - 1), "octet": (0, 255),
}
#: What an integer literal may be at all: the union of i64 and u64.
INT_LITERAL: tuple[int, int] = (-(2**63), 2**64 - 1)
FLOAT_TYPES = frozenset({"float32", "float64"})
#: The largest finite float64 and float32.
FLOAT64_MAX = 1.7976931348623157e308
FLOAT32_MAX = 3.4028234663852886e38
STRING_TYPES = frozenset({"string", "wstring"})


@spanned("span")
@dataclass(slots=True, eq=False)
class BaseType(Node):
    """A builtin type; ``bound`` is the maximum length of a bounded string."""

    name: str
    span: Span
    spelling: str = ""
    bound: int | None = None
    annotations: Sequence[Annotation] = ()

    kind: ClassVar[Literal["base"]] = "base"


@spanned("span")
@dataclass(slots=True, eq=False)
class NamedType(Node):
    """A reference to a definition by name, possibly qualified (``pkg.Type``)."""

    name: str
    span: Span
    annotations: Sequence[Annotation] = ()
    #: The definition this resolves to, or None (unknown or external).
    target: Definition | None = None
    #: For a type from an external package: the package name.
    external: str | None = None

    kind: ClassVar[Literal["named"]] = "named"

    @property
    def local_name(self) -> str:
        """The name without its package or include prefix."""
        return self.name.rpartition(".")[2]

    @property
    def qualifier(self) -> str:
        """The package or include prefix, or ''."""
        return self.name.rpartition(".")[0]


ArrayKind = Literal["fixed", "bounded", "unbounded"]


@spanned("span")
@dataclass(slots=True, eq=False)
class ArrayType(Node):
    """A sequence: ``T[]``, ``T[N]`` (fixed), ``T[<=N]`` (bounded) or Thrift ``list<T>``."""

    element: TypeRef
    span: Span
    array: ArrayKind = "unbounded"
    size: int | None = None
    spelled_list: bool = False
    annotations: Sequence[Annotation] = ()

    kind: ClassVar[Literal["array"]] = "array"


@spanned("span")
@dataclass(slots=True, eq=False)
class SetType(Node):
    """Thrift ``set<T>``."""

    element: TypeRef
    span: Span
    annotations: Sequence[Annotation] = ()

    kind: ClassVar[Literal["set"]] = "set"


@spanned("span")
@dataclass(slots=True, eq=False)
class MapType(Node):
    """Thrift ``map<K, V>``."""

    key: TypeRef
    element: TypeRef
    span: Span
    annotations: Sequence[Annotation] = ()

    kind: ClassVar[Literal["map"]] = "map"


TypeRef = Union[BaseType, NamedType, ArrayType, SetType, MapType]


# ---------------------------------------------------------------------------
# Values and annotations

ValueKind = Literal["int", "double", "string", "name", "list", "map"]


@spanned("span")
@dataclass(slots=True, eq=False)
class Value(Node):
    """A constant value as written: int, double, string, name, list or map.

    ``value`` holds an int, a float, the decoded str, the name, a list of
    Values, or a list of (key, value) pairs of Values. ``text`` is the
    original spelling (numbers keep their form, e.g. ``0x10`` or ``1.50``).
    """

    kind: ValueKind
    value: Any
    span: Span
    text: str = ""


@spanned("span")
@dataclass(slots=True, eq=False)
class Annotation(Node):
    """A Thrift annotation ``key = value`` (value None for a bare flag)."""

    key: str
    value: Value | None
    span: Span

    @property
    def text(self) -> str:
        """The value as a string ('' for a bare flag)."""
        if self.value is None:
            return ""
        v = self.value.value
        return v if isinstance(v, str) else self.value.text


def annotation(annotations: Sequence[Annotation], key: str) -> Annotation | None:
    """The last annotation with ``key``, if any."""
    for a in reversed(annotations):
        if a.key == key:
            return a
    return None


# ---------------------------------------------------------------------------
# Members

Requiredness = Literal["required", "optional"]


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Field(Node):
    """A field of a struct-like body, a section, a function's argument list or throws."""

    name: str
    type: TypeRef
    span: Span
    name_span: Span
    id: int | None = None
    id_span: Span | None = None
    requiredness: Requiredness | None = None
    default: Value | None = None
    annotations: Sequence[Annotation] = ()
    doc: str | None = None
    reference: bool = False

    @property
    def unit(self) -> str | None:
        """The ``unit`` annotation."""
        a = annotation(self.annotations, "unit")
        return a.text if a else None

    @property
    def range(self) -> tuple[float | None, float | None] | None:
        """(min, max) from ``range = "lo..hi"`` or ``min``/``max`` annotations."""
        lo = hi = None
        a = annotation(self.annotations, "range")
        if a is not None:
            low, sep, high = a.text.partition("..")
            if not sep:
                return None
            try:
                lo = float(low) if low.strip() else None
                hi = float(high) if high.strip() else None
            except ValueError:
                return None
        for key in ("min", "max"):
            b = annotation(self.annotations, key)
            if b is not None:
                try:
                    number = float(b.text)
                except ValueError:
                    return None
                if key == "min":
                    lo = number
                else:
                    hi = number
        if lo is None and hi is None or not all(math.isfinite(b) for b in (lo, hi) if b is not None):
            return None  # a NaN or infinite bound is refused (validate says why): no target expresses it
        return lo, hi


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Const(Node):
    """A constant, at top level or inside a body (ROS 2 message constants)."""

    name: str
    type: TypeRef
    value: Value
    span: Span
    name_span: Span
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["const"]] = "const"


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Section(Node):
    """A part of a service or action: request/response, goal/result/feedback."""

    name: str
    span: Span
    name_span: Span
    fields: list[Field] = field(default_factory=list)
    consts: list[Const] = field(default_factory=list)
    #: True when read from a flat body rather than written as a section.
    implicit: bool = False
    doc: str | None = None


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Function(Node):
    """A Thrift service function: one request/response pair."""

    name: str
    returns: TypeRef | None
    span: Span
    name_span: Span
    params: list[Field] = field(default_factory=list)
    throws: list[Field] = field(default_factory=list)
    oneway: bool = False
    annotations: Sequence[Annotation] = ()
    doc: str | None = None


# ---------------------------------------------------------------------------
# Definitions

StructKind = Literal["struct", "union", "exception", "message", "configuration", "state"]
BodyForm = Literal["explicit", "flat", "functions", "empty"]


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Struct(Node):
    """struct, union, exception (Thrift); message, configuration, state (iface)."""

    kind: StructKind
    name: str
    span: Span
    name_span: Span
    fields: list[Field] = field(default_factory=list)
    consts: list[Const] = field(default_factory=list)
    annotations: Sequence[Annotation] = ()
    doc: str | None = None


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Service(Node):
    """A service: Thrift functions, or one request/response pair (flat or explicit)."""

    name: str
    span: Span
    name_span: Span
    form: BodyForm = "empty"
    extends: NamedType | None = None
    functions: list[Function] = field(default_factory=list)
    request: Section | None = None
    response: Section | None = None
    #: Sections as written (explicit form), including unknown ones.
    sections: list[Section] = field(default_factory=list)
    #: Fields as written in a flat body.
    flat_fields: list[Field] = field(default_factory=list)
    consts: list[Const] = field(default_factory=list)
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["service"]] = "service"

    @property
    def is_diagnostics(self) -> bool:
        """True for the Δ service: named ``diagnostics`` or annotated ``(diagnostics)``."""
        return self.name == "diagnostics" or annotation(self.annotations, "diagnostics") is not None or (
            (a := annotation(self.annotations, "role")) is not None and a.text == "diagnostics")


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Action(Node):
    """An action: goal, result and feedback."""

    name: str
    span: Span
    name_span: Span
    form: BodyForm = "empty"
    goal: Section | None = None
    result: Section | None = None
    feedback: Section | None = None
    sections: list[Section] = field(default_factory=list)
    flat_fields: list[Field] = field(default_factory=list)
    consts: list[Const] = field(default_factory=list)
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["action"]] = "action"


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class EnumValue(Node):
    """One enumerator; ``value`` is explicit or counted on from the previous one."""

    name: str
    value: int
    span: Span
    name_span: Span
    explicit: bool = False
    annotations: Sequence[Annotation] = ()
    doc: str | None = None


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Enum(Node):
    """A Thrift enum."""

    name: str
    span: Span
    name_span: Span
    values: list[EnumValue] = field(default_factory=list)
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["enum"]] = "enum"
    #: (number of values, first value by name, the numbers): built when first asked, again if values change
    _index: tuple[int, dict[str, EnumValue], frozenset[int]] | None = field(default=None, repr=False,
                                                                            metadata={"derived": True})

    def _indexed(self) -> tuple[int, dict[str, EnumValue], frozenset[int]]:
        if self._index is None or self._index[0] != len(self.values):
            by_name: dict[str, EnumValue] = {}
            for v in self.values:
                by_name.setdefault(v.name, v)
            self._index = (len(self.values), by_name, frozenset(v.value for v in self.values))
        return self._index

    def named(self, name: str) -> EnumValue | None:
        """The (first) value called ``name``, found in constant time."""
        return self._indexed()[1].get(name)

    def has_number(self, number: int) -> bool:
        """True when a value of the enum is ``number``."""
        return number in self._indexed()[2]


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Senum(Node):
    """A Thrift senum (deprecated string enum)."""

    name: str
    span: Span
    name_span: Span
    values: list[Value] = field(default_factory=list)
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["senum"]] = "senum"


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class Typedef(Node):
    """``typedef T Name``."""

    name: str
    type: TypeRef
    span: Span
    name_span: Span
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    kind: ClassVar[Literal["typedef"]] = "typedef"
    #: What the typedef finally stands for, through other typedefs; set by resolution on every compile
    #: (``semantics.resolve.settle_typedefs``), so a chain is followed once per compile, not once per use.
    final: TypeRef | None = field(default=None, repr=False, metadata={"derived": True})


Definition = Union[Struct, Service, Action, Enum, Senum, Typedef, Const]


# ---------------------------------------------------------------------------
# Headers and wiring


@spanned("span", "path_span")
@dataclass(slots=True, eq=False)
class Include(Node):
    """``include "file"``; ``resolved`` is the absolute path once found."""

    path: str
    span: Span
    path_span: Span
    cpp: bool = False
    resolved: str | None = None


@spanned("span")
@dataclass(slots=True, eq=False)
class Namespace(Node):
    """``namespace scope name`` (scope ``ros2``, ``px4``, ``cpp``, ``*`` …)."""

    scope: str
    name: str
    span: Span
    annotations: Sequence[Annotation] = ()


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class ComponentDecl(Node):
    """``component name version "x.y"``."""

    name: str
    span: Span
    name_span: Span
    version: str | None = None
    annotations: Sequence[Annotation] = ()
    doc: str | None = None


@spanned("span")
@dataclass(slots=True, eq=False)
class External(Node):
    """``external pkg`` or ``external pkg.Type``: types that live outside iface."""

    name: str
    span: Span


@spanned("span", "name_span")
@dataclass(slots=True, eq=False)
class SystemDecl(Node):
    """``system name version "x.y"``: the file describes a system of component instances."""

    name: str
    span: Span
    name_span: Span
    version: str | None = None
    annotations: Sequence[Annotation] = ()
    doc: str | None = None


@spanned("span", "name_span", "component_span")
@dataclass(slots=True, eq=False)
class Instance(Node):
    """``instance name : component (annotations)``: one running component of a system."""

    name: str
    component: str
    span: Span
    name_span: Span
    component_span: Span
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    def value(self, key: str) -> str | None:
        """The text of the annotation ``key`` (the last one), or None when it is not given."""
        a = annotation(self.annotations, key)
        return a.text if a is not None else None

    @property
    def node(self) -> str:
        """The ROS 2 node name: the ``node`` annotation, else the instance name."""
        return self.value("node") or self.name

    @property
    def after(self) -> list[Annotation]:
        """The ``after`` annotations: the instances this one starts after."""
        return [a for a in self.annotations if a.key == "after"]


Direction = Literal["publishes", "subscribes", "provides", "calls"]


@spanned("span", "topic_span")
@dataclass(slots=True, eq=False)
class Wiring(Node):
    """A direction statement: ``publishes T on "/topic"`` and the like."""

    direction: Direction
    type: NamedType
    topic: str
    span: Span
    topic_span: Span
    annotations: Sequence[Annotation] = ()
    doc: str | None = None

    @property
    def qos(self) -> dict[str, str]:
        """QoS settings from ``qos.*`` annotations."""
        return {a.key[4:]: a.text for a in self.annotations if a.key.startswith("qos.")}


Item = Union[Definition, Include, Namespace, ComponentDecl, External, Wiring, SystemDecl, Instance]


# ---------------------------------------------------------------------------
# The seven sets


@dataclass(slots=True, eq=False)
class Endpoint:
    """An element of M, N, S or A: a definition bound to a topic or name with a role."""

    role: Direction
    name: str
    definition: Definition | None
    wiring: Wiring | None = None

    @property
    def span(self) -> Span:
        """Where the element is stated."""
        if self.wiring is not None:
            return self.wiring.span
        assert self.definition is not None
        return self.definition.span


@dataclass(eq=False)
class Interface:
    """One compiled file: its items in order and the seven sets derived from them."""

    source: Source
    name: str
    version: str | None = None
    items: list[Item] = field(default_factory=list)
    includes: list[Include] = field(default_factory=list)
    namespaces: list[Namespace] = field(default_factory=list)
    externals: list[External] = field(default_factory=list)
    wirings: list[Wiring] = field(default_factory=list)
    definitions: list[Definition] = field(default_factory=list)
    component: ComponentDecl | None = None
    #: Every component declaration, the first one being ``component`` (a second one is an error).
    component_decls: list[ComponentDecl] = field(default_factory=list)
    #: The system declaration of a system file (the first one; a second one is an error), else None.
    system: SystemDecl | None = None
    #: Every system declaration, the first one being ``system``.
    system_decls: list[SystemDecl] = field(default_factory=list)
    #: The component instances of a system file, in declaration order.
    instances: list[Instance] = field(default_factory=list)
    #: Definitions of this file by name (first one wins on duplicates).
    symbols: dict[str, Definition] = field(default_factory=dict)
    #: Interfaces of included files, by the prefix used to refer to them.
    included: dict[str, Interface] = field(default_factory=dict)
    #: When this version's lists were made from the last version's: (id of the last version's Interface,
    #: {list name: (index, items there before, items there now)} for the lists the edit changed).
    spliced: tuple[int, dict[str, tuple[int, int, int]]] | None = None

    # the seven sets, filled by ``sets.derive``
    subscribed: list[Endpoint] = field(default_factory=list)       # M
    published: list[Endpoint] = field(default_factory=list)        # N
    services: list[Endpoint] = field(default_factory=list)         # S (provides and calls), never Δ
    actions: list[Endpoint] = field(default_factory=list)          # A (provides and calls)
    parameters: list[Field] = field(default_factory=list)          # P
    state: list[Field] = field(default_factory=list)               # Σ
    diagnostics: list[Service] = field(default_factory=list)       # Δ
    #: Δ with the name each service is served under (its `provides` wiring, else its own name).
    diagnostics_endpoints: list[Endpoint] = field(default_factory=list)

    def __getattr__(self, name: str) -> Any:
        # the seven sets of a compile that left them to be made when first read (see ``defer_sets``)
        fill = self.__dict__.get("_fill_sets")
        if fill is not None and name in SET_FIELDS:
            del self.__dict__["_fill_sets"]
            fill(self)
            return self.__dict__[name]
        raise AttributeError(name)

    def defer_sets(self, fill: Any) -> None:
        """Make the seven sets when one is first read, by ``fill(self)`` (which sets every one of them)."""
        for name in SET_FIELDS:
            self.__dict__.pop(name, None)
        self.__dict__["_fill_sets"] = fill

    @property
    def path(self) -> str:
        """Path of the file."""
        return self.source.path

    def namespace(self, scope: str) -> str | None:
        """The namespace for ``scope`` (``ros2``, ``px4``, …), falling back to ``*``."""
        found = None
        for ns in self.namespaces:
            if ns.scope == scope:
                return ns.name
            if ns.scope == "*":
                found = ns.name
        return found

    @property
    def assumptions(self) -> list[Endpoint | Field]:
        """What the component assumes of its environment: M, called S and A, P."""
        called = [e for e in self.services + self.actions if e.role == "calls"]
        return [*self.subscribed, *called, *self.parameters]

    @property
    def guarantees(self) -> list[Endpoint | Field | Service]:
        """What it guarantees: N, provided S and A, Δ (Σ is both, see ``state``)."""
        provided = [e for e in self.services + self.actions if e.role == "provides"]
        return [*self.published, *provided, *self.diagnostics]

    def lookup(self, name: str) -> Definition | None:
        """A definition of this file or of an included one (``prefix.Name``)."""
        found = self.symbols.get(name)
        if found is not None:
            return found
        prefix, _, local = name.rpartition(".")
        if prefix and prefix in self.included:
            return self.included[prefix].symbols.get(local)
        return None


#: The fields of ``Interface`` that hold the seven sets (``sets.derive`` fills them).
SET_FIELDS = frozenset({"subscribed", "published", "services", "actions", "parameters", "state", "diagnostics",
                        "diagnostics_endpoints"})
