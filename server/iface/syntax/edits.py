"""An edited document's parse made from its last one, in time that follows the edit.

``parse_edited`` gives what ``parse_text`` gives with a cache: ``resplit`` says
which chunks are the last version's (kept at the front, moved at the back), so
only those between are parsed, and the kept chunks' results are taken by their
place, without looking at each one. What this does not handle the simple way
(a chunk left open, a comment that never closes, a last version whose chunks
were merged) goes to ``parse_text``, which looks at every chunk.

Moving the chunks after an edit costs one addition per block of chunks, not one
per chunk: each chunk's bounds are kept relative to the base of its block, about
sqrt(n) consecutive chunks (``EditCache.blocks``), and its result's spans
relative to the chunk (``ChunkResult.move_with``).
"""

from __future__ import annotations

from bisect import bisect_left
from itertools import chain
from math import isqrt
from operator import attrgetter
from typing import Any

from ..model.source import Span
from .chunks import Chunk, resplit
from .parse import ChunkCache, ChunkResult, ParseResult, chunk_parser, parse_text

_ITEMS = attrgetter("items")
_START = attrgetter("span.start")
#: What an edit changed: (offset, items gone, items new, the items of the version before). The items
#: before ``offset`` are the version before's, and so are those after what is new (moved).
Change = tuple[int, list[Any], list[Any], list[Any]]


class EditCache(ChunkCache):
    """A ``ChunkCache`` that also keeps the last version's parse, its chunks in blocks."""

    def __init__(self) -> None:
        super().__init__()
        self.last: ParseResult | None = None
        #: What the last parse changed, when it kept the chunks around the edit.
        self.change: Change | None = None
        #: The bases of the blocks of chunks, in text order (empty: the chunks are in no block).
        self.blocks: list[Span] = []
        #: What the next text is known to keep of the last one: (the last text, head, tail) when only the
        #: characters between its first ``head`` and last ``tail`` were edited (``Workspace.compile_text``).
        self.known: tuple[str, int, int] | None = None

    def block_up(self) -> None:
        """Put the chunks, one result per chunk (moving with it), in blocks of about sqrt(n)."""
        self.blocks = []
        chunks = self.split[1] if self.split is not None else []
        if len(chunks) != len(self.results):
            return  # merged chunks: the next edit is parsed by ``parse_text``
        size = max(16, isqrt(len(chunks)))
        for a in range(0, len(chunks), size):
            base = Span(chunks[a].start, 0)
            self.blocks.append(base)
            for ch in chunks[a:a + size]:
                ch.keep_relative_to(base)

    def move_chunks(self, chunks: list[Chunk], i: int, delta: int, middle: list[Chunk]) -> None:
        """Move ``chunks[i:]`` (and so their results) by ``delta``, and put ``middle`` (at their offsets in
        the new text) in a block before them."""
        blocks = self.blocks
        at = len(blocks)
        if i < len(chunks):
            block = chunks[i].anchor
            at = next(j for j, b in enumerate(blocks) if b is block)
            if i > 0 and chunks[i - 1].anchor is block:  # the moved chunks start a block of their own
                base = Span(chunks[i].start, 0)
                t = i
                while t < len(chunks) and chunks[t].anchor is block:
                    chunks[t].keep_relative_to(base)
                    t += 1
                at += 1
                blocks.insert(at, base)
            if delta:
                for b in blocks[at:]:
                    b.start += delta
        if middle:
            base = Span(middle[0].start, 0)
            for ch in middle:
                ch.keep_relative_to(base)
            blocks.insert(at, base)


def parse_edited(text: str, cache: EditCache) -> ParseResult:
    """``parse_text(text, cache)``, re-parsing only the chunks between those the edit left as they were."""
    cache.change = None
    known, cache.known = cache.known, None
    reused = _reuse(text, cache, known)
    result = reused if reused is not None else parse_text(text, cache)
    # each edit adds a block or two: they are made again after a whole parse and about every sqrt(n) edits
    if reused is None or len(cache.blocks) > 3 * isqrt(len(result.chunks)) + 16:
        cache.block_up()
    cache.last = result
    return result


def _reuse(text: str, cache: EditCache, known: tuple[str, int, int] | None = None) -> ParseResult | None:
    prev = cache.last
    if prev is None or cache.split is None or not cache.blocks:
        return None
    old_text, old_chunks = cache.split
    old = prev.chunks
    if len(old) != len(old_chunks) or (prev.problems and any(r.open_at_end for r in old)):
        return None  # merged chunks, or one left open that what follows may close now
    kept = known[1:] if known is not None and known[0] is old_text else None
    k, fresh, i = resplit(text, old_text, old_chunks, kept)
    parser = chunk_parser()
    middle: list[ChunkResult] = []
    for ch in fresh:
        if ch.unterminated:
            return None
        r = parser.parse(text[ch.start:ch.end], ch.doc_map())
        if r.open_at_end:
            return None
        r.move_with(ch)
        middle.append(r)
    cut = old_chunks[k].start if k < len(old_chunks) else len(text)
    cache.move_chunks(old_chunks, i, len(text) - len(old_text), fresh)
    # the items before the change start before it (the others are further on, moved or gone): a binary search
    before = bisect_left(prev.items, cut, key=_START)
    behind = len(prev.items) - before - sum(len(r.items) for r in old[k:i])
    new = list(chain.from_iterable(map(_ITEMS, middle)))
    # one copy of each long list, then the part that changed replaced in place (no copies of the two ends)
    items: list[Any] = prev.items.copy()
    items[before:len(items) - behind] = new
    cache.change = (cut, prev.items[before:len(prev.items) - behind], new, prev.items)
    # the cache's own lists, changed in place: the last version's parse is not kept (``cache.last`` is this
    # one from now on), and a copy of each would touch every chunk and result of the file
    old[k:i] = middle
    if prev.problems:
        problems = [p for r in old if r.problems for p in r.problems]
    else:
        problems = [p for r in middle for p in r.problems]
    old_chunks[k:i] = fresh
    cache.split = (text, old_chunks)
    cache.results = old
    return ParseResult(items, problems, old)
