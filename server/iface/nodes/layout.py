"""Generated lines a person reads: a call or literal too long for its line laid out over several, text wrapped.

Both node targets write expressions whose length grows with the interface (a member's QoS, a parameter's
description, a handler's types). ``fit`` lays such an expression out, as a formatter would: on one line
when it fits, otherwise each bracket's items one per line (recursively, the closing bracket on a line of
its own), and a string literal too long even so cut into adjacent literals (which Python, inside
brackets, and C++ join). Python and C++ expressions share the syntax it reads: ``()[]{}`` brackets,
comma-separated items, quoted strings with backslash escapes. ``wrap`` wraps prose (comments, docstrings).
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass, field

#: The longest line the generated code has (the issue's rule); the user's files: ``USER_WIDTH``.
WIDTH = 200
USER_WIDTH = 100
_OPEN = {"(": ")", "[": "]", "{": "}"}
_CLOSE = frozenset(_OPEN.values())


@dataclass
class _Group:
    """``head`` (the text up to and with the opening bracket), the items, the closing bracket and what follows."""

    head: str
    items: list[list[str | _Group]] = field(default_factory=list)
    close: str = ""


def _tokens(text: str) -> list[str]:
    """Strings (quotes and escapes kept), brackets, commas and runs of anything else."""
    out: list[str] = []
    i = 0
    while i < len(text):
        ch = text[i]
        if ch in "'\"":
            j = i + 1
            while j < len(text) and text[j] != ch:
                j += 2 if text[j] == "\\" else 1
            out.append(text[i:j + 1])
            i = j + 1
        elif ch in _OPEN or ch in _CLOSE or ch == ",":
            out.append(ch)
            i += 1
        else:
            j = i
            while j < len(text) and text[j] not in "'\"," and text[j] not in _OPEN and text[j] not in _CLOSE:
                j += 1
            out.append(text[i:j])
            i = j
    return out


def _parse(tokens: list[str]) -> list[str | _Group]:
    """The tokens as a sequence of text and bracket groups (each group's items split at its commas)."""
    root: list[str | _Group] = []
    stack: list[tuple[_Group, list[str | _Group]]] = []
    current = root
    for tok in tokens:
        if tok in _OPEN:
            head = ""
            while current and isinstance(current[-1], str) and not current[-1].endswith((",", " ")):
                head = str(current.pop()) + head  # the name or operator right before the bracket
            group = _Group(head + tok)
            current.append(group)
            stack.append((group, current))
            group.items.append([])
            current = group.items[-1]
        elif tok in _CLOSE and stack:
            group, current = stack.pop()
            group.close = tok
            if group.items == [[]]:
                group.items = []
        elif tok == "," and stack:
            group = stack[-1][0]
            group.items.append([])
            current = group.items[-1]
        else:
            current.append(tok.lstrip(" ") if tok.startswith(" ") and stack and not current else tok)
    return root


def _flat(parts: list[str | _Group]) -> str:
    out = []
    for part in parts:
        if isinstance(part, _Group):
            out.append(part.head + ", ".join(_flat(item) for item in part.items) + part.close)
        else:
            out.append(part)
    return "".join(out)


def _cut(literal: str, first: int, room: int) -> list[str]:
    """A quoted string as adjacent literals, the first of at most ``first`` characters and the others of at most
    ``room``, cut after spaces (never between a backslash and what it escapes)."""
    quote, body = literal[0], literal[1:-1]
    pieces: list[str] = []
    limit = first
    while len(body) + 2 > limit:
        at = body.rfind(" ", 0, max(limit - 2, 1))
        if at <= 0 or body[:at + 1].endswith("\\"):
            if pieces or limit == room:
                break
            pieces.append("")  # no room left on the first line: the literal starts on the next one
            limit = room
            continue
        pieces.append(body[:at + 1])
        body = body[at + 1:]
        limit = room
    pieces.append(body)
    return [f"{quote}{p}{quote}" for p in pieces if p] if pieces[0] else \
        ["", *(f"{quote}{p}{quote}" for p in pieces[1:])]


def _lay(parts: list[str | _Group], indent: int, width: int, step: int) -> list[str]:
    """Lines for ``parts`` starting at column ``indent`` (the first line unindented, the others indented)."""
    flat = _flat(parts)
    if indent + len(flat) <= width:
        return [flat]
    lines = [""]
    for part in parts:
        if isinstance(part, _Group) and part.items:
            lines[-1] += part.head
            for n, item in enumerate(part.items):
                sub = _lay(item, indent + step, width, step)
                sub[-1] += "," if n < len(part.items) - 1 else ""
                lines.append(" " * (indent + step) + sub[0])
                lines.extend(sub[1:])
            lines.append(" " * indent + part.close)
        elif isinstance(part, str) and len(part) > 2 and part[0] in "'\"" and part[-1] == part[0] \
                and indent + len(lines[-1]) + len(part) > width:
            column = len(lines[-1]) + (indent if len(lines) == 1 else 0)
            pieces = _cut(part, width - column, width - indent - step)
            lines[-1] += pieces[0]
            lines.extend(" " * (indent + step) + p for p in pieces[1:])
        else:
            lines[-1] += _flat([part])
    return lines


def fit(line: str, indent: int, width: int = WIDTH, step: int = 4) -> str:
    """``line`` (an expression or statement at column ``indent``, without its indentation) laid out to fit.

    The result's first line has no indentation (the template's), the following ones have their own.
    """
    if indent + len(line) <= width:
        return line
    return "\n".join(_lay(_parse(_tokens(line)), indent, width, step))


def wrap(text: str, indent: int, prefix: str = "", width: int = WIDTH) -> list[str]:
    """``text`` as lines of at most ``width`` characters at column ``indent``, each starting with ``prefix``.

    A text that fits is one line, as it is.
    """
    if indent + len(prefix) + len(text) <= width:
        return [prefix + text]
    room = max(20, width - indent - len(prefix))
    return [prefix + line for line in textwrap.wrap(text, room, break_long_words=False, break_on_hyphens=False)]


def comment(text: str, indent: int, prefix: str, width: int = WIDTH) -> str:
    """A comment (``//! text``) wrapped to ``width`` at column ``indent``: its lines, the first unindented."""
    return ("\n" + " " * indent).join(wrap(text, indent, prefix, width))


__all__ = ["USER_WIDTH", "WIDTH", "comment", "fit", "wrap"]
