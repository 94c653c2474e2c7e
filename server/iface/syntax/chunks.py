"""Split a text into independent top-level chunks, and find its doc comments.

A chunk starts at a definition keyword in column 0 (or at the doc comment
right before it). A block comment that never closes starts the last chunk: the
rest of the text is comment, and is neither parsed nor modelled. Chunks are parsed separately, so a syntax error stays in its
chunk and an edit re-parses only the chunks it touches. The split is a
heuristic: a chunk that ends inside an open body is merged with the next one
by the parser (see ``parse``), so it never changes what a valid file means.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

TOP_KEYWORDS = (
    "include", "cpp_include", "namespace", "component", "external",
    "publishes", "subscribes", "provides", "calls",
    "const", "typedef", "enum", "senum", "struct", "union", "exception",
    "message", "configuration", "state", "service", "action",
)

_SCAN = re.compile(
    r"/\*.*?(?:\*/|\Z)|//[^\n]*|#[^\n]*|^(?:%s)\b" % "|".join(TOP_KEYWORDS),
    re.M | re.S,
)
_SPACE = re.compile(r"\s*")


@dataclass(slots=True)
class Chunk:
    """A piece of the text: ``text[start:end]``, with its doc comments (relative offsets)."""

    start: int
    end: int
    docs: dict[int, str]
    #: The chunk is a block comment that never closes: it runs to the end of the text and is not parsed.
    unterminated: bool = False


def clean_doc(comment: str) -> str:
    """The text of a ``/** … */`` comment without its markers and leading stars."""
    body = comment[3:-2] if comment.endswith("*/") else comment[3:]
    lines = body.split("\n")
    out = []
    for line in lines:
        s = line.strip()
        if s.startswith("*"):
            s = s[1:]
            if s.startswith(" "):
                s = s[1:]
        out.append(s.rstrip())
    while out and not out[0]:
        out.pop(0)
    while out and not out[-1]:
        out.pop()
    return "\n".join(out)


def split(text: str) -> list[Chunk]:
    """Cut ``text`` into chunks covering it without gaps."""
    cuts = [0]
    docs: list[tuple[int, int, str]] = []  # (comment start, documented offset, text)
    pending_doc = -1
    open_comment = -1
    for match in _SCAN.finditer(text):
        s = match.start()
        c = text[s]
        closed = match.end() - s >= 4 and text.startswith("*/", match.end() - 2)  # no copy of a long comment
        if c == "/" and text.startswith("/*", s) and not closed:
            open_comment = s  # a block comment that never closes: the rest of the text is comment
            break
        if c == "/" and text.startswith("/**", s) and not text.startswith("/**/", s):
            target = _SPACE.match(text, match.end()).end()  # type: ignore[union-attr]  # \s* always matches
            docs.append((s, target, clean_doc(match.group())))
            pending_doc = s
            continue
        if c in "/#":
            continue
        cut = s
        if pending_doc >= 0 and docs[-1][1] == s:
            cut = pending_doc
        if cut > cuts[-1]:
            cuts.append(cut)
        pending_doc = -1
    if open_comment > cuts[-1]:
        cuts.append(open_comment)
    cuts.append(len(text))
    chunks: list[Chunk] = []
    di = 0
    for a, b in zip(cuts, cuts[1:]):
        cd: dict[int, str] = {}
        while di < len(docs) and docs[di][0] < b:
            _, target, doc = docs[di]
            cd[target - a] = doc
            di += 1
        chunks.append(Chunk(a, b, cd, a == open_comment))
    if not chunks:
        chunks.append(Chunk(0, 0, {}))
    return chunks
