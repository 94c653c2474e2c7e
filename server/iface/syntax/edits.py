"""An edited document's parse made from its last one, in time that follows the edit.

``parse_edited`` gives what ``parse_text`` gives with a cache: ``split`` says
which chunks are the last version's (kept at the front, moved at the back), so
only those between are parsed, and the kept chunks' results are taken by their
place, without looking at each one. What this does not handle the simple way
(a chunk left open, a comment that never closes, a last version whose chunks
were merged) goes to ``parse_text``, which looks at every chunk.
"""

from __future__ import annotations

from bisect import bisect_left
from itertools import chain
from operator import attrgetter
from typing import Any

from .chunks import split
from .parse import ChunkCache, ChunkResult, ParseResult, chunk_parser, parse_text

_ITEMS = attrgetter("items")
_START = attrgetter("span.start")
#: What an edit changed: (offset, items gone, items new, the items of the version before). The items
#: before ``offset`` are the version before's, and so are those after what is new (moved).
Change = tuple[int, list[Any], list[Any], list[Any]]


class EditCache(ChunkCache):
    """A ``ChunkCache`` that also keeps the last version's parse."""

    def __init__(self) -> None:
        super().__init__()
        self.last: ParseResult | None = None
        #: What the last parse changed, when it kept the chunks around the edit.
        self.change: Change | None = None

    def forget(self, r: ChunkResult) -> None:
        """``r`` is no longer a chunk of the document."""
        same = self._by_text.get(r.text)
        if same is None:
            return
        for i, x in enumerate(same):
            if x is r:
                del same[i]
                break
        if not same:
            del self._by_text[r.text]

    def keep(self, r: ChunkResult) -> None:
        """``r`` is a chunk of the document now."""
        self._by_text.setdefault(r.text, []).append(r)


def parse_edited(text: str, cache: EditCache) -> ParseResult:
    """``parse_text(text, cache)``, re-parsing only the chunks between those the edit left as they were."""
    cache.change = None
    result = _reuse(text, cache)
    if result is None:
        result = parse_text(text, cache)
    cache.last = result
    return result


def _reuse(text: str, cache: EditCache) -> ParseResult | None:
    prev = cache.last
    if prev is None or cache.split is None:
        return None
    old_chunks = cache.split[1]
    old = prev.chunks
    if len(old) != len(old_chunks) or (prev.problems and any(r.open_at_end for r in old)):
        return None  # merged chunks, or one left open that what follows may close now
    kept: list[int] = []
    chunks = split(text, cache.split, kept)
    if not kept:
        return None
    k, end = kept
    after = len(chunks) - end
    parser = chunk_parser()
    middle: list[ChunkResult] = []
    for ch in chunks[k:end]:
        if ch.unterminated:
            return None
        r = parser.parse(text[ch.start:ch.end], ch.docs)
        if r.open_at_end:
            return None
        r.move_to(ch.start)
        middle.append(r)
    for r in old[k:len(old) - after]:
        cache.forget(r)
    for r in middle:
        cache.keep(r)
    suffix = old[len(old) - after:]
    delta = len(text) - len(cache.split[0])
    if delta:  # every chunk after the change moves by as much (``ChunkResult.move_to``, one loop)
        for r in suffix:
            for s in r.spans:  # a chunk records one span, its anchor (see ``ModelBuilder.reset``)
                s.start += delta
                s.end += delta
            r.base += delta
    cut = chunks[k].start if k < len(chunks) else len(text)
    # the items before the change start before it (the others are further on, moved or gone): a binary search
    before = bisect_left(prev.items, cut, key=_START)
    behind = len(prev.items) - before - sum(len(r.items) for r in old[k:len(old) - after])
    new = list(chain.from_iterable(map(_ITEMS, middle)))
    items: list[Any] = [*prev.items[:before], *new, *prev.items[len(prev.items) - behind:]]
    cache.change = (cut, prev.items[before:len(prev.items) - behind], new, prev.items)
    results = [*old[:k], *middle, *suffix]
    if prev.problems:
        problems = [p for r in results if r.problems for p in r.problems]
    else:
        problems = [p for r in middle for p in r.problems]
    cache.split = (text, chunks)
    return ParseResult(items, problems, results)
