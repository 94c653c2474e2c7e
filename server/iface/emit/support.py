"""Model helpers targets share: which file owns a definition, values as Python data, name styles."""

from __future__ import annotations

import re
from collections.abc import Iterator

from ..model import nodes as m
from ..model.naming import ros_type_name, words
from ..model.source import Source, Span
from ..model.walk import resolve_typedefs
from ..semantics.compile import Compilation
from ..semantics.resolve import constant_value

#: A Python value read from an interface value: what templates format.
Literal = int | float | bool | str | list["Literal"] | None
#: A PX4 or ArduPilot parameter name (and prefix): UPPER_CASE letters and digits.
PARAM_NAME = re.compile(r"^[A-Z][A-Z0-9]*(_[A-Z0-9]+)*$")


class Owners:
    """Which interface (hence which source file) holds each definition of a compilation."""

    def __init__(self, comp: Compilation) -> None:
        self.root = comp.interface
        self._by_id: dict[int, m.Interface] = {}
        for c in reversed(comp.closure()):
            for d in c.interface.definitions:
                self._by_id[id(d)] = c.interface

    def of(self, defn: object, default: m.Interface | None = None) -> m.Interface:
        """The interface that defines ``defn``; ``default`` (else the root one) when it is no definition."""
        return self._by_id.get(id(defn), default if default is not None else self.root)

    def source(self, defn: m.Definition) -> Source:
        """The source file of ``defn``."""
        return self.of(defn).source


def literal(iface: m.Interface, v: m.Value, depth: int = 0) -> Literal:
    """The value ``v`` as Python data, names resolved to the constants or enum values they name."""
    if depth > 32:
        return None
    if v.kind in ("int", "double", "string"):
        return v.value
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
        return [literal(iface, x, depth + 1) for x in v.value]
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


def component_span(iface: m.Interface) -> Span:
    """Where the component is named (the start of the file when it has no declaration)."""
    return iface.component.name_span if iface.component is not None else Span(0, 0)


def parameter_prefixes(iface: m.Interface, key: str) -> Iterator[tuple[m.Struct, str, Span]]:
    """Each configuration block with its parameter name prefix and where the prefix is stated.

    The prefix is the block's ``key`` annotation, else the component's, else the
    component name in UPPER_CASE (located at the block's name).
    """
    decl = iface.component
    stated = m.annotation(decl.annotations, key) if decl is not None else None
    for block in configuration_blocks(iface):
        ann = m.annotation(block.annotations, key) or stated
        yield block, (ann.text if ann else upper(iface.name)), (ann.span if ann else block.name_span)
