"""A line parser for ROS 2 ``.msg``, ``.srv`` and ``.action`` files that reads them as rosidl does.

It follows ``rosidl_adapter.parser`` rule for rule: tabs are spaces; a ``#``
starts a comment anywhere on a line (even inside a quoted value); the leading
``#`` lines of a body are its own comment; comment lines before an element and
a comment after it on its line belong to that element, an indented comment
line to the element before; ``TYPE NAME=VALUE`` is a constant, ``TYPE NAME
[DEFAULT]`` a field; ``---`` alone on a line separates the parts of a service
(two) or an action (three). Values are decoded as rosidl decodes them (both
quote styles, ``\\'`` and ``\\"`` inside, ``true/false/1/0`` for bool, integers
in any Python base). Unlike rosidl it reports every malformed line of a file,
each with its line number, instead of stopping at the first.
"""

from __future__ import annotations

import re
import textwrap
from dataclasses import dataclass, field
from typing import Literal

PRIMITIVE_TYPES = ("bool", "byte", "char", "float32", "float64", "int8", "uint8", "int16", "uint16",
                   "int32", "uint32", "int64", "uint64", "string", "wstring")
#: ROS 1 types rosidl still accepts in .msg files, which ROS 2 code generators refuse.
ROS1_TYPES = ("duration", "time")

_PACKAGE = re.compile(r"^(?!.*__)(?!.*_$)[a-z][a-z0-9_]*$")
_FIELD = _PACKAGE
_MESSAGE = re.compile(r"^[A-Z][A-Za-z0-9]*$")
_CONSTANT = re.compile(r"^[A-Z]([A-Z0-9_]?[A-Z0-9]+)*$")
_SUFFIXES = ("_Request", "_Response", "_Goal", "_Result", "_Feedback")

Kind = Literal["msg", "srv", "action"]
ArrayKind = Literal["fixed", "bounded", "unbounded"]
Scalar = bool | int | float | str
PARTS: dict[str, tuple[str, ...]] = {"msg": ("",), "srv": ("_Request", "_Response"),
                                     "action": ("_Goal", "_Result", "_Feedback")}


class RosSyntaxError(ValueError):
    """A line rosidl would refuse."""


@dataclass(frozen=True, slots=True)
class RosType:
    """A field or constant type: a primitive (maybe a bounded string) or a message, maybe an array."""

    name: str
    package: str | None = None
    primitive: bool = True
    string_bound: int | None = None
    array: ArrayKind | None = None
    size: int | None = None

    def text(self) -> str:
        """The type as a .msg file writes it."""
        core = self.name if self.package is None else f"{self.package}/{self.name}"
        if self.string_bound is not None:
            core += f"<={self.string_bound}"
        if self.array == "fixed":
            return f"{core}[{self.size}]"
        if self.array == "bounded":
            return f"{core}[<={self.size}]"
        return core + ("[]" if self.array == "unbounded" else "")


@dataclass(slots=True)
class Element:
    """A field or a constant; ``value`` is the decoded default or constant value, ``texts`` its spelling."""

    kind: Literal["field", "constant"]
    type: RosType
    name: str
    line: int
    value: Scalar | list[Scalar] | None = None
    texts: list[str] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)
    #: the comment on the element's own line (also the last of ``comments``), if any
    inline: str | None = None


@dataclass(slots=True)
class Part:
    """One body: a message, a request, a response, a goal, a result or a feedback."""

    name: str
    line: int
    comments: list[str] = field(default_factory=list)
    elements: list[Element] = field(default_factory=list)


@dataclass(slots=True)
class RosFile:
    """One interface file: its parts and the malformed lines found in it."""

    kind: Kind
    package: str
    name: str
    parts: list[Part] = field(default_factory=list)
    problems: list[tuple[int, str]] = field(default_factory=list)


# ---------------------------------------------------------------------------
# Names


def is_package_name(name: str) -> bool:
    """A valid ROS 2 package name."""
    return bool(_PACKAGE.match(name))


def is_message_name(name: str) -> bool:
    """A valid message name as rosidl checks it (``Sample_`` and part suffixes allowed)."""
    if name.startswith("Sample_"):
        name = name[len("Sample_"):]
    for suffix in _SUFFIXES:
        if name.endswith(suffix):
            name = name[:-len(suffix)]
    return bool(_MESSAGE.match(name))


# ---------------------------------------------------------------------------
# Types


def parse_type(text: str) -> RosType:
    """A type string: ``int32``, ``string<=5``, ``pkg/Msg``, ``Msg``, each optionally ``[]``, ``[N]``, ``[<=N]``."""
    array: ArrayKind | None = None
    size = None
    if text.endswith("]"):
        index = text.rfind("[")
        if index < 0:
            raise RosSyntaxError(f"the type '{text}' ends with ']' but has no '['")
        inner = text[index + 1:-1]
        array = "unbounded"
        if inner:
            array = "bounded" if inner.startswith("<=") else "fixed"
            number = inner[2:] if array == "bounded" else inner
            size = _positive(number, f"the size of the array type '{text}' must be an integer > 0, "
                                     "optionally prefixed with '<='")
        text = text[:index]
    if text in PRIMITIVE_TYPES:
        return RosType(text, array=array, size=size)
    if text in ROS1_TYPES:
        raise RosSyntaxError(f"'{text}' is a ROS 1 type that ROS 2 does not generate: use "
                             f"builtin_interfaces/{text.capitalize()}")
    for base in ("string", "wstring"):
        if text.startswith(base + "<="):
            bound = _positive(text[len(base) + 2:], f"the bound of the string type '{text}' must be an integer > 0")
            return RosType(base, string_bound=bound, array=array, size=size)
    parts = text.split("/")
    if len(parts) > 2 or not all(parts):
        raise RosSyntaxError(f"'{text}' is not a type: write TYPE, PACKAGE/TYPE or a primitive type")
    package = parts[0] if len(parts) == 2 else None
    name = parts[-1]
    if package is not None and not is_package_name(package):
        raise RosSyntaxError(f"'{package}' is not a valid package name (lower-case letters, digits, single "
                             "underscores)")
    if not is_message_name(name):
        raise RosSyntaxError(f"'{name}' is not a valid message name (CamelCase letters and digits) and not a "
                             "primitive type")
    return RosType(name, package, primitive=False, array=array, size=size)


def _positive(text: str, message: str) -> int:
    try:
        number = int(text)
    except ValueError:
        raise RosSyntaxError(message) from None
    if number <= 0:
        raise RosSyntaxError(message)
    return number


# ---------------------------------------------------------------------------
# Values


def _int_range(name: str) -> tuple[int, int]:
    if name in ("byte", "char"):
        return 0, 255
    unsigned = name.startswith("u")
    bits = int(name[4 if unsigned else 3:])
    return (0, 2**bits - 1) if unsigned else (-(2 ** (bits - 1)), 2 ** (bits - 1) - 1)


def parse_primitive(t: RosType, text: str) -> Scalar:
    """One value of a non-array primitive type, decoded as rosidl decodes it."""
    name = t.name
    if name == "bool":
        if text.lower() not in ("true", "1", "false", "0"):
            raise RosSyntaxError(f"value '{text}' is not a bool: write true, false, 1 or 0")
        return text.lower() in ("true", "1")
    if name in ("float32", "float64"):
        try:
            return float(text)
        except ValueError:
            raise RosSyntaxError(f"value '{text}' is not a {name}: write a number with '.' as the separator") from None
    if name in ("string", "wstring"):
        for q in ('"', "'"):
            if text.startswith(q) and text.endswith(q):
                text = text[1:-1]
                if re.search(r"(?<!\\)%s" % q, text):
                    raise RosSyntaxError(f"the string {q}{text}{q} has an unescaped {q} inside")
                text = text.replace("\\" + q, q)
                break
        if t.string_bound is not None and len(text) > t.string_bound:
            raise RosSyntaxError(f"the string '{text}' is longer than its bound {t.string_bound}")
        return text
    lo, hi = _int_range(name)
    try:
        value = int(text)
    except ValueError:
        try:
            value = int(text, 0)
        except ValueError:
            raise RosSyntaxError(f"value '{text}' is not an integer ({name}: {lo}..{hi})") from None
    if not lo <= value <= hi:
        raise RosSyntaxError(f"value {text} does not fit in {name} ({lo}..{hi})")
    return value


def parse_value(t: RosType, text: str) -> tuple[Scalar | list[Scalar], list[str]]:
    """A default or constant value and the spelling of each element."""
    if not t.primitive:
        raise RosSyntaxError(f"a field of the message type '{t.text()}' cannot have a default value")
    if t.array is None:
        return parse_primitive(t, text), [text]
    if not (text.startswith("[") and text.endswith("]")):
        raise RosSyntaxError(f"the default of the array '{t.text()}' must be written [a, b, …]")
    inner = text[1:-1]
    if t.name in ("string", "wstring"):
        items = _string_array_items(inner)
    else:
        items = inner.split(",") if inner else []
    if t.size is not None:
        if t.array == "fixed" and len(items) != t.size:
            raise RosSyntaxError(f"the array '{t.text()}' needs exactly {t.size} values, not {len(items)}")
        if t.array == "bounded" and len(items) > t.size:
            raise RosSyntaxError(f"the array '{t.text()}' holds at most {t.size} values, not {len(items)}")
    element = RosType(t.name, string_bound=t.string_bound)
    values: list[Scalar] = []
    texts: list[str] = []
    for i, item in enumerate(items):
        item = item.strip()
        try:
            values.append(parse_primitive(element, item))
        except RosSyntaxError as e:
            raise RosSyntaxError(f"element {i} of the array: {e}") from None
        texts.append(item)
    return values, texts


def _string_array_items(text: str) -> list[str]:
    """rosidl's split of a string array's elements: quoted ones may hold commas."""
    out: list[str] = []
    while text:
        text = text.lstrip(" ")
        if not text:
            break
        if text[0] == ",":
            raise RosSyntaxError(f"unexpected ',' at the start of [{text}]")
        quoted = False
        for q in ('"', "'"):
            if text.startswith(q):
                quoted = True
                end = _matching_quote(text, q)
                if end == -1:
                    raise RosSyntaxError(f"the string [{text}] is not closed")
                out.append(text[1:end + 1].replace("\\" + q, q))
                text = text[end + 2:]
        if not quoted:
            comma = text.find(",")
            if comma == -1:
                out.append(text)
                text = ""
            else:
                out.append(text[:comma])
                text = text[comma:]
        text = text.lstrip(" ")
        if text and text[0] == ",":
            text = text[1:]
    return out


def _matching_quote(text: str, quote: str) -> int:
    """rosidl's ``find_matching_end_quote``, kept exactly (offsets included)."""
    end = -1
    final = 0
    while text:
        end = text[1:].find(quote)
        if end == -1:
            return -1
        if text[end:end + 2] != "\\" + quote:
            return final + end
        text = text[end + 2:]
        final = end + 2
    return -1


# ---------------------------------------------------------------------------
# Files


def parse_file(kind: Kind, package: str, name: str, text: str) -> RosFile:
    """A whole ``.msg`` (kind ``msg``), ``.srv`` or ``.action`` file."""
    out = RosFile(kind, package, name)
    if not is_message_name(name):
        out.problems.append((0, f"'{name}' is not a valid interface name (CamelCase letters and digits)"))
    lines = text.splitlines()
    separators = [i for i, line in enumerate(lines) if line == "---"]
    wanted = len(PARTS[kind]) - 1
    if len(separators) != wanted:
        where = separators[wanted] + 1 if len(separators) > wanted else 0
        what = {0: "a message has no '---' line", 1: "a service needs one '---' line between request and response",
                2: "an action needs two '---' lines: goal, result, feedback"}[wanted]
        out.problems.append((where, f"{what}; found {len(separators)}"))
        return out
    bounds = [-1, *separators, len(lines)]
    for suffix, start, end in zip(PARTS[kind], bounds, bounds[1:]):
        part = Part(name + suffix, start + 2)
        _parse_body(lines[start + 1:end], start + 2, part, out.problems)
        out.parts.append(part)
    return out


def _parse_body(lines: list[str], first: int, part: Part, problems: list[tuple[int, str]]) -> None:
    """One body, as ``parse_message_string``; ``first`` is the file line number of ``lines[0]``."""
    lines = [line.replace("\t", " ") for line in lines]
    index = next((i for i, v in enumerate(lines) if not v.startswith("#")), len(lines))
    part.comments = [line.lstrip("#") for line in lines[:index]]
    last: Element | None = None
    pending: list[str] = []
    fields: dict[str, int] = {}
    consts: dict[str, int] = {}
    for offset, raw in enumerate(lines[index:]):
        number = first + index + offset
        line = raw.rstrip()
        if not line:
            continue
        comment = inline = None
        hash_at = line.find("#")
        if hash_at >= 0:
            comment = line[hash_at:].lstrip("#")
            line = line[:hash_at]
        if comment is not None:
            if line and not line.strip():
                if last is not None:
                    last.comments.append(comment)
                continue
            pending.append(comment)
            line = line.rstrip()
            if not line:
                continue
            inline = comment
        try:
            element = _element(line, number)
        except RosSyntaxError as e:
            problems.append((number, str(e)))
            pending = []
            continue
        seen = fields if element.kind == "field" else consts
        if element.name in seen:
            problems.append((number, f"'{element.name}' is already a {element.kind} of {part.name} "
                                     f"(line {seen[element.name]})"))
            pending = []
            continue
        seen[element.name] = number
        element.comments = pending
        element.inline = inline
        pending = []
        part.elements.append(element)
        last = element


def _element(line: str, number: int) -> Element:
    type_text, _, rest = line.partition(" ")
    rest = rest.lstrip()
    if not type_text:
        raise RosSyntaxError("a field or constant must start at the beginning of the line")
    if not rest:
        raise RosSyntaxError(f"'{line}' has a type but no name")
    if "=" not in rest:
        name, _, default = rest.partition(" ")
        default = default.lstrip()
        t = parse_type(type_text)
        if not _FIELD.match(name):
            raise RosSyntaxError(f"'{name}' is not a valid field name (lower-case letters, digits, single "
                                 "underscores, starting with a letter)")
        element = Element("field", t, name, number)
        if default:
            element.value, element.texts = parse_value(t, default)
        return element
    name, _, value = rest.partition("=")
    name = name.rstrip()
    value = value.lstrip()
    if type_text not in PRIMITIVE_TYPES:
        raise RosSyntaxError(f"the constant type '{type_text}' must be a primitive type (no arrays or bounds)")
    if not _CONSTANT.match(name):
        raise RosSyntaxError(f"'{name}' is not a valid constant name (UPPER_CASE letters, digits, single "
                             "underscores)")
    t = RosType(type_text)
    element = Element("constant", t, name, number)
    element.value, element.texts = parse_value(t, value)
    return element


_BOX_EDGE = re.compile(r"\s#+$")


def _unbox(line: str) -> str:
    """A line of a ``#`` box without its right edge; a centred title without its padding."""
    inner = re.sub(r"\s*#+$", "", line)
    return " " + inner.strip() if len(inner) - len(inner.lstrip()) > 4 else inner  # "# text", as the others


def clean_comments(lines: list[str]) -> str | None:
    """Comment lines as one doc text, the way rosidl condenses them (no unit extraction).

    A box drawn with ``#`` (``#   Title   #``, ``#####``) loses its frame: the closing ``#``
    of each line and the padding that centres a title, so the doc reads as written text.
    """
    lines = [line.rstrip() for line in lines]
    if any(_BOX_EDGE.search(line) for line in lines):
        lines = [_unbox(line) for line in lines]
    while lines and not lines[0]:
        lines.pop(0)
    while lines and not lines[-1]:
        lines.pop()
    out: list[str] = []
    for line in lines:
        if line or (out and out[-1]):
            out.append(line)
    if not out:
        return None
    return textwrap.dedent("\n".join(out))
