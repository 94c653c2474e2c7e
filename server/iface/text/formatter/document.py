"""A whole text: clean chunks formatted item by item, broken chunks kept as written.

A text that parses is one segment. Otherwise it is cut into top-level chunks
the way the compiler cuts it (``parse.parse_text``), and runs of chunks that
parse cleanly form segments. In a segment every top-level item becomes one
region of the output, and the comments and blank lines after the last item
form its tail region. A chunk with a syntax error is one region, kept byte
for byte. Every formatted item is parsed again and must give the same tokens
and comments as the original, or it too is kept as written (``Region.unsafe``).
"""

from __future__ import annotations

import gc
from bisect import bisect_left
from dataclasses import dataclass
from typing import Literal

from lark import Token, Tree

from ...syntax.parse import parse_text
from .doc import LeadComment, render
from .layout import Layout
from .lex import (
    Attached,
    Comment,
    FormatterBug,
    attach_comments,
    end_of,
    kept_tokens,
    parse_strict,
    start_of,
)

#: Items that always stand apart from their neighbours by a blank line.
BLOCK_KINDS = frozenset({"enum", "senum", "struct", "service", "action"})
#: The widest line the formatter aims for (lists and parameters break beyond it).
WIDTH = 100

RegionKind = Literal["item", "tail", "broken"]
Signature = list[tuple[str, ...]]


@dataclass(slots=True)
class Region:
    """A piece of the original text, ``[start, end)``, and what it becomes.

    ``content_start``/``content_end`` bound its tokens and comments (without
    the whitespace before them); range formatting selects regions by them.
    """

    start: int
    end: int
    content_start: int
    content_end: int
    text: str
    kind: RegionKind
    #: Why a region that should have been formatted was kept as written.
    unsafe: str = ""


@dataclass(slots=True)
class Formatted:
    """The formatted text and the regions it was made of."""

    text: str
    regions: list[Region]

    @property
    def unsafe(self) -> list[Region]:
        """Regions left as written because the formatter could not vouch for its output."""
        return [r for r in self.regions if r.unsafe]

    @property
    def broken(self) -> list[Region]:
        """Regions left as written because they hold syntax errors."""
        return [r for r in self.regions if r.kind == "broken"]


@dataclass(slots=True)
class _Segment:
    start: int
    end: int
    chunks: list[tuple[int, Tree]]


def format_document(text: str, indent: int = 4, width: int = WIDTH) -> Formatted:
    """Format ``text``; see the module docstring."""
    # the formatter makes millions of objects and frees none until it is done: the collector, run all the
    # while, would walk them again and again (a third of the time, and superlinear)
    enabled = gc.isenabled()
    gc.disable()
    try:
        return _format_document(text, indent, width)
    finally:
        if enabled:
            gc.enable()


def _format_document(text: str, indent: int, width: int) -> Formatted:
    regions: list[Region] = []
    segment: _Segment | None = None
    whole = parse_strict(text)
    spans = [(0, len(text))] if whole is not None else _chunk_spans(text)
    for start, end in spans:
        tree = whole if whole is not None else parse_strict(text[start:end])
        if tree is None:
            if segment is not None:
                regions += _format_segment(text, segment, indent, width)
                segment = None
            regions.append(Region(start, end, start, end, text[start:end], "broken"))
        elif segment is None:
            segment = _Segment(start, end, [(start, tree)])
        else:
            segment.end = end
            segment.chunks.append((start, tree))
    if segment is not None:
        regions += _format_segment(text, segment, indent, width)
    return Formatted("".join(r.text for r in regions), regions)


def _chunk_spans(text: str) -> list[tuple[int, int]]:
    """The [start, end) of every top-level chunk, as the compiler cuts them."""
    starts = sorted({r.base for r in parse_text(text).chunks} | {0})
    return [(a, b) for a, b in zip(starts, [*starts[1:], len(text)]) if a < b]


def _format_segment(text: str, seg: _Segment, indent: int, width: int) -> list[Region]:
    """The regions of one run of clean chunks: one per top-level item, then the tail."""
    items = [(base, child) for base, tree in seg.chunks for child in tree.children if isinstance(child, Tree)]
    tokens = [(base, tok) for base, tree in seg.chunks for tok in kept_tokens(tree)]
    try:
        infos, tail = attach_comments(text, seg.start, seg.end,
                                      [(b + start_of(t), b + end_of(t)) for b, t in tokens], indent)
    except FormatterBug as e:
        return [Region(seg.start, seg.end, seg.start, seg.end, text[seg.start:seg.end], "tail", unsafe=str(e))]
    original = _original_signature(tokens, infos, tail)
    layout = Layout(infos)
    fresh_line = seg.start == 0 or text[seg.start - 1] == "\n"
    regions: list[Region] = []
    prev_end = seg.start
    prev_block: bool | None = None
    for base, item in items:
        start, end = layout.extent(item, base)
        try:
            body, mark = render(layout.item(item, base), width, indent)
            block = item.data in BLOCK_KINDS or body.count("\n") > (mark or 0)
            if prev_block is None:
                sep = "" if fresh_line else "\n"
            else:
                blank = prev_block or block or text.count("\n", prev_end, start) >= 2
                sep = "\n\n" if blank else "\n"
            new = sep + body
            problem = _check(new, original, prev_end, end)
        except Exception as e:  # noqa: BLE001 — a bug in one item's layout must not lose the others
            problem, block = f"{type(e).__name__}: {e}", True
        if problem:
            regions.append(Region(prev_end, end, start, end, text[prev_end:end], "item", unsafe=problem))
        else:
            regions.append(Region(prev_end, end, start, end, new, "item"))
        prev_end, prev_block = end, block
    last = _tail(text, seg, tail, prev_end, has_items=bool(items), fresh_line=fresh_line,
                 indent=indent, at_eof=seg.end == len(text))
    problem = _check(last.text, original, last.start, last.end)
    if problem:
        last.text, last.unsafe = text[last.start:last.end], problem
    regions.append(last)
    return regions


def _tail(text: str, seg: _Segment, tail: list[Comment], start: int, *, has_items: bool,
          fresh_line: bool, indent: int, at_eof: bool) -> Region:
    """The comments after the last item, and the line breaks that end the segment."""
    out = ""
    if tail:
        printed, _ = render([LeadComment(c, blank=i > 0 and c.blank_before) for i, c in enumerate(tail)],
                            unit=indent)
        if has_items:
            out = ("\n\n" if tail[0].blank_before else "\n") + printed
        else:
            out = ("" if fresh_line else "\n") + printed
    content_end = tail[-1].end if tail else start
    if not (has_items or tail):
        end = ""
    elif at_eof:
        end = "\n"
    else:
        end = "\n\n" if text.count("\n", content_end, seg.end) >= 2 else "\n"
    content_start = tail[0].start if tail else start
    return Region(start, seg.end, content_start, seg.end, out + end, "tail")


# ---- meaning check -------------------------------------------------------------------------

def _token_key(tok: Token) -> tuple[str, ...]:
    return ("token", tok.type, str(tok))


def _comment_key(c: Comment) -> tuple[str, ...]:
    return ("comment", *c.key())


@dataclass(slots=True)
class _Sig:
    """The kept tokens and comments of a text in order, with their offsets."""

    offsets: list[int]
    keys: Signature


def _original_signature(tokens: list[tuple[int, Token]], infos: dict[int, Attached],
                        tail: list[Comment]) -> _Sig:
    """Every kept token and comment of a segment with its offset, in text order."""
    out: list[tuple[int, tuple[str, ...]]] = []
    for base, tok in tokens:
        pos = base + start_of(tok)
        info = infos[pos]
        out += [(c.start, _comment_key(c)) for c in info.leading]
        out.append((pos, _token_key(tok)))
        out += [(c.start, _comment_key(c)) for c in info.trailing]
    out += [(c.start, _comment_key(c)) for c in tail]
    return _Sig([pos for pos, _ in out], [key for _, key in out])


def signature(text: str) -> Signature | None:
    """The kept tokens and comments of ``text`` in order, or None if it does not parse."""
    tree = parse_strict(text)
    if tree is None:
        return None
    toks = list(kept_tokens(tree))
    infos, tail = attach_comments(text, 0, len(text), [(start_of(t), end_of(t)) for t in toks])
    return _original_signature([(0, t) for t in toks], infos, tail).keys


def _check(new: str, original: _Sig, start: int, end: int) -> str:
    """'' when ``new`` holds the same tokens and comments as ``original`` has in [start, end), else why not."""
    got = signature(new)
    if got is None:
        return "the formatted text does not parse"
    if got != original.keys[bisect_left(original.offsets, start):bisect_left(original.offsets, end)]:
        return "the formatted text differs in its tokens or comments"
    return ""
