"""Where the cursor is, read from the text around it: what completion may offer there.

Completion must answer while the document is being typed, before (and
without) a compile; this reads only the top-level chunk that holds the cursor.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Literal

from ..syntax.chunks import TOP_KEYWORDS

Where = Literal["top", "type", "member", "member-name", "wiring-type", "wiring-on", "topic", "annotation-key",
                "annotation-value", "value", "dotted", "namespace-scope", "instance-component",
                "instance-annotation-key", "instance-annotation-value", "none"]

_TOP = re.compile(r"^(?:%s)\b" % "|".join(TOP_KEYWORDS), re.M)
_TOKEN = re.compile(r"""
    (?P<comment>//[^\n]*|\#[^\n]*|/\*.*?(?:\*/|\Z))
  | (?P<string>"(?:[^"\\\n]|\\.)*"?|'(?:[^'\\\n]|\\.)*'?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*\.?)
  | (?P<number>[+-]?[0-9][0-9A-Za-z_.]*)
  | (?P<newline>\n)
  | (?P<punct>[{}()<>\[\]=,;:&*])
  | (?P<space>[ \t\r\f]+)
  | (?P<other>.)
""", re.S | re.X)
_WORD_CHARS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.")
WINDOW = 20_000
BODY_KEYWORDS = frozenset({"struct", "union", "exception", "message", "configuration", "state", "service",
                           "action", "enum", "senum"})
DIRECTIONS = frozenset({"publishes", "subscribes", "provides", "calls"})


@dataclass(slots=True)
class Context:
    """What is being written at the cursor."""

    where: Where
    prefix: str
    prefix_start: int
    #: The kind of the enclosing body (``message``, ``service``, ``request``, ``enum``…), or None at top level.
    body: str | None = None
    #: The definition keyword of the enclosing top-level definition, if any.
    definition: str | None = None
    depth: int = 0
    #: For wiring contexts: the direction, and the type once written.
    direction: str | None = None
    wired_type: str | None = None
    #: The tokens of the current statement before the prefix.
    tokens: list[str] = field(default_factory=list)
    #: For a string being typed: where its opening quote is.
    string_start: int | None = None
    #: For a default value: the type written before the field name.
    value_type: str | None = None
    #: For an instance annotation's value: its key.
    key: str | None = None


def _chunk_start(text: str, offset: int) -> int:
    lo = max(0, offset - WINDOW)
    last = lo
    for mt in _TOP.finditer(text, lo, offset):
        last = mt.start()
    return last


def context_at(text: str, offset: int) -> Context:
    """The completion context at ``offset`` of ``text``."""
    offset = max(0, min(offset, len(text)))
    prefix_start = offset
    while prefix_start > 0 and text[prefix_start - 1] in _WORD_CHARS:
        prefix_start -= 1
    prefix = text[prefix_start:offset]
    start = _chunk_start(text, prefix_start)
    stack: list[str] = []  # body kinds
    parens = 0
    angles = 0
    statement: list[str] = []
    definition: str | None = None
    string_start: int | None = None
    for mt in _TOKEN.finditer(text, start, prefix_start):
        kind = mt.lastgroup
        tok = mt.group()
        string_start = None
        if kind in ("space", "comment"):
            continue
        if kind == "newline":
            if not stack and parens == 0:
                statement = []
            elif stack and parens == 0 and angles == 0 and statement and statement[-1] not in ("=",):
                statement = []
            continue
        if kind == "string":
            if len(tok) == 1 or tok[-1] != tok[0] or (len(tok) > 1 and tok.endswith("\\" + tok[0])):
                string_start = mt.start()
            statement.append('"')
            continue
        if tok == "{":
            body = _body_kind([t for t in statement if t != '"'], stack)
            if not stack:
                definition = body
            stack.append(body)
            statement = []
            continue
        if tok == "}":
            if stack:
                stack.pop()
            statement = []
            continue
        if tok == "(":
            parens += 1
        elif tok == ")":
            parens = max(0, parens - 1)
        elif tok == "<":
            angles += 1
        elif tok == ">":
            angles = max(0, angles - 1)
        elif tok in (",", ";") and parens == 0 and angles == 0:
            statement = []
            continue
        statement.append(tok)
    ctx = Context("none", prefix, prefix_start, stack[-1] if stack else None, definition, len(stack),
                  tokens=statement, string_start=string_start)
    if string_start is not None:
        before = statement[:-1]
        if parens > 0 and statement and statement[0] == "instance" and len(before) >= 2 and before[-1] == "=":
            ctx.where, ctx.key = "instance-annotation-value", before[-2]
            return ctx
        if len(before) >= 3 and before[0] in DIRECTIONS and before[-1] == "on":
            ctx.where = "topic"
            ctx.direction, ctx.wired_type = before[0], before[1]
        return ctx
    if "." in prefix and not prefix.startswith("."):
        ctx.where = "dotted"
    if parens > 0:
        inner = statement[_last_index(statement, "(") + 1:]
        if statement and statement[0] == "instance":
            tail = inner[_last_index(inner, ",") + 1:] if "," in inner else inner
            if tail and tail[-1] == "=":
                ctx.where, ctx.key = "instance-annotation-value", tail[-2] if len(tail) > 1 else None
            else:
                ctx.where = "instance-annotation-key"
            return ctx
        if statement and statement[0] in DIRECTIONS and len(statement) > 1:
            ctx.direction, ctx.wired_type = statement[0], statement[1]
        tail = inner[_last_index(inner, ",") + 1:] if "," in inner else inner
        ctx.where = "annotation-value" if tail and tail[-1] == "=" else "annotation-key"
        return ctx
    if ctx.where == "dotted":
        return ctx
    if not stack:
        return _top(ctx, statement)
    return _member(ctx, statement)


def _last_index(tokens: list[str], tok: str) -> int:
    for i in range(len(tokens) - 1, -1, -1):
        if tokens[i] == tok:
            return i
    return -1


def _body_kind(header: list[str], stack: list[str]) -> str:
    if not stack:
        return header[0] if header and header[0] in BODY_KEYWORDS else "body"
    if stack[-1] in ("service", "action") and header:
        return header[-1]  # a section: request, response, goal, result, feedback
    return "body"


def _top(ctx: Context, statement: list[str]) -> Context:
    words = statement
    if not words:
        ctx.where = "top"
        return ctx
    first = words[0]
    if first == "instance" and len(words) == 3 and words[2] == ":":
        ctx.where = "instance-component"
        return ctx
    if first in DIRECTIONS:
        ctx.direction = first
        if len(words) == 1:
            ctx.where = "wiring-type"
        elif len(words) == 2:
            ctx.wired_type = words[1]
            ctx.where = "wiring-on"
        elif len(words) == 3 and words[2] == "on":
            ctx.wired_type = words[1]
            ctx.where = "topic"
        return ctx
    if first in ("typedef", "const") and len(words) == 1:
        ctx.where = "type"
    elif first == "namespace" and len(words) == 1:
        ctx.where = "namespace-scope"
    elif first == "service" and len(words) == 3 and words[2] == "extends":
        ctx.where = "wiring-type"
        ctx.direction = "extends"
    elif first == "const" and words[-1] == "=":
        ctx.where = "value"
        ctx.value_type = words[1] if len(words) > 1 else None
    return ctx


_MODIFIERS = frozenset({"required", "optional", "const", "oneway"})


def _member(ctx: Context, statement: list[str]) -> Context:
    words = statement
    if ctx.body == "enum":
        ctx.where = "none"
        return ctx
    if words and words[-1] == "=":
        ctx.where = "value"
        typed = [w for w in words[:-1] if w not in _MODIFIERS and w != ":" and not w[0].isdigit()]
        ctx.value_type = typed[0] if len(typed) >= 2 else None
        return ctx
    core = [w for w in words if w not in _MODIFIERS and w != ":" and not (w[0].isdigit() or w[0] in "+-")]
    if any(w in ("<", ",", "[") for w in words[-1:]):
        ctx.where = "type"
        return ctx
    if not core:
        ctx.where = "member"
        return ctx
    if len(core) == 1 and core[0] not in ("]", ">"):
        ctx.where = "member-name"
        return ctx
    ctx.where = "none"
    return ctx
