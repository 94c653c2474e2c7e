"""What the platforms' own parsers read from an interface file: the judge of a round trip.

- ROS 2 ``.idl``: rosbags' IDL parser (``rosbags.typesys.get_types_from_idl``, through
  ``importers.idl.read_idl``) gives fields and constants of every struct, ``importers.idl.defaults``
  their ``@default`` values (which rosbags does not read); compared like .msg, with the same RIHS01 hash.
- ROS 2: the rosidl parser vendored in ``mcap-ros2-support``
  (``mcap_ros2._vendor.rosidl_adapter.parser``) gives fields (name, type with
  bounds, default) and constants of every part; the RIHS01 type hash of each
  part is computed over those fields as ``rosbags.typesys.Typestore.hash_rihs01``
  does (its algorithm, with the wstring type ids that rosbags leaves out), and
  types from packages that were not given are taken from rosbags' ROS 2 store.
- PX4: ``genmsg`` (``pyros-genmsg``) gives fields and constants; topics are read
  from ``# TOPICS`` lines as PX4's generator reads them.

These packages are test dependencies (``pip install -e .[test]``); a missing
one is an ``OracleMissing`` error that names it.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from hashlib import sha256
from typing import Any

from .px4 import topics_of

#: type_description_interfaces/FieldType ids (REP-2011), as rosbags uses them, plus wstring.
TYPE_IDS = {"nested": 1, "int8": 2, "uint8": 3, "int16": 4, "uint16": 5, "int32": 6, "uint32": 7, "int64": 8,
            "uint64": 9, "float32": 10, "float64": 11, "char": 13, "wchar": 14, "bool": 15, "byte": 16,
            "string": 17, "wstring": 18, "bounded_string": 21, "bounded_wstring": 22}
FIXED, BOUNDED, UNBOUNDED = 48, 96, 144
PART_SUFFIXES = {"msg": ("",), "srv": ("_Request", "_Response"), "action": ("_Goal", "_Result", "_Feedback")}


class OracleMissing(RuntimeError):
    """A parser the round trip needs is not installed."""


class OracleRefused(ValueError):
    """The platform's parser refuses the file."""


@dataclass(slots=True)
class PartView:
    """One part as the platform reads it."""

    name: str
    fields: list[tuple[str, str, Any]] = field(default_factory=list)
    constants: list[tuple[str, str, Any]] = field(default_factory=list)
    #: the part's fields in rosbags' desc form, for the hash
    descs: list[tuple[str, Any]] = field(default_factory=list)


@dataclass(slots=True)
class FileView:
    """A whole file as the platform reads it."""

    kind: str
    parts: list[PartView]
    topics: list[str] = field(default_factory=list)


# ---------------------------------------------------------------------------
# ROS 2


def _rosidl() -> Any:
    try:
        from mcap_ros2._vendor.rosidl_adapter import parser
    except ImportError:
        raise OracleMissing("the ROS 2 round trip needs mcap-ros2-support (pip install mcap-ros2-support)") from None
    return parser


def ros_view(kind: str, package: str, name: str, text: str) -> FileView:
    """A .msg/.srv/.action file as rosidl reads it."""
    parser = _rosidl()
    try:
        if kind == "msg":
            specs = [parser.parse_message_string(package, name, text)]
        elif kind == "srv":
            s = parser.parse_service_string(package, name, text)
            specs = [s.request, s.response]
        else:
            a = parser.parse_action_string(package, name, text)
            specs = [a.goal, a.result, a.feedback]
    except Exception as e:  # rosidl raises many exception types, and prints to stderr
        raise OracleRefused(f"rosidl refuses it: {e}") from None
    folder = "msg" if kind == "msg" else kind
    parts = []
    for spec in specs:
        part = PartView(f"{package}/{folder}/{spec.msg_name}")
        for f in spec.fields:
            part.fields.append((f.name, str(f.type), f.default_value))
            part.descs.append((f.name, _desc(f.type)))
        for c in spec.constants:
            part.constants.append((c.type, c.name, c.value))
        parts.append(part)
    return FileView(kind, parts)


def idl_views(text: str) -> dict[str, FileView]:
    """Every interface of an .idl file as rosbags' IDL parser reads it, by name (fields without defaults).

    Raises OracleRefused when rosbags refuses the file.
    """
    try:
        from .idl import defaults, read_idl, structs_of
    except ImportError:
        raise OracleMissing("the ROS 2 round trip of .idl files needs rosbags (pip install rosbags)") from None
    try:
        types = read_idl(text)
    except ImportError:
        raise OracleMissing("the ROS 2 round trip of .idl files needs rosbags (pip install rosbags)") from None
    except Exception as e:  # rosbags raises its own error types
        raise OracleRefused(f"rosbags refuses it: {str(e).splitlines()[0]}") from None
    values = defaults(text)
    out: dict[str, FileView] = {}
    for kind, name, fulls in structs_of(types):
        parts = []
        for full in fulls:
            consts, fields = types[full]
            short = full.rpartition("/")[2]
            part = PartView(full)
            part.descs = [(n, _from_rosbags(d)) for n, d in fields]
            part.fields = [(n, "", _default(values.get((short, n)), d)) for n, d in part.descs]
            part.constants = [(t, n, v) for n, t, v in consts]
            parts.append(part)
        out[name] = structural(FileView(kind, parts))
    return out


def _default(value: Any, desc: tuple[Any, ...]) -> Any:
    from .idl import array_value

    return array_value(value) if desc[0] in ("array", "sequence") else value


def structural(view: FileView) -> FileView:
    """``view`` with field types written from their descs, as an .idl file and a .msg file both state them."""
    parts = []
    for p in view.parts:
        given = {f[0]: f[2] for f in p.fields}
        parts.append(PartView(p.name, [(n, desc_text(d), given.get(n)) for n, d in p.descs], p.constants, p.descs))
    return FileView(view.kind, parts, view.topics)


def renamed(view: FileView, names: dict[str, str]) -> FileView:
    """A structural ``view`` with type names replaced (``test_msgs/idl/T`` → ``pkg/msg/T``)."""

    def desc(d: tuple[Any, ...]) -> tuple[Any, ...]:
        kind, rest = d
        if kind == "name":
            return (kind, names.get(rest, rest))
        if kind in ("array", "sequence"):
            return (kind, (desc(rest[0]), rest[1]))
        return d

    parts = [PartView(names.get(p.name, p.name), p.fields, p.constants, [(n, desc(d)) for n, d in p.descs])
             for p in view.parts]
    return structural(FileView(view.kind, parts, view.topics))


def desc_text(d: tuple[Any, ...]) -> str:
    """A desc as a .msg type: ``int32``, ``wstring<=5``, ``pkg/msg/T[3]``, ``string[<=2]``, ``uint8[]``."""
    kind, rest = d
    if kind == "array":
        return f"{desc_text(rest[0])}[{rest[1]}]"
    if kind == "sequence":
        return f"{desc_text(rest[0])}[<={rest[1]}]" if rest[1] else f"{desc_text(rest[0])}[]"
    if kind == "name":
        return str(rest)
    return f"{rest[0]}<={rest[1]}" if rest[1] else str(rest[0])


def _desc(t: Any) -> tuple[Any, ...]:
    """A rosidl type in rosbags' desc form: ('base', (name, bound)) / ('name', 'pkg/msg/T'), maybe in an array."""
    if t.is_primitive_type():
        core: tuple[Any, ...] = ("base", (t.type, t.string_upper_bound or 0))
    else:
        core = ("name", f"{t.pkg_name}/msg/{t.type}")
    if not t.is_array:
        return core
    if t.array_size and not t.is_upper_bound:
        return ("array", (core, t.array_size))
    return ("sequence", (core, t.array_size or 0))


def _store_defs() -> dict[str, list[tuple[str, Any]]]:
    """Fields of the types rosbags knows (its latest ROS 2 store), in desc form."""
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        return {}
    out: dict[str, list[tuple[str, Any]]] = {}
    for typename, (_, fields) in get_typestore(Stores.LATEST).fielddefs.items():
        out[typename] = [(n, _from_rosbags(d)) for n, d in fields]
    return out


def _from_rosbags(desc: Any) -> tuple[Any, ...]:
    node, rest = desc
    kind = node.name.lower()
    if kind in ("array", "sequence"):
        return (kind, (_from_rosbags(rest[0]), rest[1]))
    return (kind, rest)


_STORE: dict[str, list[tuple[str, Any]]] | None = None


def known_types() -> dict[str, list[tuple[str, Any]]]:
    """Types from packages outside the round trip (builtin_interfaces …), loaded once."""
    global _STORE
    if _STORE is None:
        _STORE = _store_defs()
    return _STORE


def rihs01(typename: str, defs: dict[str, list[tuple[str, Any]]]) -> str | None:
    """The RIHS01 hash of ``typename`` over ``defs`` (then rosbags' store); None when a type is unknown."""
    structs: dict[str, dict[str, Any]] = {}

    def lookup(name: str) -> list[tuple[str, Any]] | None:
        found = defs.get(name)
        return found if found is not None else known_types().get(name)

    def field_of(name: str, desc: tuple[Any, ...]) -> dict[str, Any] | None:
        increment = capacity = string_capacity = 0
        kind, rest = desc
        if kind == "array":
            increment, capacity = FIXED, rest[1]
            kind, rest = rest[0]
        elif kind == "sequence":
            increment, capacity = (BOUNDED, rest[1]) if rest[1] else (UNBOUNDED, 0)
            kind, rest = rest[0]
        subtype = ""
        if kind == "name":
            subtype = rest
            if struct(subtype) is None:
                return None
            tid = increment + TYPE_IDS["nested"]
        elif rest[0] in ("string", "wstring") and rest[1]:
            string_capacity = rest[1]
            tid = increment + TYPE_IDS[f"bounded_{rest[0]}"]
        else:
            tid = increment + TYPE_IDS[rest[0]]
        return {"name": name, "type": {"type_id": tid, "capacity": capacity, "string_capacity": string_capacity,
                                       "nested_type_name": subtype}}

    def struct(name: str) -> dict[str, Any] | None:
        if name in structs:
            return structs[name]
        fields = lookup(name)
        if fields is None:
            return None
        structs[name] = {}  # a placeholder: types cannot contain themselves, but stay finite anyway
        out = [field_of(n, d) for n, d in (fields or [("structure_needs_at_least_one_member", ("base", ("uint8", 0)))])]
        if any(f is None for f in out):
            return None
        structs[name] = {"type_name": name, "fields": out}
        return structs[name]

    top = struct(typename)
    if top is None:
        return None
    doc = {"type_description": top,
           "referenced_type_descriptions": [v for k, v in sorted(structs.items()) if k != typename]}
    return "RIHS01_" + sha256(json.dumps(doc).encode()).hexdigest()


# ---------------------------------------------------------------------------
# PX4


def px4_view(name: str, text: str) -> FileView:
    """A uORB .msg file as genmsg reads it, with its topics."""
    try:
        import genmsg
        from genmsg import msg_loader
    except ImportError:
        raise OracleMissing("the PX4 round trip needs pyros-genmsg (pip install pyros-genmsg)") from None
    try:
        spec = msg_loader.load_msg_from_string(genmsg.MsgContext.create_default(), text, f"px4/{name}")
    except Exception as e:  # genmsg raises its own exception types
        raise OracleRefused(f"genmsg refuses it: {e}") from None
    part = PartView(f"px4/{name}")
    part.fields = [(n, t, None) for t, n in zip(spec.types, spec.names)]
    part.constants = [(c.type, c.name, c.val) for c in spec.constants]
    return FileView("msg", [part], topics_of(text))


# ---------------------------------------------------------------------------
# Comparing


def differences(a: FileView, b: FileView) -> list[str]:
    """How ``b`` (regenerated) differs from ``a`` (original), in words; empty when they mean the same."""
    out: list[str] = []
    for pa, pb in zip(a.parts, b.parts):
        where = pa.name.rpartition("/")[2]
        out.extend(_list_diff(f"{where}: field", pa.fields, pb.fields))
        out.extend(_list_diff(f"{where}: constant", pa.constants, pb.constants))
    if len(a.parts) != len(b.parts):
        out.append(f"{len(a.parts)} parts became {len(b.parts)}")
    if a.topics != b.topics:
        out.append(f"topics {a.topics} became {b.topics}")
    return out


def _list_diff(what: str, a: list[tuple[Any, ...]], b: list[tuple[Any, ...]]) -> list[str]:
    out = []
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y or type(x[-1]) is not type(y[-1]):
            out.append(f"{what} {i + 1}: expected {_show(x)}, got {_show(y)}")
    if len(a) > len(b):
        out.extend(f"{what} {_show(x)} is missing" for x in a[len(b):])
    elif len(b) > len(a):
        out.extend(f"{what} {_show(y)} is extra" for y in b[len(a):])
    return out


def _show(t: tuple[Any, ...]) -> str:
    return " ".join(repr(x) if not isinstance(x, str) else x for x in t if x is not None)
