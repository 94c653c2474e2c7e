"""Source files and spans: offsets into a text, converted to lines only at the edges."""

from __future__ import annotations

import struct
from array import array
from bisect import bisect_right
from dataclasses import dataclass, field
from typing import Any


class Span:
    """A half-open range of character offsets [start, end) in one source text.

    Spans are mutable so that a cached chunk can be moved when the text before
    it changes length (see ``syntax.chunks.ChunkCache``).
    """

    __slots__ = ("start", "end")

    def __init__(self, start: int, end: int) -> None:
        self.start = start
        self.end = end

    def __repr__(self) -> str:
        return f"Span({self.start}, {self.end})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Span) and other.start == self.start and other.end == self.end

    def __hash__(self) -> int:
        return hash((self.start, self.end))

    def contains(self, offset: int) -> bool:
        """True when ``offset`` lies inside the span or touches its end."""
        return self.start <= offset <= self.end


class AnchoredSpan(Span):
    """A span of a chunk that may move: offsets kept relative to the chunk's ``anchor``.

    The anchor is the one span the chunk records, where the chunk begins (``ChunkResult.anchor``); it
    is itself relative to the base of a block of chunks (``syntax.edits.EditCache``). Moving a chunk
    is one addition to its anchor, and moving every chunk after an edit one addition per block.
    """

    __slots__ = ("anchor",)
    # The offsets relative to the anchor are kept in the two slots of ``Span``, which the properties below
    # shadow: an anchored span is a plain one plus its anchor, not two slots more (16 bytes of some 23,000
    # spans at 10k lines).
    _start: Any = Span.__dict__["start"]
    _end: Any = Span.__dict__["end"]

    def __init__(self, start: int, end: int, anchor: Span) -> None:  # noqa: D107
        self.anchor = anchor
        self._start = start - anchor.start
        self._end = end - anchor.start

    @property
    def start(self) -> int:
        """Where the span starts."""
        return self._start + self.anchor.start

    @start.setter
    def start(self, value: int) -> None:
        self._start = value - self.anchor.start

    @property
    def end(self) -> int:
        """Where the span ends."""
        return self._end + self.anchor.start

    @end.setter
    def end(self, value: int) -> None:
        self._end = value - self.anchor.start

    def rebase(self, anchor: Span) -> None:
        """Keep the same offsets, relative to ``anchor`` from now on."""
        start, end = self.start, self.end
        self.anchor = anchor
        self.start, self.end = start, end

    def pin(self, anchor: Span) -> None:
        """Put this span, empty, where ``anchor`` starts, and move it with ``anchor`` from now on."""
        self.anchor = anchor
        self._start = self._end = 0


_REL_START = AnchoredSpan.__dict__["_start"]
_REL_END = AnchoredSpan.__dict__["_end"]
_ANCHOR = AnchoredSpan.__dict__["anchor"]
_new = object.__new__
#: Two sealed 2-byte offsets (``SpanTable.seal``), in the machine's order as ``array`` writes them.
_PAIR16 = struct.Struct("=hh").unpack_from


class SpanTable(AnchoredSpan):
    """The spans of one chunk's model, kept as offsets rather than as an object each.

    A chunk's result is its table (``syntax.parse.ChunkResult``), pinned to the chunk: the offsets are
    relative to where the table starts, so moving the chunk moves them all. A node made by the parser keeps
    the table and the index of its first span (``model.nodes.spanned``) and makes a span object only when
    one is read: some 23,000 span objects of 56 bytes at 10k lines become 4 bytes each.
    """

    __slots__ = ("offsets",)
    offsets: Any  # a list while the chunk is parsed, then bytes or an array (``seal``)

    def __init__(self) -> None:  # noqa: D107
        super().__init__(0, 0, ORIGIN)
        self.offsets = []

    def add(self, start: int, end: int) -> int:
        """Record the span [start, end); its index. Spans are added while the table is at offset 0."""
        offsets = self.offsets
        offsets.append(start)
        offsets.append(end)
        return (len(offsets) >> 1) - 1

    def put(self, k: int, start: int, end: int) -> None:
        """Set the span at index ``k`` (while the table is at offset 0)."""
        self.offsets[2 * k] = start
        self.offsets[2 * k + 1] = end

    def seal(self, length: int) -> None:
        """Keep the offsets, all within [0, ``length``], in as little memory as they fit: in most chunks
        2 bytes each, in one bytes object."""
        offsets = self.offsets
        try:
            if length < 1 << 15:
                self.offsets = array("h", offsets).tobytes()
            else:
                self.offsets = array("i" if length < 1 << 31 else "q", offsets)
        except OverflowError:  # an offset beyond the chunk: kept as it is, never lost
            self.offsets = array("q", offsets)

    def at(self, k: int) -> AnchoredSpan:
        """The span at index ``k``, relative to this table: it moves when the table does."""
        offsets = self.offsets
        if offsets.__class__ is bytes:
            start, end = _PAIR16(offsets, k << 2)
        else:
            start, end = offsets[2 * k], offsets[2 * k + 1]
        span = _new(AnchoredSpan)
        _ANCHOR.__set__(span, self)
        _REL_START.__set__(span, start)
        _REL_END.__set__(span, end)
        return span


#: The anchor of spans not (yet) placed relative to anything else; never moved.
ORIGIN = Span(0, 0)


@dataclass(eq=False)
class Source:
    """The text of one file with a lazily built line index."""

    path: str
    text: str
    _lines: array[int] | None = field(default=None, repr=False)

    @property
    def line_starts(self) -> array[int]:
        """Offsets at which each line starts (machine integers: 4 bytes a line, not a list of int objects)."""
        if self._lines is None:
            starts = array("I" if len(self.text) < 1 << 32 else "q", [0])
            find = self.text.find
            i = find("\n")
            while i >= 0:
                starts.append(i + 1)
                i = find("\n", i + 1)
            self._lines = starts
        return self._lines

    def position(self, offset: int) -> tuple[int, int]:
        """0-based (line, column in code points) of ``offset``."""
        offset = max(0, min(offset, len(self.text)))
        starts = self.line_starts
        line = bisect_right(starts, offset) - 1
        return line, offset - starts[line]

    def offset(self, line: int, column: int) -> int:
        """Offset of a 0-based (line, column in code points), clamped to the text."""
        starts = self.line_starts
        if line < 0:
            return 0
        if line >= len(starts):
            return len(self.text)
        end = starts[line + 1] - 1 if line + 1 < len(starts) else len(self.text)
        return min(starts[line] + max(column, 0), end)

    def line_text(self, line: int) -> str:
        """The text of a 0-based line without its newline."""
        starts = self.line_starts
        if not 0 <= line < len(starts):
            return ""
        end = starts[line + 1] - 1 if line + 1 < len(starts) else len(self.text)
        return self.text[starts[line]:end]
