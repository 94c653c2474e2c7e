"""A compiled interface seen as a node: members, handler names, parameters with their checks, the state schema.

Every node generator (rclpy now, rclcpp next) and the editor's hover read this one description,
so the name of a handler is decided once. What becomes what (docs/runtime.md):

- ``subscribes T on "/t"`` → a subscription calling the user's ``on_<t>(msg)`` while active;
- ``publishes T on "/t"`` → a lifecycle publisher and ``publish_<t>(msg)``;
- ``provides S on "/s"`` → a service calling ``handle_<s>(request, response)``; a Thrift-style
  service becomes one ROS service per function, ``/s/<function>``, handled by ``handle_<s>_<function>``;
- ``calls S on "/s"`` → a client with ``call_<s>(request)`` and ``call_<s>_async(request)``;
- ``provides A on "/a"`` → an action server calling ``execute_<a>(goal_handle)`` (and, if the
  user defines them, ``accept_<a>_goal(goal)`` and ``cancel_<a>_goal(goal_handle)``);
- ``calls A on "/a"`` → an action client with ``send_<a>_goal(goal)``;
- Δ: each diagnostics service, served under its wired name (else ``~/<name>``) by
  ``handle_<s>(request, response)`` from the diagnostics thread.

``<t>`` is the last segment of the name in snake_case; when two members of one kind would get
the same handler, both use their whole name (``/arm/cmd`` → ``arm_cmd``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Literal

from ..compat.canon import interface_hash
from ..emit.ros2.definitions import DefinitionLowering
from ..emit.ros2.package import PyValue, RosPackage, RosType
from ..emit.text import doc_lines
from ..model import nodes as m
from ..model import qos as qos_rules
from ..model.diagnostics import Diagnostic
from ..model.naming import ros_field_name, ros_type_name, words
from ..model.source import Source, Span
from ..model.walk import resolve_typedefs
from ..semantics.compile import Compilation
from ..semantics.sets import wiring_target
from . import protocol
from .codes import diag

MemberKind = Literal["publisher", "subscription", "server", "client", "action_server", "action_client",
                     "diagnostics"]

#: Methods of the node base classes a generated name must not take.
RESERVED = frozenset({
    "on_configure", "on_activate", "on_deactivate", "on_cleanup", "on_shutdown", "on_error",
    "on_active", "on_inactive", "setup", "teardown",
})
#: The prefixes of user handlers: a user method named so that handles no member is reported.
HANDLER_PREFIXES = ("on_", "handle_", "execute_", "accept_", "cancel_")

_FLOAT32_MAX = 3.4028234663852886e38
_INT64 = m.INT_RANGES["i64"]


@dataclass(frozen=True, slots=True)
class RosRef:
    """A ROS interface type: ``package/kind/Name``."""

    package: str
    kind: str
    name: str

    @property
    def module(self) -> str:
        """The Python module that holds it (``robot_arm_msgs.msg``)."""
        return f"{self.package}.{self.kind}"

    @property
    def text(self) -> str:
        """``robot_arm_msgs/msg/JointState``."""
        return f"{self.package}/{self.kind}/{self.name}"


@dataclass(frozen=True, slots=True)
class Handler:
    """A method the user writes: its name, the arguments it is called with, whether it must exist."""

    name: str
    args: tuple[str, ...]
    required: bool = True


@dataclass(slots=True)
class Member:
    """One element of M, N, S, A or Δ as a node entity."""

    kind: MemberKind
    name: str
    type: RosRef
    qos: dict[str, str]
    what: str
    doc: list[str]
    source: Source
    span: Span
    wiring: m.Wiring | None = None
    slug: str = ""
    full_slug: str = ""

    @property
    def handlers(self) -> list[Handler]:
        """The user's methods for this member."""
        s = self.slug
        if self.kind == "subscription":
            return [Handler(f"on_{s}", ("msg",))]
        if self.kind in ("server", "diagnostics"):
            return [Handler(f"handle_{s}", ("request", "response"))]
        if self.kind == "action_server":
            return [Handler(f"execute_{s}", ("goal_handle",)),
                    Handler(f"accept_{s}_goal", ("goal",), required=False),
                    Handler(f"cancel_{s}_goal", ("goal_handle",), required=False)]
        return []

    @property
    def helpers(self) -> list[str]:
        """Methods and attributes the generated base class gives the user for this member."""
        s = self.slug
        if self.kind == "publisher":
            return [f"publish_{s}"]
        if self.kind == "client":
            return [f"call_{s}", f"call_{s}_async", f"{s}_client"]
        if self.kind == "action_client":
            return [f"send_{s}_goal", f"send_{s}_goal_async", f"{s}_action_client"]
        return []

    @property
    def names(self) -> list[str]:
        """Every identifier the member takes in the node class."""
        return [h.name for h in self.handlers] + self.helpers

    @property
    def main_handler(self) -> str | None:
        """The handler hover shows (None for publishers and clients, which the user calls)."""
        hs = self.handlers
        return hs[0].name if hs else None


@dataclass(slots=True)
class ParamSpec:
    """A configuration parameter with everything its declaration and checks need."""

    name: str
    accessor: str
    kind: str
    python_type: str
    default: PyValue | None
    note: str
    description: str
    unit: str | None
    low: float | int | None
    high: float | int | None
    read_only: bool
    choices: list[tuple[str, int]]
    max_length: int | None
    size: int | None
    size_kind: str | None
    integer: bool
    floating: bool
    constraints: str


@dataclass(slots=True)
class StateVar:
    """A state variable: its ROS field name and schema type (``float32[6]``, ``robot_arm_msgs/Pose``)."""

    name: str
    type: str


@dataclass(slots=True)
class ComponentSpec:
    """Everything a node generator needs about one component."""

    component: str
    version: str
    interface_hash: str
    source_name: str
    doc: list[str]
    ros: RosPackage
    package: str
    node: str
    class_name: str
    members: list[Member] = field(default_factory=list)
    diagnostics: list[Member] = field(default_factory=list)
    params: list[ParamSpec] = field(default_factory=list)
    state: list[StateVar] = field(default_factory=list)
    state_type: RosRef | None = None
    diagnostics_rate: float = protocol.DEFAULT_DIAGNOSTICS_RATE
    depends: list[str] = field(default_factory=list)

    @property
    def interface_package(self) -> str:
        """The ROS interface package (``robot_arm_msgs``)."""
        return self.ros.name

    def all_members(self) -> list[Member]:
        """Members then Δ services."""
        return [*self.members, *self.diagnostics]

    def of_kind(self, kind: MemberKind) -> list[Member]:
        """The members of one kind, in the order written."""
        return [x for x in self.all_members() if x.kind == kind]

    def handlers(self) -> list[tuple[Handler, Member]]:
        """Every user handler with its member."""
        return [(h, x) for x in self.all_members() for h in x.handlers]

    def types(self, with_protocol: bool = True) -> list[RosRef]:
        """Every interface type the node uses, once, sorted (``with_protocol``: the protocol services' too)."""
        refs = {x.type for x in self.all_members()}
        if with_protocol:
            refs.update(RosRef(protocol.PACKAGE, "srv", s.type_name) for s in protocol.COMPONENT_SERVICES)
        if self.state_type is not None:
            refs.add(self.state_type)
        return sorted(refs, key=lambda r: (r.package, r.kind, r.name))


# ---- building the description ---------------------------------------------------------------------


def slug_of(name: str) -> tuple[str, str]:
    """(last segment, whole name) of a ROS name in snake_case: ``/arm/joint_state`` → (joint_state, arm_joint_state)."""
    parts = [p for p in re.split(r"[/~{}]+", name) if p]

    def snake(text: str) -> str:
        return "_".join(w.lower() for w in words(text)) or "root"

    last = snake(parts[-1]) if parts else "root"
    whole = "_".join(snake(p) for p in parts) if parts else "root"
    return last, whole


def _qos(w: m.Wiring | None) -> dict[str, str]:
    """The wiring's QoS, policies under their full names, values in lower case."""
    if w is None:
        return {}
    out = {}
    for key, value in w.qos.items():
        key = qos_rules.ALIASES.get(key, key)
        if key in qos_rules.KEYS:
            out[key] = value.strip().lower()
    return dict(sorted(out.items()))


def _what(direction: str, d: m.Definition, name: str) -> str:
    return f"{direction} {d.name} on {name}"


class _Builder:
    def __init__(self, comp: Compilation, pkg: RosPackage, run: DefinitionLowering) -> None:
        self.comp = comp
        self.iface = comp.interface
        self.pkg = pkg
        self.run = run
        self.diags: list[Diagnostic] = []

    def ref(self, d: m.Definition, kind: str, suffix: str = "") -> RosRef | None:
        owner = self.run.owners.of(d)
        package = self.run.package_of(owner)
        name = self.run.type_name(d, suffix=suffix)
        if package is None or name is None:
            return None
        return RosRef(package, kind, name)

    def endpoint(self, ep: m.Endpoint, topic_kind: MemberKind | None) -> list[Member]:
        d = ep.definition
        if d is None:
            return []
        w = ep.wiring
        src = self.iface.source
        span = w.span if w is not None else d.name_span
        doc = doc_lines(w.doc if w is not None and w.doc else getattr(d, "doc", None))
        direction = ep.role
        if topic_kind is not None:
            ref = self.ref(d, "msg")
            return [] if ref is None else [Member(topic_kind, ep.name, ref, _qos(w), _what(direction, d, ep.name),
                                                  doc, src, span, w)]
        if isinstance(d, m.Action):
            ref = self.ref(d, "action")
            kind: MemberKind = "action_server" if direction == "provides" else "action_client"
            return [] if ref is None else [Member(kind, ep.name, ref, _qos(w), _what(direction, d, ep.name),
                                                  doc, src, span, w)]
        if not isinstance(d, m.Service):
            return []
        kind = "server" if direction == "provides" else "client"
        if d.form != "functions":
            ref = self.ref(d, "srv")
            return [] if ref is None else [Member(kind, ep.name, ref, _qos(w), _what(direction, d, ep.name),
                                                  doc, src, span, w)]
        out = []
        for fn in d.functions:
            fname = ros_type_name(fn.name)
            sub = ros_field_name(fn.name)
            ref = self.ref(d, "srv", fname or "")
            if ref is None or fname is None or sub is None:
                continue
            name = ep.name.rstrip("/") + "/" + sub
            out.append(Member(kind, name, ref, _qos(w), f"{direction} {d.name}.{fn.name} on {name}",
                              doc_lines(fn.doc) or doc, src, span, w))
        return out

    def members(self) -> list[Member]:
        iface = self.iface
        out: list[Member] = []
        for ep in iface.subscribed:
            out += self.endpoint(ep, "subscription")
        for ep in iface.published:
            out += self.endpoint(ep, "publisher")
        for ep in iface.services:
            d = ep.definition
            if isinstance(d, m.Service) and d.is_diagnostics and ep.role == "provides":
                continue  # Δ, not S (read from iface.diagnostics)
            out += self.endpoint(ep, None)
        for ep in iface.actions:
            out += self.endpoint(ep, None)
        return out

    def diagnostics(self) -> list[Member]:
        iface = self.iface
        out = []
        for d in iface.diagnostics:
            ref = self.ref(d, "srv")
            if ref is None:
                continue
            w = next((w for w in iface.wirings if w.direction == "provides" and wiring_target(w) is d), None)
            name = w.topic if w is not None else "~/" + slug_of(d.name)[0]
            span = w.span if w is not None else d.name_span
            out.append(Member("diagnostics", name, ref, _qos(w), f"diagnostics {d.name} on {name}",
                              doc_lines(d.doc), iface.source, span, w))
        return out

    def name_members(self, members: list[Member]) -> None:
        """Handler names: the last segment, the whole name where that is ambiguous."""
        for x in members:
            x.slug, x.full_slug = slug_of(x.name)
        for _ in range(2):
            owners: dict[str, list[Member]] = {}
            for x in members:
                for n in x.names:
                    owners.setdefault(n, []).append(x)
            clash = {id(x) for xs in owners.values() if len({id(y) for y in xs}) > 1 for x in xs}
            clash |= {id(x) for x in members if RESERVED & set(x.names)}
            if not clash:
                return
            for x in members:
                if id(x) in clash:
                    x.slug = x.full_slug if x.slug != x.full_slug else x.full_slug + "_" + x.kind
        seen: dict[str, Member] = {}
        for x in members:
            for n in x.names:
                if n in seen and seen[n] is not x:
                    self.diags.append(diag("runtime-name-clash", f"'{x.what}' and '{seen[n].what}' would both "
                                           f"get the method {n}: rename one of them", x.source, x.span))
                seen.setdefault(n, x)

    def rate(self) -> float:
        for d in self.iface.diagnostics:
            a = m.annotation(d.annotations, "rate")
            if a is None:
                continue
            hz = _rate_hz(a)
            if hz is None:
                self.diags.append(diag("runtime-annotation", f"rate = {a.text or '?'}: a diagnostics rate is a "
                                       "number of Hz (rate = 2) or a text like \"2 Hz\" or \"500ms\" (a period)",
                                       self.iface.source, a.span))
                continue
            return hz
        return protocol.DEFAULT_DIAGNOSTICS_RATE

    def params(self) -> list[ParamSpec]:
        fields = {f.name: f for f in self.iface.parameters}
        out = []
        for p in self.pkg.params:
            f = fields.get(p.name)
            if f is None:
                continue
            out.append(self.param(p.name, p.type, p.value, p.note, f))
        return out

    def param(self, name: str, rt: RosType, value: PyValue | None, note: str, f: m.Field) -> ParamSpec:
        element = rt.element
        prim = element.primitive or "int32"
        enum = _enum(f.type)
        integer = prim in _INT_TYPES or enum is not None
        floating = prim in ("float32", "float64")
        base = "bool" if prim == "bool" else "integer" if integer else "double" if floating else "string"
        kind = base + ("_array" if rt.array is not None else "")
        py = {"bool": "bool", "integer": "int", "double": "float", "string": "str"}[base]
        python_type = f"list[{py}]" if rt.array is not None else py
        lo, hi = f.range or (None, None)
        low: float | int | None = lo
        high: float | int | None = hi
        if integer and enum is None:
            tlo, thi = _int_range(prim)
            low = tlo if lo is None else max(tlo, math.ceil(lo))
            high = thi if hi is None else min(thi, math.floor(hi))
            if (low, high) == _INT64:
                low = high = None
        elif prim == "float32":
            low = -_FLOAT32_MAX if lo is None else lo
            high = _FLOAT32_MAX if hi is None else hi
        read_only = self.read_only(f)
        choices = [(ev.name, ev.value) for ev in enum.values] if enum is not None else []
        size = rt.size if rt.array in ("fixed", "bounded") else None
        unit = f.unit
        constraints = []
        if unit:
            constraints.append(f"unit: {unit}")
        if f.range is not None:
            constraints.append("range: " + "..".join("" if x is None else format(x, "g") for x in f.range))
        if choices:
            constraints.append("one of: " + ", ".join(f"{n} ({v})" for n, v in choices))
        if element.string_bound is not None:
            constraints.append(f"at most {element.string_bound} characters")
        if rt.array == "fixed":
            constraints.append(f"exactly {size} elements")
        elif rt.array == "bounded":
            constraints.append(f"at most {size} elements")
        description = " ".join(doc_lines(f.doc)) or name
        accessor = name if name.isidentifier() and not _is_keyword(name) else (ros_field_name(name) or "p") + "_"
        return ParamSpec(name, accessor, kind, python_type, value, note, description, unit, low, high, read_only,
                         choices, element.string_bound, size, rt.array if size is not None else None, integer,
                         floating, "; ".join(constraints))

    def read_only(self, f: m.Field) -> bool:
        a = m.annotation(f.annotations, "read_only")
        if a is None:
            return False
        if a.value is None or a.text.lower() in ("true", "1"):
            return True
        if a.text.lower() in ("false", "0"):
            return False
        self.diags.append(diag("runtime-annotation", f"read_only = {a.text}: write read_only (or read_only = true "
                               "/ false)", self.iface.source, a.span))
        return False

    def state(self) -> tuple[list[StateVar], RosRef | None]:
        comp_type = ros_type_name(self.iface.name)
        if not self.iface.state or comp_type is None:
            return [], None
        name = comp_type + "State"
        ri = next((i for i in self.pkg.interfaces if i.kind == "msg" and i.name == name), None)
        if ri is None:
            return [], None
        out = [StateVar(f.name, schema_type(f.type, self.pkg.name)) for f in ri.sections[0].fields]
        return out, RosRef(self.pkg.name, "msg", name)


_INT_TYPES = frozenset({"byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"})
_ROS_INT_RANGES = {"byte": (0, 255), "char": (0, 255), "int8": m.INT_RANGES["i8"], "uint8": m.INT_RANGES["u8"],
                   "int16": m.INT_RANGES["i16"], "uint16": m.INT_RANGES["u16"], "int32": m.INT_RANGES["i32"],
                   "uint32": m.INT_RANGES["u32"], "int64": _INT64, "uint64": (0, _INT64[1])}


def _int_range(prim: str) -> tuple[int, int]:
    return _ROS_INT_RANGES.get(prim, _INT64)


def _is_keyword(name: str) -> bool:
    import keyword

    return keyword.iskeyword(name) or keyword.issoftkeyword(name)


def _enum(t: m.TypeRef) -> m.Enum | None:
    r = resolve_typedefs(t)
    if isinstance(r, m.ArrayType):
        r = resolve_typedefs(r.element)
    return r.target if isinstance(r, m.NamedType) and isinstance(r.target, m.Enum) else None


_HZ = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*hz\s*$", re.IGNORECASE)


def _rate_hz(a: m.Annotation) -> float | None:
    """Hz from ``rate = 2``, ``rate = "2 Hz"`` or ``rate = "500ms"`` (a period); None when unreadable."""
    if a.value is not None and a.value.kind in ("int", "double"):
        hz = float(a.value.value)
    else:
        text = a.text
        found = _HZ.match(text)
        if found:
            hz = float(found.group(1))
        else:
            period = qos_rules.duration(text) if text.strip() else None
            if period is None or period in (0.0, math.inf):
                return None
            hz = 1.0 / period
    return hz if 0.0 < hz <= 1000.0 and math.isfinite(hz) else None


def schema_type(rt: RosType, package: str) -> str:
    """The state-document spelling of a ROS type: ``.msg`` syntax, messages qualified, ``char`` as rosidl's ``uint8``."""
    if rt.primitive is not None:
        prim = "uint8" if rt.primitive == "char" else rt.primitive
        core = prim + (f"<={rt.string_bound}" if rt.string_bound is not None else "")
    else:
        core = f"{rt.package or package}/{rt.name}"
    if rt.array == "fixed":
        return f"{core}[{rt.size}]"
    if rt.array == "bounded":
        return f"{core}[<={rt.size}]"
    if rt.array == "unbounded":
        return f"{core}[]"
    return core


def component_package_name(node: str, interface_package: str) -> str:
    """The component package: named after the component, ``<name>_node`` when the interface package has that name."""
    return node if node != interface_package else f"{node}_node"


def describe(comp: Compilation, pkg: RosPackage, run: DefinitionLowering) -> tuple[ComponentSpec, list[Diagnostic]]:
    """The node description of a compilation whose ROS 2 package lowered without errors."""
    b = _Builder(comp, pkg, run)
    iface = comp.interface
    members = b.members()
    deltas = b.diagnostics()
    b.name_members(members + deltas)
    state, state_type = b.state()
    comp_decl = iface.component
    spec = ComponentSpec(
        component=iface.name, version=pkg.version, interface_hash=interface_hash(comp),
        source_name=pkg.source_name,
        doc=doc_lines(comp_decl.doc) if comp_decl is not None else [],
        ros=pkg, package=component_package_name(pkg.node, pkg.name), node=pkg.node,
        class_name=ros_type_name(iface.name) or "Component",
        members=members, diagnostics=deltas, params=b.params(), state=state, state_type=state_type,
        diagnostics_rate=b.rate())
    deps = {r.package for r in spec.types()}
    if spec.of_kind("action_server") or spec.of_kind("action_client"):
        deps.add("action_msgs")
    spec.depends = sorted(deps)
    return spec, b.diags


def node_spec(comp: Compilation) -> ComponentSpec | None:
    """The node description of ``comp`` as the node generators see it; None when it cannot be lowered."""
    from ..emit.ros2.lower import lower_run

    pkg, found, run = lower_run(comp)
    if pkg is None or any(int(d.severity) == 1 for d in found):
        return None
    return describe(comp, pkg, run)[0]


def handler_lines(spec: ComponentSpec, wiring: m.Wiring) -> list[str]:
    """What the generated node makes of one wiring: ``handler(args)`` the user writes or helpers the user calls."""
    out: list[str] = []
    for member in spec.all_members():
        if member.wiring is not wiring:
            continue
        for h in member.handlers:
            optional = "" if h.required else " (optional)"
            out.append(f"`{h.name}({', '.join(h.args)})`{optional} handles {member.what}")
        calls = [x for x in member.helpers if not x.endswith("_client")]
        if calls:
            out.append(", ".join(f"`{x}`" for x in calls) + f" for {member.what}")
    return out
