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
from bisect import bisect_left, bisect_right
from collections.abc import Callable
from operator import attrgetter

from ..model.source import ORIGIN, AnchoredSpan

TOP_KEYWORDS = (
    "include", "cpp_include", "namespace", "component", "external", "system", "instance",
    "publishes", "subscribes", "provides", "calls",
    "const", "typedef", "enum", "senum", "struct", "union", "exception",
    "message", "configuration", "state", "service", "action",
)

_SCAN = re.compile(
    r"/\*.*?(?:\*/|\Z)|//[^\n]*|#[^\n]*|^(?:%s)\b" % "|".join(TOP_KEYWORDS),
    re.M | re.S,
)
_SPACE = re.compile(r"\s*")
_START = attrgetter("start")
#: The doc comments of the many chunks that have none (one dict, never changed).
NO_DOCS: dict[int, str] = {}


class Chunk(AnchoredSpan):
    """A piece of the text, ``text[start:end]``, with its doc comments (relative offsets).

    Its bounds are relative to its ``anchor``: the base of a block of chunks that an edit moves as
    one (``syntax.edits.EditCache``), ``ORIGIN`` for a chunk in no block.
    """

    __slots__ = ("docs", "unterminated")

    def __init__(self, start: int, end: int, docs: tuple[int | str, ...] = (), unterminated: bool = False) -> None:
        super().__init__(start, start, ORIGIN)
        self._end = end - start
        #: The doc comments, flat: (offset documented, text, offset, text …); a tuple is a quarter of a dict.
        self.docs = docs
        #: The chunk is a block comment that never closes: it runs to the end of the text and is not parsed.
        self.unterminated = unterminated

    @property
    def end(self) -> int:
        """Where the chunk ends. Its length is kept rather than its end: a small number, most often one of
        the ints Python shares, where an end relative to the block is an object of its own."""
        return self.start + self._end

    @end.setter
    def end(self, value: int) -> None:
        self._end = value - self.start

    def doc_map(self, shift: int = 0) -> dict[int, str]:
        """The doc comments by the offset they document, plus ``shift``."""
        docs = self.docs
        if not docs:
            return NO_DOCS
        return {k + shift: v for k, v in zip(docs[::2], docs[1::2])}  # type: ignore[operator, misc]

    def __repr__(self) -> str:
        return f"Chunk({self.start}, {self.end}, {self.docs!r}, {self.unterminated})"


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


def split(text: str, previous: tuple[str, list[Chunk]] | None = None) -> list[Chunk]:
    """Cut ``text`` into chunks covering it without gaps.

    With ``previous`` (an earlier version of the text and its chunks) only the
    text around what changed is scanned again (``resplit``); the chunks after
    it are copies of the earlier ones, moved.
    """
    if previous is None or not previous[1]:
        return _split(text, 0)
    old, old_chunks = previous
    k, middle, i = resplit(text, old, old_chunks)
    delta = len(text) - len(old)
    moved = [Chunk(c.start + delta, c.end + delta, c.docs, c.unterminated) for c in old_chunks[i:]]
    return [*old_chunks[:k], *middle, *moved]


def resplit(text: str, old: str, old_chunks: list[Chunk],
            known: tuple[int, int] | None = None) -> tuple[int, list[Chunk], int]:
    """Cut ``text``, an edited version of ``old`` whose chunks were ``old_chunks``, again where it changed.

    Returns ``(k, middle, i)``: the chunks of ``text`` are ``old_chunks[:k]``, then ``middle``, then
    ``old_chunks[i:]`` moved by ``len(text) - len(old)`` (which the caller does). Only the text
    around the change is scanned: once the scan reaches, past the change, a cut the earlier version
    had at the same place, the rest is as it was. Time follows the change, not the text.

    ``known`` is (head, tail) when the caller knows that the texts have at least their first ``head`` and
    last ``tail`` characters in common (an editor's edits say so): they are not compared then.
    """
    head = _common_prefix(old, text) if known is None else min(known[0], len(old), len(text))
    if head == len(old) == len(text):
        return len(old_chunks), [], len(old_chunks)
    if known is None:
        tail = _common_suffix(old, text, head)
    else:
        tail = max(min(known[1], len(old) - head, len(text) - head), 0)
    delta = len(text) - len(old)
    new_end = len(text) - tail
    k = max(bisect_right(old_chunks, head, key=_START) - 2, 0)  # one chunk of margin before the change

    def resumes(cut: int) -> bool:
        """True for a cut past the change that the earlier version had too (the rest is the same)."""
        if cut < new_end:
            return False
        j = bisect_left(old_chunks, cut - delta, key=_START)
        return j < len(old_chunks) and old_chunks[j].start == cut - delta

    middle = _split(text, old_chunks[k].start, resumes)
    last = middle[-1]
    if last.end >= len(text):
        return k, middle, len(old_chunks)
    return k, middle, bisect_left(old_chunks, last.end - delta, key=_START)


def _common_prefix(a: str, b: str, block: int = 1 << 15) -> int:
    """The length of the longest common prefix of ``a`` and ``b``, compared a block at a time in C."""
    n = min(len(a), len(b))
    i = 0
    while i < n:
        j = min(i + block, n)
        if a[i:j] != b[i:j]:
            while j - i > 32:  # halve the block that differs
                mid = (i + j) // 2
                if a[i:mid] == b[i:mid]:
                    i = mid
                else:
                    j = mid
            while a[i] == b[i]:
                i += 1
            return i
        i = j
    return n


def _common_suffix(a: str, b: str, head: int, block: int = 1 << 15) -> int:
    """The length of the longest common suffix of ``a`` and ``b`` that leaves ``head`` characters of each."""
    n = min(len(a), len(b)) - head
    la, lb = len(a), len(b)
    i = 0
    while i < n:
        j = min(i + block, n)
        if a[la - j:la - i] != b[lb - j:lb - i]:
            while j - i > 32:  # halve the block that differs, keeping the half nearest the end
                mid = (i + j) // 2
                if a[la - mid:la - i] == b[lb - mid:lb - i]:
                    i = mid
                else:
                    j = mid
            while a[la - i - 1] == b[lb - i - 1]:
                i += 1
            return i
        i = j
    return n


def _split(text: str, begin: int, resumes: Callable[[int], bool] | None = None) -> list[Chunk]:
    """Chunks of ``text`` from ``begin`` (a cut) to its end, or to the first cut for which ``resumes`` is
    true (the last chunk then ends there)."""
    cuts = [begin]
    docs: list[tuple[int, int, str]] = []  # (comment start, documented offset, text)
    pending_doc = -1
    open_comment = -1
    stop = -1
    for match in _SCAN.finditer(text, begin):
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
        pending_doc = -1
        if cut > cuts[-1]:
            if resumes is not None and resumes(cut):
                stop = cut
                break
            cuts.append(cut)
    end = len(text)
    if stop >= 0:
        end = stop
    elif open_comment > cuts[-1]:
        cuts.append(open_comment)
    cuts.append(end)
    chunks: list[Chunk] = []
    di = 0
    for a, b in zip(cuts, cuts[1:]):
        cd: tuple[int | str, ...] = ()
        while di < len(docs) and docs[di][0] < b:
            _, target, doc = docs[di]
            cd += (target - a, doc)
            di += 1
        chunks.append(Chunk(a, b, cd, a == open_comment and stop < 0))
    if not chunks:
        chunks.append(Chunk(begin, begin))
    return chunks
