"""Writing untrusted text into generated files: comments, string literals, YAML scalars, numbers.

Doc comments, units and string values come from the interface file and may hold
anything: line breaks (including U+2028 and friends), ``*/``, ``-->``, quotes,
backslashes, control characters. These helpers are shared by every target so
that such text stays inside the comment or literal it is written into, the same
way everywhere. Language-specific escaping (IDL strings, Markdown) builds on
``quote`` and ``CONTROL`` in its own target.
"""

from __future__ import annotations

import decimal
import math
import re
from collections.abc import Callable, Mapping

#: Control characters that are not line breaks for ``str.splitlines`` (plus U+0085), and DEL.
CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f\x85]")
_SPACES = re.compile(r"\s+")


def _trimmed(lines: list[str]) -> list[str]:
    """``lines`` without the blank lines at either end."""
    start, end = 0, len(lines)
    while start < end and not lines[start]:
        start += 1
    while end > start and not lines[end - 1]:
        end -= 1
    return lines[start:end]


def doc_lines(text: str | None) -> list[str]:
    """A doc comment as lines, right-stripped, without blank lines at either end.

    Every line break (including U+2028 and friends) splits, so a line never holds one;
    enough for comment syntaxes that end at the line break (``#`` in .msg files).
    """
    if not text:
        return []
    return _trimmed([line.rstrip() for line in text.splitlines()])


def _comment_safe(line: str) -> str:
    line = CONTROL.sub(" ", line.replace("\t", " ")).rstrip()
    while line.endswith("\\"):
        line = line[:-1].rstrip()
    return line


def comment_lines(text: str | None) -> list[str]:
    """``text`` as lines that are safe after a C-family line comment marker (``//``, ``#``).

    As ``doc_lines``, and control characters become spaces and trailing backslashes
    are removed: in C, C++ and IDL a backslash at the end of a line would continue
    the comment onto the next line of code.
    """
    if not text:
        return []
    return _trimmed([_comment_safe(line) for line in text.splitlines()])


def one_line(text: str | None) -> str:
    """``text`` collapsed to one comment-safe line."""
    return _SPACES.sub(" ", " ".join(comment_lines(text))).strip()


def summary(text: str | None) -> str:
    """The first sentence (or first paragraph) of a doc comment, on one line."""
    lines = comment_lines(text)
    if not lines:
        return ""
    first = one_line("\n".join(lines[: lines.index("")] if "" in lines else lines))
    m = re.match(r"(.+?[.!?])(\s|$)", first)
    return m.group(1) if m else first


def line_comment(line: str, marker: str = "#") -> str:
    """One comment line: ``# text``, or the bare marker for an empty line (no trailing space)."""
    return f"{marker} {line}" if line else marker


def header_name(path: str) -> str:
    """The file name shown in a generated header: safe in ``#``, ``//`` and ``<!-- -->`` comments.

    Only the last path component is kept (output must not depend on where the input
    lives); unprintable characters, quotes, ``<>&`` and ``--`` are replaced by ``_``.
    """
    name = path.replace("\\", "/").rpartition("/")[2]
    safe = "".join(c if c.isprintable() and c not in "\"'<>&" else "_" for c in name).replace("--", "__")
    return safe or "interface"


def _printable(c: str) -> bool:
    return c == " " or c.isprintable()


def quote(text: str, escapes: Mapping[str, str], escape: Callable[[str], str], *,
          keep: Callable[[str], bool] = _printable) -> str:
    """``text`` in double quotes: characters in ``escapes`` replaced by their escape, the ones
    ``keep`` accepts written as they are, every other one written as ``escape(c)``."""
    out = ['"']
    for c in text:
        if c in escapes:
            out.append(escapes[c])
        elif keep(c):
            out.append(c)
        else:
            out.append(escape(c))
    out.append('"')
    return "".join(out)


_CPP_ESCAPES = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "?": "\\?"}  # "\?": no trigraphs


def cpp_string(text: str) -> str:
    """A C++ string literal holding exactly ``text`` (control characters as octal escapes)."""
    return quote(text, _CPP_ESCAPES, lambda c: f"\\{ord(c):03o}", keep=lambda c: " " <= c != "\x7f")


_YAML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t"}


def _yaml_escape(c: str) -> str:
    code = ord(c)
    return f"\\u{code:04x}" if code <= 0xFFFF else f"\\U{code:08x}"


def yaml_string(text: str) -> str:
    """A double-quoted YAML scalar on one line that YAML 1.1 and 1.2 readers load back exactly."""
    return quote(text, _YAML_ESCAPES, _yaml_escape)


def number(value: float | int) -> str:
    """A number as YAML and C read it: integers as they are, floats in positional notation.

    Exponent forms like ``1e-05`` are avoided: YAML 1.1 reads them as strings.
    """
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int):
        return str(value)
    if not math.isfinite(value):
        raise ValueError(f"{value} is not a finite number")
    text = format(decimal.Decimal(repr(value)), "f")
    if "." not in text:
        text += ".0"
    return text


def compact_number(value: float) -> str:
    """``number``, but a whole number without its ``.0`` (ranges: ``0 3``, ``0.5 2.5``)."""
    return str(int(value)) if float(value).is_integer() else number(value)
