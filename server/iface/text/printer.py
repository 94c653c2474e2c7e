"""Model → ``.iface`` text: what importers write and what a JSON form reads back into.

The text parses back to an equal model (see ``forms.jsonform.canonical``): docs become
``/** */`` comments (a ``*/`` inside one is written ``*\\/``), strings are
escaped, numbers keep their spelling, bodies keep their form (flat, explicit or
functions) and members are written in source order.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from ..model import nodes as m

INDENT = "    "

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*\Z")
_INT = re.compile(r"[+-]?(0x[0-9A-Fa-f]+|[0-9]+)\Z")
_DOUBLE = re.compile(r"[+-]?([0-9]+\.[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\Z|[+-]?[0-9]+[eE][+-]?[0-9]+\Z")
_ESCAPES = {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\r": "\\r", "\t": "\\t", "\0": "\\0"}


#: Words the parser does not take as a name right after a ``,`` (a parser limitation): a list whose
#: next element starts with one of them is separated by a space instead.
_KEYWORDS = frozenset({
    "include", "cpp_include", "namespace", "component", "external", "publishes", "subscribes", "provides",
    "calls", "on", "version", "const", "typedef", "enum", "senum", "struct", "union", "exception", "message",
    "configuration", "state", "service", "action", "extends", "oneway", "void", "throws", "required",
    "optional", "map", "set", "list", "cpp_type", "xsd_all", *m.BASE_ALIASES,
})


def join(parts: list[str]) -> str:
    """Elements of a list separated by ", ", or by " " before one that starts with a keyword."""
    out = parts[:1]
    for part in parts[1:]:
        first = re.match(r"[A-Za-z_][A-Za-z0-9_]*", part)
        out.append((" " if first and first.group() in _KEYWORDS else ", ") + part)
    return "".join(out)


class PrintError(ValueError):
    """A model value that the language cannot spell (e.g. an infinite float)."""


# ---------------------------------------------------------------------------
# Pieces


def quote(text: str) -> str:
    """A double-quoted literal whose decoded value is ``text``."""
    out = []
    for c in text:
        esc = _ESCAPES.get(c)
        if esc is not None:
            out.append(esc)
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append(f"\\u{ord(c):04x}")
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _literal_ok(text: str, value: str) -> bool:
    from ..syntax.transform import decode_literal

    if len(text) < 2 or text[0] not in "\"'" or text[-1] != text[0] or "\n" in text:
        return False
    body = text[1:-1]
    i = 0
    while i < len(body):  # an unescaped closing quote inside would end the literal early
        if body[i] == "\\":
            i += 2
            continue
        if body[i] == text[0]:
            return False
        i += 1
    return decode_literal(text) == value


def value_text(v: m.Value) -> str:
    """A value as the language writes it, keeping the original spelling when it still fits."""
    kind = v.kind
    if kind == "int":
        if v.text and _INT.match(v.text) and _int_of(v.text) in (v.value, None if _beyond(v.value) else v.value):
            # an integer beyond 64 bits keeps its spelling: it is refused again, as written
            return v.text
        return str(v.value)
    if kind == "double":
        if v.text and (_DOUBLE.match(v.text) or _INT.match(v.text)):
            return v.text
        number = float(v.value)
        if number != number or number in (float("inf"), float("-inf")):
            raise PrintError(f"{number} cannot be written as an iface number")
        text = repr(number)
        return text if _DOUBLE.match(text) else f"{text}.0"
    if kind == "string":
        value = str(v.value)
        return v.text if v.text and _literal_ok(v.text, value) else quote(value)
    if kind == "name":
        return str(v.value)
    if kind == "list":
        return "[" + ", ".join(value_text(x) for x in v.value) + "]"
    return "{" + ", ".join(f"{value_text(k)}: {value_text(x)}" for k, x in v.value) + "}"


def _beyond(value: int) -> bool:
    lo, hi = m.INT_LITERAL
    return not lo <= value <= hi


def _int_of(text: str) -> int | None:
    from ..syntax.transform import parse_int

    return parse_int(text)


def annotations_text(annotations: Iterable[m.Annotation]) -> str:
    """``(k = v, flag)`` or '' when there are none."""
    parts = [a.key if a.value is None else f"{a.key} = {value_text(a.value)}" for a in annotations]
    return f"({join(parts)})" if parts else ""


def _with_annotations(text: str, annotations: Iterable[m.Annotation]) -> str:
    ann = annotations_text(annotations)
    return f"{text} {ann}" if ann else text


def type_text(t: m.TypeRef) -> str:
    """A type with its annotations and array suffixes."""
    if isinstance(t, m.ArrayType) and not t.spelled_list:
        inner = type_text(t.element)
        if t.array == "fixed":
            return f"{inner}[{t.size}]"
        if t.array == "bounded":
            return f"{inner}[<={t.size}]"
        return f"{inner}[]"
    if isinstance(t, m.BaseType):
        core = t.spelling or t.name
        if t.bound is not None:
            core = f"{core}<={t.bound}"
    elif isinstance(t, m.NamedType):
        core = t.name
    elif isinstance(t, m.MapType):
        core = f"map<{type_text(t.key)}, {type_text(t.element)}>"
    elif isinstance(t, m.SetType):
        core = f"set<{type_text(t.element)}>"
    else:
        core = f"list<{type_text(t.element)}>"
    return _with_annotations(core, t.annotations)


def doc_lines(doc: str | None, indent: str = "") -> list[str]:
    """A doc comment; ``*/`` inside it is written ``*\\/`` so the comment stays closed."""
    if doc is None:
        return []
    lines = [line.rstrip().replace("*/", "*\\/") for line in doc.split("\n")]
    while lines and not lines[0]:
        lines.pop(0)
    while lines and not lines[-1]:
        lines.pop()
    if not lines:
        return [f"{indent}/** */"]
    one = lines[0]
    if len(lines) == 1 and one == one.lstrip() and not one.startswith("*") and not one.endswith("*"):
        return [f"{indent}/** {one} */"]
    return [f"{indent}/**", *(f"{indent} * {line}".rstrip() for line in lines), f"{indent} */"]


def name_or_literal(name: str) -> str:
    """A name as it is when it is an identifier, else quoted."""
    return name if _IDENTIFIER.match(name) else quote(name)


# ---------------------------------------------------------------------------
# Members


def field_text(f: m.Field, *, annotations: bool = True) -> str:
    """One field on one line, without its doc."""
    parts = []
    if f.id is not None:
        parts.append(f"{f.id}:")
    if f.requiredness:
        parts.append(f.requiredness)
    parts.append(type_text(f.type) + ("&" if f.reference else ""))
    parts.append(f.name)
    text = " ".join(parts)
    if f.default is not None:
        text += f" = {value_text(f.default)}"
    return _with_annotations(text, f.annotations) if annotations else text


def const_text(c: m.Const) -> str:
    """``const T NAME = value``."""
    return f"const {type_text(c.type)} {c.name} = {value_text(c.value)}"


def _members(fields: list[m.Field], consts: list[m.Const], indent: str,
             annotations: bool = True) -> list[str]:
    members: list[m.Field | m.Const] = [*consts, *fields]
    members.sort(key=lambda x: x.span.start)
    out: list[str] = []
    for x in members:
        out.extend(doc_lines(x.doc, indent))
        if isinstance(x, m.Const):
            out.append(indent + const_text(x))
        else:
            out.append(indent + field_text(x, annotations=annotations))
    return out


def _body(head: str, lines: list[str], tail_annotations: Iterable[m.Annotation], indent: str) -> list[str]:
    ann = annotations_text(tail_annotations)
    close = "}" + (f" {ann}" if ann else "")
    if not lines:
        return [f"{indent}{head} {{{close}"]
    return [f"{indent}{head} {{", *lines, indent + close]


def _sections(sections: list[m.Section], indent: str) -> list[str]:
    out: list[str] = []
    for sec in sections:
        out.extend(doc_lines(sec.doc, indent))
        out.extend(_body(sec.name, _members(sec.fields, sec.consts, indent + INDENT), [], indent))
    return out


def _arguments(fields: list[m.Field], indent: str) -> list[str]:
    """An argument list: on one line, or one argument a line when some have docs."""
    if not any(f.doc is not None for f in fields):
        return [join([field_text(f) for f in fields])]
    lines = [""]
    for f in fields:
        lines.extend(doc_lines(f.doc, indent + INDENT))
        lines.append(f"{indent}{INDENT}{field_text(f)}")
    lines.append(indent)
    return lines


def _function(fn: m.Function, indent: str) -> list[str]:
    head = ("oneway " if fn.oneway else "") + ("void" if fn.returns is None else type_text(fn.returns))
    lines = _arguments(fn.params, indent)
    lines[0] = f"{indent}{head} {fn.name}({lines[0]}"
    if fn.throws:
        throws = _arguments(fn.throws, indent)
        lines[-1] += f") throws ({throws[0]}"
        lines.extend(throws[1:])
    lines[-1] += ")"
    lines[-1] = _with_annotations(lines[-1], fn.annotations)
    return [*doc_lines(fn.doc, indent), *lines]


# ---------------------------------------------------------------------------
# Items


def definition_lines(d: m.Definition) -> list[str]:
    """The lines of one definition, its doc first."""
    out = doc_lines(d.doc)
    inner = INDENT
    if isinstance(d, m.Const):
        out.append(const_text(d))
    elif isinstance(d, m.Typedef):
        out.append(_with_annotations(f"typedef {type_text(d.type)} {d.name}", d.annotations))
    elif isinstance(d, m.Enum):
        lines: list[str] = []
        for v in d.values:
            lines.extend(doc_lines(v.doc, inner))
            text = f"{v.name} = {v.value}" if v.explicit else v.name
            lines.append(inner + _with_annotations(text, v.annotations))
        out.extend(_body(f"enum {d.name}", lines, d.annotations, ""))
    elif isinstance(d, m.Senum):
        lines = [f"{inner}{value_text(v)}," for v in d.values]
        out.extend(_body(f"senum {d.name}", lines, d.annotations, ""))
    elif isinstance(d, m.Struct):
        out.extend(_body(f"{d.kind} {d.name}", _members(d.fields, d.consts, inner), d.annotations, ""))
    elif isinstance(d, m.Service):
        head = f"service {d.name}" + (f" extends {d.extends.name}" if d.extends is not None else "")
        out.extend(_body(head, _service_body(d, inner), d.annotations, ""))
    else:
        out.extend(_body(f"action {d.name}", _action_body(d, inner), d.annotations, ""))
    return out


def _service_body(d: m.Service, indent: str) -> list[str]:
    lines = _members([], d.consts, indent)
    if d.form == "functions":
        for fn in d.functions:
            lines.extend(_function(fn, indent))
    elif d.form == "explicit":
        lines.extend(_sections(d.sections, indent))
    else:
        lines.extend(_members(d.flat_fields, [], indent, annotations=False))
    return lines


def _action_body(d: m.Action, indent: str) -> list[str]:
    lines = _members([], d.consts, indent)
    if d.form == "explicit":
        lines.extend(_sections(d.sections, indent))
    else:
        lines.extend(_members(d.flat_fields, [], indent, annotations=False))
    return lines


def item_lines(item: m.Item) -> list[str]:
    """The lines of any top-level item."""
    if isinstance(item, m.Include):
        return [f"{'cpp_include' if item.cpp else 'include'} {quote(item.path)}"]
    if isinstance(item, m.Namespace):
        return [_with_annotations(f"namespace {item.scope} {name_or_literal(item.name)}", item.annotations)]
    if isinstance(item, m.ComponentDecl):
        text = f"component {item.name}" + (f" version {quote(item.version)}" if item.version is not None else "")
        return [*doc_lines(item.doc), _with_annotations(text, item.annotations)]
    if isinstance(item, m.External):
        return [f"external {item.name}"]
    if isinstance(item, m.SystemDecl):
        text = f"system {item.name}" + (f" version {quote(item.version)}" if item.version is not None else "")
        return [*doc_lines(item.doc), _with_annotations(text, item.annotations)]
    if isinstance(item, m.Instance):
        return [*doc_lines(item.doc), _with_annotations(f"instance {item.name} : {item.component}", item.annotations)]
    if isinstance(item, m.Wiring):
        text = f"{item.direction} {item.type.name} on {quote(item.topic)}"
        return [*doc_lines(item.doc), _with_annotations(text, item.annotations)]
    return definition_lines(item)


_HEADERS = (m.Include, m.Namespace, m.ComponentDecl, m.External, m.SystemDecl)


def print_items(items: Iterable[m.Item], header: str | None = None) -> str:
    """Items in order: headers and wirings close together, a blank line around bodies."""
    out: list[str] = []
    if header:
        out.extend(f"// {line}".rstrip() for line in header.split("\n"))
        out.append("")
    prev: m.Item | None = None
    for item in items:
        lines = item_lines(item)
        if prev is not None:
            compact = (isinstance(item, _HEADERS) and isinstance(prev, _HEADERS)) or (
                isinstance(item, m.Wiring) and isinstance(prev, m.Wiring)) or (
                isinstance(item, m.Instance) and isinstance(prev, m.Instance) and not item.doc)
            if not compact:
                out.append("")
        out.extend(lines)
        prev = item
    from .formatter import format_text  # the printed file is laid out as `iface-lsp fmt` lays it out

    return format_text("\n".join(out) + "\n")
