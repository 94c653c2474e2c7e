"""Writing lowered ROS 2 interfaces as OMG IDL 4 the way rosidl writes it."""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from ...model.diagnostics import Diagnostic
from .. import types
from ..ros2.codes import diag
from ..ros2.package import (
    PyValue,
    RosInterface,
    RosPackage,
    RosSection,
    RosType,
    Scalar,
)
from ..text import quote
from .reserved import idl_name

#: ROS 2 primitive → IDL type (rosidl's own mapping; ``char`` is ``uint8``, ``byte`` is ``octet``).
ROS_TO_IDL: dict[str, str] = {row.ros2: row.idl for row in types.BASE_TYPES.values()
                              if row.ros2 is not None and row.idl is not None and "[" not in row.ros2}
_PART_SUFFIXES = {"msg": ("",), "srv": ("_Request", "_Response"), "action": ("_Goal", "_Result", "_Feedback")}
_ESCAPES = {'"': '\\"', "\n": "\\n", "\t": "\\t", "\r": "\\r", "\\": "\\\\"}
#: In a @verbatim comment a backslash is written as an octal escape.
_COMMENT_ESCAPES = {**_ESCAPES, "\\": "\\134"}


def _idl_escape(c: str) -> str:
    code = ord(c)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code <= 0xFFFF else "?"


def idl_string(text: str, *, comment: bool = False) -> str:
    """A double-quoted IDL string literal; in comments a backslash is written as an octal escape."""
    return quote(text, _COMMENT_ESCAPES if comment else _ESCAPES, _idl_escape)


def idl_scalar(value: Scalar) -> str:
    """A constant or @default value."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, (int, float)):
        return repr(value)
    return idl_string(value)


def idl_default(value: PyValue) -> str:
    """An @default value: arrays as rosidl writes them, a string of a Python-style tuple."""
    if isinstance(value, list):
        return idl_string("(" + ", ".join(repr(v) for v in value) + ")")
    return idl_scalar(value)


def element(rt: RosType, escape: bool = False) -> str:
    """The IDL element type (no array); ``escape``: keyword parts of a message type's scoped name escaped."""
    if rt.primitive is not None:
        base = ROS_TO_IDL[rt.primitive]
        return f"{base}<{rt.string_bound}>" if rt.string_bound is not None else base
    if not escape:
        return f"{rt.package}::msg::{rt.name}"
    return f"{idl_name(rt.package or '')}::msg::{idl_name(rt.name or '')}"


def typedef_name(rt: RosType) -> str:
    """The typedef rosidl declares for a fixed array (``double__9``), from the unescaped names."""
    return re.sub(r"[^A-Za-z0-9]+", "__", element(rt)).strip("_") + f"__{rt.size}"


def idl_type(rt: RosType, escape: bool = False) -> str:
    """The type of a member (``escape``: keyword-named message types escaped)."""
    if rt.array == "fixed":
        return typedef_name(rt)
    if rt.array == "bounded":
        return f"sequence<{element(rt, escape)}, {rt.size}>"
    if rt.array == "unbounded":
        return f"sequence<{element(rt, escape)}>"
    return element(rt, escape)


@dataclass(frozen=True, slots=True)
class IdlStruct:
    """One struct of an IDL file: name, the section it holds, and its ``@verbatim`` comment lines."""

    name: str
    section: RosSection
    comments: list[str]


def structs(ri: RosInterface) -> list[IdlStruct]:
    """The structs of an interface file (``Foo``; ``Foo_Request``/``_Response``; ``Foo_Goal``/…).

    As in rosidl, each struct carries its part's comment; the first one also the file's
    (the definition's doc), a blank line before the part's own.
    """
    out = []
    for i, (suffix, sec) in enumerate(zip(_PART_SUFFIXES[ri.kind], ri.sections)):
        comments = list(sec.comments)
        if i == 0 and ri.comments:
            comments = [*ri.comments, *([""] if comments else []), *comments]
        out.append(IdlStruct(ri.name + suffix, sec, comments))
    return out


def typedefs(ri: RosInterface, escape: bool = False) -> list[tuple[str, str, int]]:
    """(element, name, size) of every fixed-array typedef the file needs, once each, in order."""
    seen: dict[str, tuple[str, str, int]] = {}
    for sec in ri.sections:
        for f in sec.fields:
            if f.type.array == "fixed":
                seen.setdefault(typedef_name(f.type), (element(f.type, escape), typedef_name(f.type),
                                                              f.type.size or 0))
    return list(seen.values())


def includes(ri: RosInterface) -> list[str]:
    """The IDL files of the message types a file uses."""
    found = {f"{f.type.package}/msg/{f.type.name}.idl" for sec in ri.sections for f in sec.fields
             if f.type.primitive is None}
    return sorted(found)


def check_idl_values(pkg: RosPackage) -> Iterator[Diagnostic]:
    """Errors for string values IDL readers would decode differently (a backslash)."""
    for ri in pkg.interfaces:
        for sec in ri.sections:
            for c in sec.consts:
                if isinstance(c.value, str) and "\\" in c.value:
                    yield diag("idl-unwritable-string", f"constant '{c.name}' of {ri.name} holds a backslash, "
                               "which IDL readers decode differently", c.source, c.span)
            for f in sec.fields:
                values = f.default if isinstance(f.default, list) else [f.default]
                if any(isinstance(v, str) and ("\\" in v or (isinstance(f.default, list) and "'" in v))
                       for v in values):
                    yield diag("idl-unwritable-string", f"the default of '{f.name}' in {ri.name} holds a "
                               "backslash (or a quote inside an array), which IDL readers decode differently",
                               f.source, f.span)


FILTERS: dict[str, Callable[..., Any]] = {
    "idl_string": idl_string,
    "idl_comment": lambda text: idl_string(text, comment=True),
    "idl_scalar": idl_scalar,
    "idl_default": idl_default,
    "idl_type": idl_type,
    "idl_name": lambda name, escape=False: idl_name(name) if escape else name,
    "idl_primitive": ROS_TO_IDL.__getitem__,
}
