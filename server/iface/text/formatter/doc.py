"""A small Wadler-style document algebra and its printer, with comments built in.

A document is a node or a list of nodes. ``Group`` contents are printed on one
line when they fit in the width and hold nothing that forces a break (a line
comment, a comment on its own line, a hard line); otherwise every ``Line`` and
``SoftLine`` of the group becomes a line break. ``Nest`` indents the lines it
breaks by one level. Spaces are soft: never at the start or end of a line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from .lex import Comment


@dataclass(frozen=True, slots=True)
class Text:
    """Words printed as they are (never holds a line break)."""

    text: str


class _Atom:
    """A layout instruction without content."""

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name

    def __repr__(self) -> str:
        return self.name


#: One space, unless at the start or end of a line.
SPACE = _Atom("SPACE")
#: A space in a flat group, a line break in a broken one.
LINE = _Atom("LINE")
#: Nothing in a flat group, a line break in a broken one.
SOFTLINE = _Atom("SOFTLINE")
#: Always a line break.
HARDLINE = _Atom("HARDLINE")
#: An empty line before the next content, if that content starts a line.
BLANK = _Atom("BLANK")
#: Like BLANK, but only inside a broken group.
BLANK_IF_BREAK = _Atom("BLANK_IF_BREAK")
#: Marks where the item proper starts (after its leading comments).
MARK = _Atom("MARK")


@dataclass(slots=True, eq=False)
class Group:
    """Contents printed flat when they fit, else broken at their lines."""

    parts: list[Doc]
    _must_break: bool | None = field(default=None, repr=False)

    @property
    def must_break(self) -> bool:
        """True when the contents cannot be printed on one line."""
        if self._must_break is None:
            self._must_break = forces_break(self.parts)
        return self._must_break


@dataclass(slots=True, eq=False)
class Nest:
    """Contents whose line breaks are indented one more level."""

    parts: list[Doc]


@dataclass(slots=True, eq=False)
class LeadComment:
    """A comment on its own line(s) before a token; ``blank`` keeps an empty line before it."""

    comment: Comment
    blank: bool = False


@dataclass(slots=True, eq=False)
class TrailComment:
    """A comment after a token on the token's line."""

    comment: Comment


Node = Union[Text, _Atom, Group, Nest, LeadComment, TrailComment]
Doc = Union[Node, list["Doc"]]


def forces_break(doc: Doc) -> bool:
    """True when ``doc`` holds something that cannot be printed inside one line."""
    stack: list[Doc] = [doc]
    while stack:
        d = stack.pop()
        if isinstance(d, list):
            stack.extend(d)
        elif isinstance(d, Nest):
            stack.extend(d.parts)
        elif isinstance(d, Group):
            if d.must_break:
                return True
        elif d is HARDLINE or d is BLANK or isinstance(d, LeadComment):
            return True
        elif isinstance(d, TrailComment) and (d.comment.break_after or "\n" in d.comment.text):
            return True
    return False


def split_trailing(doc: Doc) -> tuple[Doc, list[Doc]]:
    """``doc`` without the trailing comments at its very end, and those comments.

    Used to put a separator between a list element and the comments after it.
    """
    if isinstance(doc, TrailComment):
        return [], [doc]
    if isinstance(doc, list):
        return _split_parts(doc)
    if isinstance(doc, (Group, Nest)):
        inner, moved = _split_parts(doc.parts)
        if not moved:
            return doc, []
        rebuilt: Doc = Group(inner) if isinstance(doc, Group) else Nest(inner)
        return rebuilt, moved
    return doc, []


def _split_parts(doc: list[Doc]) -> tuple[list[Doc], list[Doc]]:
    """``split_trailing`` of a list of parts: the list stays a list."""
    parts = list(doc)
    moved: list[Doc] = []
    while parts:
        last, trail = split_trailing(parts[-1])
        if not trail:
            break
        moved[:0] = trail
        if last == []:
            parts.pop()  # the part was only comments: look further back
            continue
        parts[-1] = last
        break
    return parts, moved


_FLAT, _BREAK = 0, 1


class _Printer:
    """Accumulates lines; indentation and spaces are written lazily."""

    def __init__(self, unit: int) -> None:
        self.unit = unit
        self.lines: list[str] = []
        self.cur = ""
        self.cur_indent = 0
        self.has_content = False
        self.pending_space = False
        self.pending_blank = False
        #: After a line comment: the next content starts a new line at this indent.
        self.need_newline: int | None = None
        self.mark_line: int | None = None
        self.mark_pending = False
        #: The line so far ends with a leading comment that did not end its line (``/* a */ // b``).
        self.after_lead = False

    @property
    def column(self) -> int:
        if not self.has_content:
            return self.cur_indent
        return len(self.cur) + (1 if self.pending_space else 0)

    def newline(self, indent: int) -> None:
        if self.has_content:
            self.lines.append(self.cur)
            self.cur = ""
            self.has_content = False
        self.cur_indent = indent
        self.pending_space = False
        self.need_newline = None

    def space(self) -> None:
        if self.has_content:
            self.pending_space = True

    def write(self, text: str) -> None:
        self.after_lead = False
        if self.need_newline is not None:
            self.newline(self.need_newline)
        if not self.has_content:
            if self.pending_blank and self.lines and self.lines[-1] != "":
                self.lines.append("")
            self.cur = " " * self.cur_indent
            self.has_content = True
        elif self.pending_space:
            self.cur += " "
        self.pending_space = False
        self.pending_blank = False
        if self.mark_pending:
            self.mark_line = len(self.lines)
            self.mark_pending = False
        self.cur += text

    def comment(self, c: Comment) -> None:
        """Write a comment where the cursor is, re-indenting the lines of a block comment."""
        lines = [line.rstrip() for line in c.text.split("\n")]
        self.write(lines[0])
        if len(lines) == 1:
            return
        delta = (len(self.cur) - len(lines[0])) - c.column
        self.lines.append(self.cur)
        for line in lines[1:]:
            body = line.lstrip(" \t")
            lead = len(line[:len(line) - len(body)].expandtabs(self.unit))
            self.lines.append(" " * max(0, lead + delta) + body if body else "")
        self.cur = self.lines.pop()
        self.has_content = True

    def lead_comment(self, d: LeadComment, indent: int) -> None:
        if self.need_newline is not None:
            self.newline(self.need_newline)
        elif self.has_content and not self.after_lead:
            self.newline(indent + self.unit)
        if d.blank:
            self.pending_blank = True
        self.comment(d.comment)
        if d.comment.break_after:
            self.need_newline = self.cur_indent
        else:
            self.space()
            self.after_lead = True

    def trail_comment(self, d: TrailComment, indent: int) -> None:
        self.space()
        self.comment(d.comment)
        if d.comment.break_after:
            self.need_newline = indent + self.unit
        else:
            self.space()

    def text(self) -> str:
        lines = self.lines + ([self.cur] if self.has_content else [])
        return "\n".join(lines)


def _fits(width: int, head: tuple[int, int, Doc], rest: list[tuple[int, int, Doc]]) -> bool:
    """True when ``head`` printed flat, and what follows up to the next line break, fit."""
    stack = [head]
    rest_i = len(rest)
    in_rest = False
    while width >= 0:
        if not stack:
            if rest_i == 0:
                return True
            rest_i -= 1
            stack.append(rest[rest_i])
            in_rest = True
            continue
        ind, mode, d = stack.pop()
        if isinstance(d, list):
            stack.extend((ind, mode, x) for x in reversed(d))
        elif isinstance(d, Text):
            width -= len(d.text)
        elif d is SPACE:
            width -= 1
        elif d is LINE:
            if mode == _BREAK:
                return True
            width -= 1
        elif d is SOFTLINE:
            if mode == _BREAK:
                return True
        elif d is HARDLINE or isinstance(d, LeadComment):
            return True
        elif isinstance(d, TrailComment):
            if in_rest or d.comment.break_after or "\n" in d.comment.text:
                # comments after the group do not count: whether one ends its line is not
                # stable from one run to the next, and the width must not depend on it
                return True
            width -= 1 + len(d.comment.text)
        elif isinstance(d, Nest):
            stack.append((ind, mode, d.parts))
        elif isinstance(d, Group):
            stack.append((ind, _BREAK if d.must_break else mode, d.parts))
    return False


def render(doc: Doc, width: int = 100, unit: int = 4) -> tuple[str, int | None]:
    """Print ``doc`` from column 0; also returns the line index of its MARK, if any."""
    p = _Printer(unit)
    stack: list[tuple[int, int, Doc]] = [(0, _BREAK, doc)]
    while stack:
        ind, mode, d = stack.pop()
        if isinstance(d, list):
            stack.extend((ind, mode, x) for x in reversed(d))
        elif isinstance(d, Text):
            p.write(d.text)
        elif d is SPACE:
            p.space()
        elif d is LINE:
            if mode == _FLAT:
                p.space()
            else:
                p.newline(ind)
        elif d is SOFTLINE:
            if mode == _BREAK:
                p.newline(ind)
        elif d is HARDLINE:
            p.newline(ind)
        elif d is BLANK or (d is BLANK_IF_BREAK and mode == _BREAK):
            p.pending_blank = True
        elif d is MARK:
            p.mark_pending = True
        elif isinstance(d, Nest):
            stack.append((ind + unit, mode, d.parts))
        elif isinstance(d, Group):
            if mode == _FLAT and not d.must_break:
                stack.append((ind, _FLAT, d.parts))
            elif d.must_break or not _fits(width - p.column, (ind, _FLAT, d.parts), stack):
                stack.append((ind, _BREAK, d.parts))
            else:
                stack.append((ind, _FLAT, d.parts))
        elif isinstance(d, LeadComment):
            p.lead_comment(d, ind)
        elif isinstance(d, TrailComment):
            p.trail_comment(d, ind)
    return p.text(), p.mark_line
