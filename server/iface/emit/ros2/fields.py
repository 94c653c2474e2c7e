"""Lowering, part 2: ROS 2 types, decoded values, sections of fields and constants."""

from __future__ import annotations

from dataclasses import replace

from ...model import nodes as m
from ...model.naming import is_ros_field, is_ros_type, ros_constant_name
from ...model.source import Source
from ...model.walk import resolve_typedefs
from ...semantics.resolve import constant_value
from .. import types
from ..text import doc_lines
from .names import Namer
from .package import (
    ENUM_PRIMITIVE,
    PyValue,
    RosConst,
    RosField,
    RosSection,
    RosType,
    Scalar,
)

_INT_PRIMITIVES = frozenset({"int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
                             "byte", "char", "wchar"})
_FLOAT_PRIMITIVES = frozenset({"float32", "float64"})
_STRING_PRIMITIVES = frozenset({"string", "wstring"})


def field_comments(f: m.Field) -> list[str]:
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


class FieldLowering(Namer):
    """Types, values and sections (the parts every interface file is made of)."""

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
            sec.fields.append(RosField(fname, rt, default, field_comments(f), src, f.name_span))
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


_INT_RANGE: dict[str, tuple[int, int]] = {
    types_name: m.INT_RANGES[canonical]
    for canonical, row in types.BASE_TYPES.items()
    if canonical in m.INT_RANGES and (types_name := row.ros2) is not None
}
