"""Tree → document: the formatting style, rule by rule.

The tree is lark's full parse tree of grammar.lark (every token kept). Each
token is printed with the comments attached to it; optional separators are
dropped and written again where the style wants them. A rule without a
method here has its parts joined by single spaces, so the layout stays
meaning-preserving when the grammar grows.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from lark import Token, Tree

from .doc import (
    BLANK,
    BLANK_IF_BREAK,
    HARDLINE,
    LINE,
    MARK,
    SOFTLINE,
    SPACE,
    Doc,
    Group,
    LeadComment,
    Nest,
    Text,
    TrailComment,
    split_trailing,
)
from .lex import Attached, FormatterBug, end_of, is_separator, kept_tokens, start_of

Child = Tree | Token

#: Definitions whose members go one per line between braces.
BODY_RULES = frozenset({"enum", "senum", "struct", "service", "action", "section"})
#: ROS 2 array suffixes, written right after their type: ``T[]``, ``T[N]``, ``T[<=N]``.
ARRAY_RULES = frozenset({"unbounded_array", "fixed_array", "bounded_array"})
#: Rules whose tokens are written without spaces: ``1:``, ``string<=8``, ``[<=3]``.
TIGHT_RULES = frozenset({"field_id", "bounded_string"}) | ARRAY_RULES


def first_token(x: Child) -> Token:
    """The first kept token of a subtree."""
    if isinstance(x, Token):
        return x
    for tok in kept_tokens(x):
        return tok
    raise FormatterBug(f"empty rule {x.data}")


def last_token(x: Child) -> Token:
    """The last kept token of a subtree."""
    if isinstance(x, Token):
        return x
    last = None
    for last in kept_tokens(x):
        pass
    if last is None:
        raise FormatterBug(f"empty rule {x.data}")
    return last


def _with_separators(elements: Sequence[Doc], wants: Callable[[int], bool]) -> list[Doc]:
    """Elements with a ``,`` after element ``j`` when ``wants(j)``, before its trailing comments."""
    out: list[Doc] = []
    for j, e in enumerate(elements):
        if wants(j):
            body, trail = split_trailing(e)
            e = [body, Text(","), *trail]
        out.append(e)
    return out


class Layout:
    """Builds the document of top-level items of one text."""

    def __init__(self, infos: dict[int, Attached]) -> None:
        self.infos = infos
        self.base = 0
        self._mark = -1

    # ---- tokens and their comments ------------------------------------------------
    def info(self, tok: Token) -> Attached:
        """The comments attached to ``tok``."""
        try:
            return self.infos[self.base + start_of(tok)]
        except KeyError:
            raise FormatterBug(f"token {tok!r} has no place in the text") from None

    @staticmethod
    def leading(info: Attached, blank_before_token: bool = True) -> list[Doc]:
        """The own-line comments before a token (the first one's blank line is the caller's)."""
        parts: list[Doc] = [LeadComment(c, blank=i > 0 and c.blank_before) for i, c in enumerate(info.leading)]
        if blank_before_token and info.leading and info.blank_before:
            parts.append(BLANK)
        return parts

    def t(self, tok: Token, lead: bool = True) -> list[Doc]:
        """A token with its comments."""
        info = self.info(tok)
        parts = self.leading(info) if lead else []
        if self.base + start_of(tok) == self._mark:
            parts.append(MARK)
        parts.append(Text(str(tok)))
        parts.extend(TrailComment(c) for c in info.trailing)
        return parts

    def extent(self, item: Tree, base: int) -> tuple[int, int]:
        """Offsets of an item's first own-line comment (or first token) and of its line's end."""
        self.base = base
        first, last = self.info(first_token(item)), self.info(last_token(item))
        start = first.leading[0].start if first.leading else base + start_of(first_token(item))
        end = last.trailing[-1].end if last.trailing else base + end_of(last_token(item))
        return start, end

    def first_blank(self, x: Child) -> bool:
        """True when the author left a blank line before ``x`` (or before its comments)."""
        return self.info(first_token(x)).first_blank

    # ---- dispatch -------------------------------------------------------------------
    def item(self, tree: Tree, base: int) -> Doc:
        """The document of one top-level item parsed at offset ``base``; MARK is at its first token."""
        self.base = base
        self._mark = base + start_of(first_token(tree))
        return self.node(tree)

    def node(self, x: Child) -> Doc:
        """The document of any subtree or token."""
        if isinstance(x, Token):
            return self.t(x)
        if x.data in BODY_RULES:
            return self.body(x)
        if x.data in TIGHT_RULES:
            return [self.node(c) for c in self.kept(x)]
        method = getattr(self, "rule_" + x.data, None)
        if method is not None:
            return method(x)
        return self.spaced(self.kept(x))

    @staticmethod
    def kept(tree: Tree) -> list[Child]:
        """The children of ``tree`` without optional separators."""
        return [c for c in tree.children if not (isinstance(c, Token) and is_separator(c))]

    def spaced(self, children: Sequence[Child]) -> list[Doc]:
        """Children joined by single spaces."""
        parts: list[Doc] = []
        for c in children:
            if parts:
                parts.append(SPACE)
            parts.append(self.node(c))
        return parts

    # ---- bodies: one member per line ----------------------------------------------------
    def body(self, tree: Tree) -> Doc:
        """``header {`` members one per line ``}`` annotations."""
        ch = self.kept(tree)
        lb = next(i for i, c in enumerate(ch) if isinstance(c, Token) and c.type == "LBRACE")
        rb = max(i for i, c in enumerate(ch) if isinstance(c, Token) and c.type == "RBRACE")
        members = ch[lb + 1:rb]
        open_tok, close_tok = ch[lb], ch[rb]
        assert isinstance(open_tok, Token) and isinstance(close_tok, Token)
        parts: list[Doc] = [self.spaced(ch[:lb]), SPACE, self.t(open_tok)]

        def sep_after(j: int) -> bool:
            return j + 1 < len(members) and not _is_section(members[j]) and not _is_section(members[j + 1])

        inner: list[Doc] = []
        for j, m in enumerate(_with_separators([self.node(m) for m in members], sep_after)):
            inner.append(HARDLINE)
            if j and self.first_blank(members[j]):
                inner.append(BLANK)
            inner.append(m)
        close = self.info(close_tok)
        if close.leading:
            inner.append(HARDLINE)
            if members and close.leading[0].blank_before:
                inner.append(BLANK)
            inner.extend(self.leading(close, blank_before_token=False))
        if inner or self.info(open_tok).trailing:
            parts += [Nest(inner), HARDLINE]
        parts.append(self.t(close_tok, lead=False))
        for c in ch[rb + 1:]:
            parts += [SPACE, self.node(c)]
        return parts

    # ---- bracketed lists: one line when they fit, else one element per line -------------
    def bracketed(self, open_tok: Child, elements: Sequence[Doc], firsts: Sequence[Child],
                  close_tok: Child) -> list[Doc]:
        """``(a, b)`` flat, or broken with one element per line; comments after ``)`` stay outside."""
        assert isinstance(open_tok, Token) and isinstance(close_tok, Token)
        n = len(elements)
        inner: list[Doc] = [SOFTLINE]
        for j, e in enumerate(_with_separators(elements, lambda j: j + 1 < n)):
            if j:
                inner.append(LINE)
                if self.first_blank(firsts[j]):
                    inner.append(BLANK_IF_BREAK)
            inner.append(e)
        close = self.info(close_tok)
        if close.leading:
            inner.append(LINE)
            if n and close.leading[0].blank_before:
                inner.append(BLANK_IF_BREAK)
            inner.extend(self.leading(close, blank_before_token=False))
        closing, after = split_trailing(self.t(close_tok, lead=False))
        return [Group([self.t(open_tok), Nest(inner), SOFTLINE, closing]), *after]

    def listing(self, tree: Tree) -> Doc:
        """Children ``open element* close``: annotations and list values."""
        ch = self.kept(tree)
        items = ch[1:-1]
        return self.bracketed(ch[0], [self.node(c) for c in items], items, ch[-1])

    rule_annotations = listing
    rule_list_value = listing

    def rule_map_value(self, tree: Tree) -> Doc:
        """``{k: v, …}``."""
        ch = self.kept(tree)
        flat = ch[1:-1]
        if len(flat) % 3:
            raise FormatterBug("map value entries are not key ':' value")
        entries: list[Doc] = []
        keys: list[Child] = []
        for i in range(0, len(flat), 3):
            key, colon, value = flat[i:i + 3]
            entries.append([self.node(key), self.node(colon), SPACE, self.node(value)])
            keys.append(key)
        return self.bracketed(ch[0], entries, keys, ch[-1])

    def call(self, tree: Tree, space_before: bool) -> Doc:
        """``head(fields) rest``: functions (``f(…)``) and throws (``throws (…)``)."""
        ch = self.kept(tree)
        lp = next(i for i, c in enumerate(ch) if isinstance(c, Token) and c.type == "LPAR")
        rp = next(i for i, c in enumerate(ch) if i > lp and isinstance(c, Token) and c.type == "RPAR")
        params = ch[lp + 1:rp]
        parts: list[Doc] = [self.spaced(ch[:lp])]
        if space_before and lp:
            parts.append(SPACE)
        parts.append(self.bracketed(ch[lp], [self.node(p) for p in params], params, ch[rp]))
        for c in ch[rp + 1:]:
            parts += [SPACE, self.node(c)]
        return parts

    def rule_function(self, tree: Tree) -> Doc:
        """``T name(params) throws (…) (annotations)``."""
        return self.call(tree, space_before=False)

    def rule_throws(self, tree: Tree) -> Doc:
        """``throws (fields)``."""
        return self.call(tree, space_before=True)

    # ---- types ------------------------------------------------------------------------------
    def rule_field_type(self, tree: Tree) -> Doc:
        """A type, ``(annotations)`` after a space, array suffixes right after it."""
        parts: list[Doc] = []
        for c in self.kept(tree):
            if parts and not (isinstance(c, Tree) and c.data in ARRAY_RULES):
                parts.append(SPACE)
            parts.append(self.node(c))
        return parts

    def container(self, tree: Tree) -> Doc:
        """``map<K, V>``, ``set<T>``, ``list<T>``; a ``cpp_type "…"`` stands apart by spaces."""
        parts: list[Doc] = []
        prev: Child | None = None
        types_seen = 0
        for c in self.kept(tree):
            # a lone base type or name arrives as its token (``?field_type`` in the grammar)
            is_type = prev is not None and (
                (isinstance(c, Tree) and not _is_rule(c, "cpp_type"))
                or (isinstance(c, Token) and c.type in ("BASE_TYPE", "IDENTIFIER")))
            if is_type and types_seen == 1:  # the separator between a map's key and value types
                key, trail = split_trailing(parts.pop())
                parts += [key, Text(","), *trail, SPACE]
            elif prev is not None and (_is_rule(c, "cpp_type") or _is_rule(prev, "cpp_type")):
                parts.append(SPACE)
            types_seen += is_type
            parts.append(self.node(c))
            prev = c
        return parts

    rule_map_type = container
    rule_set_type = container
    rule_list_type = container


def _is_rule(x: Child, name: str) -> bool:
    return isinstance(x, Tree) and x.data == name


def _is_section(x: Child) -> bool:
    return _is_rule(x, "section")
