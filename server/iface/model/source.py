"""Source files and spans: offsets into a text, converted to lines only at the edges."""

from __future__ import annotations

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
    """A span that moves with another: its offsets are kept relative to its ``anchor``.

    Spans of the model made by the parser are relative to their chunk's result (``ChunkResult.anchor``),
    which is relative to the chunk, which is relative to the base of a block of chunks
    (``syntax.edits.EditCache``): moving every chunk after an edit is one addition per block.
    """

    __slots__ = ("anchor",)
    # The offsets relative to the anchor are kept in the two slots of ``Span`` (``_start``, ``_end`` below),
    # which the ``start`` and ``end`` properties shadow: one slot more than a plain span, not three.
    _start: Any = Span.__dict__["start"]
    _end: Any = Span.__dict__["end"]

    def __init__(self, start: int, end: int, anchor: Span) -> None:  # noqa: D107
        self.anchor = anchor
        self._start = start - anchor.start
        self._end = end - anchor.start

    @classmethod
    def relative(cls, start: int, end: int, anchor: Span) -> AnchoredSpan:
        """The span at ``start``..``end`` counted from where ``anchor`` is (the parser's offsets in a chunk)."""
        span = cls.__new__(cls)
        span.anchor = anchor
        span._start = start
        span._end = end
        return span

    def __getstate__(self) -> tuple[Span, int, int]:
        return self.anchor, self._start, self._end

    def __setstate__(self, state: tuple[Span, int, int]) -> None:
        self.anchor, self._start, self._end = state

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

    def keep_relative_to(self, anchor: Span) -> None:
        """Keep the same offsets, relative to ``anchor`` from now on."""
        start, end = self.start, self.end
        self.anchor = anchor
        self.start, self.end = start, end

    def move_to_start_of(self, anchor: Span) -> None:
        """Put this span, empty, where ``anchor`` starts, and move it with ``anchor`` from now on."""
        self.anchor = anchor
        self._start = self._end = 0


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
