"""The fast path's scanner: every terminal of grammar.lark in one compiled pattern.

lark's contextual lexer tries the terminals of the parser's state one by one
for every token; this scanner's pattern matches all of them at once, and the
driver (``driver.py``) makes the same contextual choice between a keyword and
a name by asking the parser's current state which of the two it accepts.
Anything it cannot read raises ``ScanError``, and the caller falls back to
lark's own lexer with error recovery.
"""

from __future__ import annotations

import re
import string

from lark import Lark


class ScanError(Exception):
    """The fast scanner met something it does not read; use lark's lexer instead."""


class FastScanner:
    """One-regex scanner of the terminals of a parser built from grammar.lark."""

    def __init__(self, parser: Lark) -> None:
        terminals = {t.name: t for t in parser.terminals}
        words: dict[str, str] = {}
        punct: list[tuple[str, str]] = []
        for t in parser.terminals:
            if t.pattern.type != "str":
                continue
            value = t.pattern.value
            if re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", value):
                words[value] = t.name
            else:
                punct.append((t.name, value))
        base = re.search(r"\(([a-z0-9|]+)\)", terminals["BASE_TYPE"].pattern.value)
        assert base is not None, "BASE_TYPE is an alternation of words"
        for word in base.group(1).split("|"):
            words[word] = "BASE_TYPE"
        # separators are one terminal, a pattern in the grammar
        punct += [("_SEP", ","), ("_SEP", ";")]
        punct.sort(key=lambda p: -len(p[1]))  # "<=" before "<"
        self.punct = {value: name for name, value in punct}
        self.words = words
        # the whole-file path (driver.py): one match per token with the blanks and comments before it,
        # read with findall (no match objects); a character no token reads is a match of its own
        ws = terminals["WS"].pattern.to_regexp()
        assert re.fullmatch(r"\[[^\]]+\]\+", ws), "WS is one character class, repeated"
        blank = f"{ws[:-1]}*+(?:(?:{_uncaptured(terminals['COMMENT'].pattern.to_regexp())}){ws[:-1]}*+)*+"
        # each token pattern starts with characters no other starts with, so their order only decides how
        # soon one is found: names first, then punctuation (the longer first), numbers (INT before DOUBLE),
        # strings
        singles = "".join(re.escape(v) for _, v in punct if len(v) == 1)
        longer = [re.escape(v) for _, v in punct if len(v) > 1]
        token = "|".join([_uncaptured(terminals["IDENTIFIER"].pattern.to_regexp()), *longer, f"[{singles}]",
                          *(_uncaptured(terminals[name].pattern.to_regexp()) for name in ("INT", "DOUBLE", "LITERAL"))])
        #: (blanks and comments, a token, a character no token reads); at the end of the text both are empty
        self.triples = re.compile(f"({blank})(?:({token})|((?s:.))|\\Z)")
        #: the terminal read from a token's first character: None for a number (INT or DOUBLE)
        self.first: dict[str, str | None] = {c: "IDENTIFIER" for c in string.ascii_letters + "_"}
        self.first.update({'"': "LITERAL", "'": "LITERAL"})
        self.first.update({c: None for c in string.digits + "+-."})
        self.int = re.compile(terminals["INT"].pattern.to_regexp())
        self.block_comment = re.compile(r"(?=/\*)(?:" + terminals["COMMENT"].pattern.to_regexp() + ")")


def _uncaptured(regex: str) -> str:
    """``regex`` with its groups made non-capturing (the same matches; the findall pattern has only its own)."""
    out = re.sub(r"(?<!\\)\((?!\?)", "(?:", regex)
    assert re.compile(out).groups == 0 and "(?P=" not in out, regex
    return out
