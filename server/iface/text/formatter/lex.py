"""The formatter's view of a text: lark's own tokens, with every comment kept.

A clean chunk is parsed with the project's grammar into a tree that keeps
every token (``keep_all_tokens``). What lies between two tokens can only be
whitespace, comments and list separators; those gaps are scanned with the
grammar's own ``COMMENT`` and ``WS`` patterns, so comments are found exactly
where the parser skipped them.
"""

from __future__ import annotations

import re
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import lru_cache

from lark import Lark, Token, Tree
from lark.exceptions import LarkError

from ...syntax.driver import Driver
from ...syntax.grammar import grammar_text
from ...syntax.lexer import FastScanner, ScanError

#: Token types of the separators ``,`` and ``;`` (the grammar's filtered ``_SEP`` terminal).
SEPARATOR_TYPES = frozenset({"_SEP"})

_lock = threading.Lock()


class FormatterBug(Exception):
    """The formatter met something it does not expect; the text is left as written."""


@lru_cache(maxsize=1)
def tree_parser() -> Lark:
    """An LALR parser for grammar.lark that keeps every token in its tree.

    Like ``grammar.build_parser``, its tables are cached on disk by lark when it can.
    """
    options = dict(parser="lalr", lexer="contextual", keep_all_tokens=True, maybe_placeholders=False)
    try:
        return Lark(grammar_text(), cache=True, **options)
    except OSError:
        return Lark(grammar_text(), **options)


@lru_cache(maxsize=1)
def _gap_pattern() -> re.Pattern[str]:
    terminals = {t.name: t.pattern.to_regexp() for t in tree_parser().terminals}
    return re.compile(rf"(?P<comment>{terminals['COMMENT']})|(?P<ws>{terminals['WS']})|(?P<sep>[,;])")


@lru_cache(maxsize=1)
def _driver() -> Driver:
    parser = tree_parser()
    return Driver(parser, None, FastScanner(parser))


def parse_strict(text: str) -> Tree | None:
    """The full tree of ``text``, or None when it does not parse cleanly.

    The compiler's fast path reads it (one regex for the tokens, lark's tables driven by one loop, the
    same tree as lark's); only where that gives up does lark itself read the text.
    """
    parser = tree_parser()
    try:
        with _lock:
            try:
                tree = _driver().parse(text)
            except ScanError:
                tree = parser.parse(text)
            return tree if isinstance(tree, Tree) else None
    except (LarkError, RecursionError):
        return None


def start_of(tok: Token) -> int:
    """Offset of a token in the text it was parsed from."""
    if tok.start_pos is None:
        raise FormatterBug(f"token {tok!r} has no position")
    return tok.start_pos


def end_of(tok: Token) -> int:
    """Offset just past a token."""
    if tok.end_pos is None:
        raise FormatterBug(f"token {tok!r} has no position")
    return tok.end_pos


def is_separator(tok: Token) -> bool:
    """True for a ``,`` or ``;``: the formatter writes separators itself."""
    return tok.type in SEPARATOR_TYPES


def kept_tokens(tree: Tree) -> Iterator[Token]:
    """Every token of ``tree`` in source order, without optional separators."""
    stack: list[tuple[Tree, int]] = [(tree, 0)]
    while stack:
        node, i = stack.pop()
        if i >= len(node.children):
            continue
        stack.append((node, i + 1))
        child = node.children[i]
        if isinstance(child, Tree):
            stack.append((child, 0))
        elif not is_separator(child):
            yield child


@dataclass(slots=True, eq=False)
class Comment:
    """One comment as written, and how it sits between its neighbours."""

    text: str
    start: int
    #: Column of its first character in the original line (tabs expanded).
    column: int
    #: A blank line separates it from what comes before.
    blank_before: bool = False
    #: A line break follows it (always true for ``//`` and ``#`` comments).
    break_after: bool = True

    @property
    def end(self) -> int:
        """Offset just past the comment."""
        return self.start + len(self.text)

    @property
    def is_line(self) -> bool:
        """True for ``//`` and ``#`` comments, which run to the end of their line."""
        return not self.text.startswith("/*")

    def key(self) -> tuple[str, ...]:
        """The comment's words line by line: equal for a comment and its re-indented form."""
        return tuple(line.strip() for line in self.text.split("\n"))


@dataclass(slots=True, eq=False)
class Attached:
    """The comments around one token: own-line ones before it, same-line ones after it."""

    leading: list[Comment] = field(default_factory=list)
    trailing: list[Comment] = field(default_factory=list)
    #: A blank line right before the token (after its last leading comment).
    blank_before: bool = False

    @property
    def first_blank(self) -> bool:
        """A blank line before the token's first leading comment, or before the token."""
        return self.leading[0].blank_before if self.leading else self.blank_before


def attach_comments(text: str, start: int, end: int, tokens: list[tuple[int, int]],
                    tab: int = 4) -> tuple[dict[int, Attached], list[Comment]]:
    """Attach every comment of ``text[start:end]`` to a token.

    ``tokens`` are the (start, end) offsets of the kept tokens, in order. A
    comment on the line of the token before it trails that token; any other
    comment leads the next token. Comments after the last token are returned
    as the tail. Raises FormatterBug if a gap holds anything but whitespace,
    comments and separators.
    """
    scanner = _GapScanner(text, tab)
    infos: dict[int, Attached] = {}
    prev: Attached | None = None
    pos = start
    for tok_start, tok_end in tokens:
        leading, newlines = scanner.scan(pos, tok_start, prev, at_end=False)
        prev = infos[tok_start] = Attached(leading, [], blank_before=newlines >= 2)
        pos = tok_end
    tail, _ = scanner.scan(pos, end, prev, at_end=True)
    return infos, tail


class _GapScanner:
    """Reads the whitespace, comments and separators between two tokens."""

    def __init__(self, text: str, tab: int) -> None:
        self.text = text
        self.tab = tab
        self.pattern = _gap_pattern()
        # the column at offset ``_at``: columns are asked for in text order, so each character is read once
        self._at = 0
        self._col = 0

    def column(self, offset: int) -> int:
        """The column of ``offset`` (tabs expanded); offsets must not decrease from one call to the next."""
        text = self.text
        nl = text.rfind("\n", self._at, offset)
        if nl >= 0:
            self._at, self._col = nl + 1, 0
        seg = text[self._at:offset]
        col = self._col
        if "\t" in seg:
            tab = self.tab
            for ch in seg:
                col = (col // tab + 1) * tab if ch == "\t" else col + 1
        else:
            col += len(seg)
        self._at, self._col = offset, col
        return col

    def scan(self, pos: int, stop: int, prev: Attached | None, at_end: bool) -> tuple[list[Comment], int]:
        """Comments of ``text[pos:stop]``: same-line ones go to ``prev``; the rest are returned.

        Also returns the number of line breaks after the last comment.
        """
        leading: list[Comment] = []
        on_prev_line = prev is not None
        newlines = 0
        last: Comment | None = None
        for m in self.pattern.finditer(self.text, pos, stop):
            if m.start() != pos:
                break
            pos = m.end()
            if m.lastgroup == "ws":
                newlines += m.group().count("\n")
            elif m.lastgroup == "comment":
                if last is not None:
                    last.break_after = last.is_line or newlines > 0
                last = Comment(m.group(), m.start(), self.column(m.start()),
                               blank_before=newlines >= 2)
                if on_prev_line and newlines == 0:
                    assert prev is not None
                    prev.trailing.append(last)
                else:
                    on_prev_line = False
                    leading.append(last)
                newlines = 0
        if pos != stop:
            raise FormatterBug(f"unexpected text at offset {pos}")
        if last is not None:
            last.break_after = last.is_line or newlines > 0 or at_end
        return leading, newlines
