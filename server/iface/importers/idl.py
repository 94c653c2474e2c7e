"""ROS 2 ``.idl`` files, as rosbags' IDL parser reads them, → parsed interface files.

rosbags gives each struct's fields and constants (not defaults or comments). Before it reads
a file, preprocessor lines (``#include``, ``#ifndef`` guards …) are blanked — the types an
include brings are named by their scoped name (``pkg::msg::T``) and resolved against the
packages being imported, as rosidl resolves them — and a ``>>`` that closes two templates
(``sequence<string<5>>``, as rosidl writes it) is split, which rosbags' tokenizer needs.
A ``srv`` module's ``X_Request``/``X_Response`` structs make a service, an ``action``
module's ``X_Goal``/``X_Result``/``X_Feedback`` an action; every other struct a message.
"""

from __future__ import annotations

import re
from typing import Any

from .rosidl import PRIMITIVE_TYPES, ArrayKind, Element, Kind, Part, RosFile, RosType

#: rosbags' base type names → ROS primitive names (wchar exists in .idl only).
_BASE = {name: name for name in PRIMITIVE_TYPES} | {"octet": "byte", "wchar": "wchar"}
_DIRECTIVE = re.compile(r"^[ \t]*#.*$", re.MULTILINE)
_CLOSE = re.compile(r">>(?=[\s\w,>])")
_PARTS: dict[str, tuple[str, ...]] = {"srv": ("_Request", "_Response"), "action": ("_Goal", "_Result", "_Feedback")}


def rosbags_text(text: str) -> str:
    """``text`` as rosbags' IDL parser reads it (same line numbers)."""
    text = _DIRECTIVE.sub("", text)
    return "\n".join(line if line.lstrip().startswith("const ") else _CLOSE.sub("> >", line)
                     for line in text.split("\n"))


def read_idl(text: str) -> dict[str, Any]:
    """rosbags' view of an .idl file: ``{'pkg/msg/Name': (constants, fields)}``; raises on bad IDL."""
    from rosbags.typesys import get_types_from_idl

    return dict(get_types_from_idl(rosbags_text(text)))


def _type(desc: Any, module: str) -> RosType:
    node, rest = desc
    kind = getattr(node, "name", str(node))
    if kind in ("ARRAY", "SEQUENCE"):
        inner, count = rest
        element = _type(inner, module)
        if kind == "ARRAY":
            return RosType(element.name, element.package, element.primitive, element.string_bound, "fixed", count)
        array: ArrayKind = "bounded" if count else "unbounded"
        return RosType(element.name, element.package, element.primitive, element.string_bound, array,
                       count or None)
    if kind == "NAME":
        package, _, name = str(rest).partition("/")
        name = name.rpartition("/")[2]
        return RosType(name, None if package == module else package, primitive=False)
    base, bound = rest
    if base not in _BASE:
        raise ValueError(f"the IDL type '{base}' has no iface equivalent")
    return RosType(_BASE[base], string_bound=bound or None)


def _part(full: str, consts: list[Any], fields: list[Any], problems: list[str]) -> Part | None:
    module = full.partition("/")[0]
    name = full.rpartition("/")[2]
    part = Part(name, 0)
    ok = True
    for cname, ctype, value in consts:
        if ctype not in _BASE:
            problems.append(f"{name}.{cname}: the IDL type '{ctype}' has no iface equivalent")
            ok = False
            continue
        text = ("true" if value else "false") if isinstance(value, bool) else str(value)
        part.elements.append(Element("constant", RosType(_BASE[ctype]), cname, 0, value, [text]))
    for fname, desc in fields:
        try:
            part.elements.append(Element("field", _type(desc, module), fname, 0))
        except ValueError as e:
            problems.append(f"{name}.{fname}: {e}")
            ok = False
    return part if ok else None


def structs_of(types: dict[str, Any]) -> list[tuple[Kind, str, list[str]]]:
    """(kind, interface name, full struct names in part order) of every interface in an .idl file."""
    out: list[tuple[Kind, str, list[str]]] = []
    used: set[str] = set()
    for full in sorted(types):
        prefix, _, name = full.rpartition("/")
        sub = prefix.rpartition("/")[2]
        suffixes = _PARTS.get(sub)
        if suffixes and name.endswith(suffixes[0]):
            stem = name[: -len(suffixes[0])]
            parts = [f"{prefix}/{stem}{s}" for s in suffixes]
            if all(p in types for p in parts):
                out.append(("srv" if sub == "srv" else "action", stem, parts))
                used.update(parts)
    out.extend(("msg", full.rpartition("/")[2], [full]) for full in sorted(types) if full not in used)
    return sorted(out, key=lambda x: x[2][0])


def ros_files_from_idl(types: dict[str, Any], package: str) -> tuple[list[RosFile], list[str]]:
    """One interface per message struct, service or action; problems name the struct and the field."""
    files: list[RosFile] = []
    problems: list[str] = []
    for kind, name, fulls in structs_of(types):
        parts = [_part(full, *types[full], problems) for full in fulls]
        if all(p is not None for p in parts):
            rf = RosFile(kind, package, name)
            rf.parts.extend(p for p in parts if p is not None)
            files.append(rf)
    return files, problems
