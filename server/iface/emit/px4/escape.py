"""Writing untrusted text (doc comments, string values) into C-family, YAML and .msg files.

Doc comments and string values come from the interface file and may hold
anything: line breaks, ``*/``, quotes, backslashes. These helpers make sure
such text stays inside the comment or literal it is written into.
"""

from __future__ import annotations

import decimal
import math
import re

import yaml

_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f\x85]")
_SPACES = re.compile(r"\s+")


def comment_lines(text: str | None) -> list[str]:
    """``text`` as lines that are safe after a line comment marker (``//``, ``#``).

    Every line break (including U+2028 and friends) starts a new line, control
    characters become spaces, and trailing backslashes are removed: in C, C++
    and IDL a backslash at the end of a line would continue the comment onto
    the next line of code.
    """
    if not text:
        return []
    lines = []
    for line in text.splitlines():
        line = _CONTROL.sub(" ", line.replace("\t", " ")).rstrip()
        while line.endswith("\\"):
            line = line[:-1].rstrip()
        lines.append(line)
    while lines and not lines[-1]:
        lines.pop()
    while lines and not lines[0]:
        lines.pop(0)
    return lines


def one_line(text: str | None) -> str:
    """``text`` collapsed to one comment-safe line."""
    return _SPACES.sub(" ", " ".join(comment_lines(text))).strip()


def summary(text: str | None) -> str:
    """The first sentence (or first line) of a doc comment, on one line."""
    lines = comment_lines(text)
    if not lines:
        return ""
    first = one_line("\n".join(lines[: lines.index("")] if "" in lines else lines))
    m = re.match(r"(.+?[.!?])(\s|$)", first)
    return m.group(1) if m else first


def cpp_string(text: str) -> str:
    """A C++ string literal holding exactly ``text``."""
    out = ['"']
    for ch in text:
        code = ord(ch)
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif ch == "?":
            out.append("\\?")  # no trigraphs
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\{code:03o}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def yaml_str(text: str) -> str:
    """A YAML double-quoted scalar holding exactly ``text`` (one line, fully escaped)."""
    return yaml.safe_dump(text, default_style='"', width=1 << 30, allow_unicode=True).rstrip("\n")


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
