"""ROS 2 ``.idl`` files, as rosbags' IDL parser reads them, → parsed interface files.

rosbags gives each struct's fields and constants, not their ``@default`` values: those are
read here from each member's annotations (``@default (value=…)``, as rosidl writes them, an
array as the string of a tuple). Before rosbags reads
a file, preprocessor lines (``#include``, ``#ifndef`` guards …) are blanked — the types an
include brings are named by their scoped name (``pkg::msg::T``) and resolved against the
packages being imported, as rosidl resolves them — and a ``>>`` that closes two templates
(``sequence<string<5>>``, as rosidl writes it) is split, which rosbags' tokenizer needs.
A ``srv`` module's ``X_Request``/``X_Response`` structs make a service, an ``action``
module's ``X_Goal``/``X_Result``/``X_Feedback`` an action; every other struct a message.
"""

from __future__ import annotations

import ast
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


_COMMENT = re.compile(r'"(?:\\.|[^"\\])*"|//[^\n]*|/\*.*?\*/', re.DOTALL)
_STRUCT = re.compile(r"\bstruct\s+([A-Za-z_]\w*)\s*\{")
_TOKEN = re.compile(r'L?"(?:\\.|[^"\\])*"|[{};]|[^{};"]+')
_DEFAULT = re.compile(r'@default\s*\(\s*value\s*=\s*(L?"(?:\\.|[^"\\])*"|[^)\s]+)\s*\)')
_NAME = re.compile(r"([A-Za-z_]\w*)\s*(?:\[[^\]]*\]\s*)*$")


def defaults(text: str) -> dict[tuple[str, str], Any]:
    """``@default`` values by (struct name, member name), decoded as rosidl_parser decodes them."""
    text = _COMMENT.sub(lambda mt: mt.group() if mt.group().startswith('"') else " ", _DIRECTIVE.sub("", text))
    out: dict[tuple[str, str], Any] = {}
    for found in _STRUCT.finditer(text):
        members, depth = [""], 1
        for token in _TOKEN.finditer(text, found.end()):
            t = token.group()
            depth += (t == "{") - (t == "}")
            if depth == 0:
                break
            if t == ";":  # a ';' inside a string literal is part of its token
                members.append("")
            else:
                members[-1] += t
        for member in members:
            value = _DEFAULT.search(member)
            name = _NAME.search(member.strip())
            if value and name:
                out[(found.group(1), name.group(1))] = _literal(value.group(1))
    return out


def _literal(text: str) -> Any:
    """An IDL literal: TRUE/FALSE, a number, a string."""
    if text in ("TRUE", "FALSE"):
        return text == "TRUE"
    try:
        return ast.literal_eval(text[1:] if text.startswith('L"') else text)
    except (ValueError, SyntaxError):  # not a Python literal either: kept as written
        return text


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


def array_value(value: Any) -> Any:
    """An array field's default: rosidl writes it as the string of a tuple, ``"(1, 2)"``."""
    if isinstance(value, str):
        try:
            parsed = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            return value
        return list(parsed) if isinstance(parsed, (tuple, list)) else value
    return value


def _part(full: str, consts: list[Any], fields: list[Any], problems: list[str],
          values: dict[tuple[str, str], Any]) -> Part | None:
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
            element = Element("field", _type(desc, module), fname, 0)
        except ValueError as e:
            problems.append(f"{name}.{fname}: {e}")
            ok = False
            continue
        if (name, fname) in values:
            value = values[name, fname]
            element.value = array_value(value) if element.type.array else value
            items = element.value if isinstance(element.value, list) else [element.value]
            if not element.type.primitive or not all(_fits(element.type.name, v) for v in items) or \
                    (element.type.array is not None) != isinstance(element.value, list):
                problems.append(f"{name}.{fname}: the @default value {value!r} is not a value of type "
                                f"{element.type.text()}")
                ok = False
                continue
            element.texts = [("true" if v else "false") if isinstance(v, bool) else str(v) for v in items]
        part.elements.append(element)
    return part if ok else None


def _fits(primitive: str, value: Any) -> bool:
    """True when a decoded default is a value of the ROS primitive (ranges are checked by the compiler)."""
    if primitive == "bool":
        return isinstance(value, bool)
    if primitive in ("string", "wstring"):
        return isinstance(value, str)
    if primitive in ("float32", "float64"):
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    return isinstance(value, int) and not isinstance(value, bool)


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


def line_of(text: str, problem: str) -> int:
    """The line of the member a problem names (``Struct.member: …``), 0 when it cannot be found."""
    where = problem.partition(":")[0]
    struct, _, member = where.partition(".")
    start = re.search(rf"\b(?:struct|module)\s+{re.escape(struct)}(?:_Constants)?\b", text)
    if start is None:
        return 0
    found = re.compile(rf"\b{re.escape(member)}\s*(?:\[[^\]]*\]\s*)*[;=]").search(text, start.end())
    return text.count("\n", 0, (found or start).start()) + 1


def ros_files_from_idl(types: dict[str, Any], package: str, text: str = "") -> tuple[list[RosFile], list[str]]:
    """One interface per message struct, service or action, with the defaults ``text`` states; problems name
    the struct and the member (``Struct.member: …``, see ``line_of``)."""
    files: list[RosFile] = []
    problems: list[str] = []
    values = defaults(text) if text else {}
    for kind, name, fulls in structs_of(types):
        parts = [_part(full, types[full][0], types[full][1], problems, values) for full in fulls]
        if all(p is not None for p in parts):
            rf = RosFile(kind, package, name)
            rf.parts.extend(p for p in parts if p is not None)
            files.append(rf)
    return files, problems
