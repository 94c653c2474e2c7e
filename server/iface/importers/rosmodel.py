"""Parsed ROS interface files → model definitions (shared by the ROS 2 and PX4 importers)."""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Hashable, Iterable
from typing import TypeVar

from ..model import nodes as m
from ..model.source import Span
from ..text.printer import quote
from .rosidl import Element, Part, RosSyntaxError, RosType, Scalar, clean_comments
from .units import unit_of_comment

_INT = re.compile(r"[+-]?(0x[0-9A-Fa-f]+|[0-9]+)\Z")
_DOUBLE = re.compile(r"[+-]?([0-9]+\.[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\Z|[+-]?[0-9]+[eE][+-]?[0-9]+\Z")

#: ROS primitive → (canonical model name, spelling written in the .iface file).
PRIMITIVES: dict[str, tuple[str, str]] = {
    "bool": ("bool", "bool"), "byte": ("octet", "octet"), "char": ("char", "char"),
    "int8": ("i8", "int8"), "uint8": ("u8", "uint8"), "int16": ("i16", "int16"), "uint16": ("u16", "uint16"),
    "int32": ("i32", "int32"), "uint32": ("u32", "uint32"), "int64": ("i64", "int64"),
    "uint64": ("u64", "uint64"), "float32": ("float32", "float32"), "float64": ("float64", "float64"),
    "string": ("string", "string"), "wstring": ("wstring", "wstring"), "wchar": ("wchar", "wchar"),
}

#: Resolves a message type to the name the .iface file uses for it (raises RosSyntaxError if unknown).
NameOf = Callable[[RosType], str]

#: What an interface file holding a NUL byte is told (``check`` tells an .iface file the same).
BINARY_FILE = "the file holds NUL bytes: it is binary, not an interface file"

K = TypeVar("K", bound=Hashable)


def nul_line(text: str) -> int | None:
    """The line of the first NUL byte of ``text`` (1-based), or None when it has none."""
    at = text.find("\0")
    return None if at < 0 else text.count("\n", 0, at) + 1


def not_imported_type(shown: str, path: object) -> str:
    """Why a message type named ``shown`` whose file ``path`` is not imported cannot be used."""
    return f"unknown type '{shown}': {path} is not imported, as it has errors (reported on it)"


def uses(parts: Iterable[Part]) -> tuple[list[RosType], bool]:
    """The message types the members of ``parts`` use, and whether a member has a problem of its own (a value
    its type cannot hold): then the definition is not imported whatever it uses."""
    used: list[RosType] = []

    def name_of(t: RosType) -> str:
        used.append(t)
        return t.name

    problems: list[tuple[int, str]] = []
    for part in parts:
        members(part, name_of, Spans(), problems=problems)
    return used, bool(problems)


def not_imported(broken: Iterable[K], users: dict[K, list[K]]) -> set[K]:
    """``broken`` and every definition that uses one of them, and so on (``users``: who uses each one): a
    definition written beside them would name a type the written file lacks."""
    out = set(broken)
    queue = list(out)
    while queue:
        for user in users.get(queue.pop(), ()):
            if user not in out:
                out.add(user)
                queue.append(user)
    return out


class Spans:
    """Increasing spans, so that the printer writes members in the order they were read."""

    def __init__(self) -> None:
        self.at = 0

    def __call__(self) -> Span:
        self.at += 1
        return Span(self.at, self.at)


def model_type(t: RosType, name_of: NameOf, spans: Spans) -> m.TypeRef:
    """The model type of a ROS type."""
    core: m.TypeRef
    if t.primitive:
        canonical, spelling = PRIMITIVES[t.name]
        core = m.BaseType(canonical, spans(), spelling, t.string_bound)
    else:
        core = m.NamedType(name_of(t), spans())
    if t.array is None:
        return core
    return m.ArrayType(core, spans(), t.array, t.size)


def _scalar(t: str, value: Scalar, text: str, spans: Spans) -> m.Value:
    if t in ("char", "wchar") and isinstance(value, str) and len(value) == 1:  # an IDL character literal
        value = ord(value)
        text = str(value)
    if t == "bool":
        word = "true" if value else "false"
        return m.Value("name", word, spans(), word)
    if t in ("string", "wstring"):
        return m.Value("string", value, spans(), quote(str(value)))
    if t in ("float32", "float64"):
        number = float(value)
        if math.isinf(number) or math.isnan(number):
            raise RosSyntaxError(f"value '{text}' is not finite: iface numbers are finite")
        if _INT.match(text):
            return m.Value("int", int(text, 16) if "x" in text.lower() else int(text), spans(), text)
        if _DOUBLE.match(text):
            return m.Value("double", number, spans(), text)
        return m.Value("double", number, spans(), repr(number))
    text = text if _INT.match(text) and _int(text) == value else str(value)
    return m.Value("int", value, spans(), text)


def _int(text: str) -> int:
    sign = -1 if text.startswith("-") else 1
    digits = text.lstrip("+-")
    return sign * (int(digits[2:], 16) if digits[:2].lower() == "0x" else int(digits, 10))


def model_value(e: Element, spans: Spans) -> m.Value | None:
    """The model value of a default or a constant value, spelled as written where the language allows."""
    if e.value is None:
        return None
    if isinstance(e.value, list):
        items = [_scalar(e.type.name, v, text, spans) for v, text in zip(e.value, e.texts)]
        return m.Value("list", items, spans())
    return _scalar(e.type.name, e.value, e.texts[0], spans)


def members(part: Part, name_of: NameOf, spans: Spans, *, lead: list[str] | None = None,
            problems: list[tuple[int, str]]) -> tuple[list[m.Field], list[m.Const]]:
    """Fields and constants of one body; ``lead`` comments go to the first member."""
    fields: list[m.Field] = []
    consts: list[m.Const] = []
    for i, e in enumerate(part.elements):
        comments = ([*lead, ""] if lead and i == 0 else []) + e.comments
        doc = clean_comments(comments)
        try:
            t = model_type(e.type, name_of, spans)
            value = model_value(e, spans)
        except RosSyntaxError as err:
            problems.append((e.line, str(err)))
            continue
        if e.kind == "constant":
            assert value is not None
            consts.append(m.Const(e.name, t, value, spans(), spans(), [], doc))
        else:
            unit = unit_of_comment([e.inline] if e.inline is not None else e.comments) \
                if e.type.name in _NUMBERS and e.type.package is None else None
            annotations = [m.Annotation("unit", m.Value("string", unit, spans()), spans())] if unit else []
            fields.append(m.Field(e.name, t, spans(), spans(), default=value, annotations=annotations, doc=doc))
    return fields, consts


#: ROS 2 number types: their fields may carry a unit read from the comment.
_NUMBERS = frozenset({"float32", "float64", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32",
                      "uint64"})
