"""Model helpers the PX4 and ArduPilot targets share: owners, values, names, code tables."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from ... import model as m
from ...compile import Compilation
from ...diagnostics import Diagnostic, Severity
from ...naming import ros_type_name, words
from ...resolve import constant_value
from ...source import Source, Span
from ...walk import resolve_typedefs
from .escape import one_line

#: A Python value read from an interface value: what templates format.
Literal = int | float | bool | str | list["Literal"] | None


class CodeTable:
    """A target's diagnostic codes: each with a default severity and a summary."""

    def __init__(self, codes: dict[str, tuple[Severity, str]]) -> None:
        self.codes = codes

    def __call__(self, code: str, message: str, source: Source, span: Span) -> Diagnostic:
        """A located diagnostic with ``code`` at its default severity."""
        return Diagnostic(code, message, source, span, self.codes[code][0])


class Owners:
    """Which interface (hence which source file) holds each definition of a compilation."""

    def __init__(self, comp: Compilation) -> None:
        self.root = comp.interface
        self._by_id: dict[int, m.Interface] = {}
        for c in reversed(comp.closure()):
            for d in c.interface.definitions:
                self._by_id[id(d)] = c.interface

    def of(self, defn: m.Definition) -> m.Interface:
        """The interface that defines ``defn`` (the root one when unknown)."""
        return self._by_id.get(id(defn), self.root)

    def source(self, defn: m.Definition) -> Source:
        """The source file of ``defn``."""
        return self.of(defn).source


def source_name(comp: Compilation) -> str:
    """The file name shown in generated headers (never a full path: output must not depend on it)."""
    return one_line(Path(comp.path).name) or "interface"


def literal(iface: m.Interface, v: m.Value, depth: int = 0) -> Literal:
    """The value ``v`` as Python data, names resolved to the constants or enum values they name."""
    if depth > 32:
        return None
    if v.kind in ("int", "double", "string"):
        return v.value  # type: ignore[return-value]
    if v.kind == "name":
        if v.value in ("true", "false"):
            return v.value == "true"
        ref = constant_value(iface, str(v.value))
        if isinstance(ref, m.EnumValue):
            return ref.value
        if isinstance(ref, m.Const):
            return literal(iface, ref.value, depth + 1)
        return None
    if v.kind == "list":
        return [literal(iface, x, depth + 1) for x in v.value]  # type: ignore[union-attr]
    return None


def snake(name: str) -> str:
    """``SensorAccel`` → ``sensor_accel``, ``maxSpeed`` → ``max_speed``."""
    return "_".join(w.lower() for w in words(name))


def upper(name: str) -> str:
    """``maxSpeed`` → ``MAX_SPEED``."""
    return "_".join(w.upper() for w in words(name))


def camel(name: str) -> str | None:
    """``robot_arm`` → ``RobotArm``; None when no C++/ROS type name results."""
    return ros_type_name(name)


def humanize(name: str) -> str:
    """``max_speed`` → ``Max speed``."""
    text = " ".join(w.lower() for w in words(name))
    return text[:1].upper() + text[1:]


def member_order(body: m.Struct | m.Section) -> list[m.Field | m.Const]:
    """Fields and constants of a body in the order they are written."""
    return sorted([*body.fields, *body.consts], key=lambda x: x.span.start)


def enum_of(t: m.TypeRef) -> m.Enum | None:
    """The enum a type stands for, through typedefs."""
    r = resolve_typedefs(t)
    return r.target if isinstance(r, m.NamedType) and isinstance(r.target, m.Enum) else None


def configuration_blocks(iface: m.Interface) -> Iterator[m.Struct]:
    """The configuration bodies of the interface (P), in order."""
    for d in iface.definitions:
        if isinstance(d, m.Struct) and d.kind == "configuration":
            yield d


_INT_TYPES = (("uint8", 0, 2**8 - 1), ("int8", -(2**7), 2**7 - 1), ("uint16", 0, 2**16 - 1),
              ("int16", -(2**15), 2**15 - 1), ("uint32", 0, 2**32 - 1), ("int32", -(2**31), 2**31 - 1))


def enum_int_type(enum: m.Enum) -> str:
    """The smallest integer type (uORB/ROS spelling) that holds every value of ``enum``."""
    values = [v.value for v in enum.values] or [0]
    for name, lo, hi in _INT_TYPES:
        if lo <= min(values) and max(values) <= hi:
            return name
    return "int64"
