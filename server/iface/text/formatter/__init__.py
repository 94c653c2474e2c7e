"""Format .iface and .thrift text: the library behind ``iface-lsp fmt`` and the language server.

``format_text`` re-writes a whole text in the house style (docs/formatting.md),
keeping every comment; ``format_range`` re-formats only the top-level
definitions a range touches and returns the edits that do it. Both leave
definitions with syntax errors exactly as written, and both are idempotent.

May import: ``model``, ``syntax`` (as ``text`` may).
"""

from __future__ import annotations

from typing import NamedTuple

from .document import Formatted, format_document

__all__ = ["TextEdit", "format_text", "format_range", "format_document", "Formatted"]


class TextEdit(NamedTuple):
    """Replace ``text[start:end]`` (character offsets) with ``new_text``."""

    start: int
    end: int
    new_text: str


def format_text(text: str, *, indent: int = 4) -> str:
    """``text`` formatted; definitions with syntax errors are kept byte for byte."""
    return format_document(text, _check_indent(indent)).text


def format_range(text: str, start: int, end: int, *, indent: int = 4) -> list[TextEdit]:
    """Edits that format every top-level definition ``text[start:end]`` touches.

    An empty range (``start == end``) selects the definition around the
    offset. Edits do not overlap, are in text order, and are trimmed to what
    actually changes; apply them from last to first (or all at once, as LSP does).
    """
    start, end = sorted((max(0, min(start, len(text))), max(0, min(end, len(text)))))
    formatted = format_document(text, _check_indent(indent))
    edits: list[TextEdit] = []
    run: list[tuple[int, int, str]] = []
    for r in formatted.regions:
        if r.kind != "broken" and _touches(r.content_start, r.content_end, start, end):
            if run and run[-1][1] == r.start:
                a, _, new = run[-1]
                run[-1] = (a, r.end, new + r.text)
            else:
                run.append((r.start, r.end, r.text))
    for a, b, new in run:
        edit = _trim(text, a, b, new)
        if edit is not None:
            edits.append(edit)
    return edits


def _check_indent(indent: int) -> int:
    if not 1 <= indent <= 16:
        raise ValueError(f"indent must be between 1 and 16 spaces, not {indent}")
    return indent


def _touches(a: int, b: int, start: int, end: int) -> bool:
    if start == end:
        return a <= start <= b
    return start < b and end > a


def _trim(text: str, a: int, b: int, new: str) -> TextEdit | None:
    """The smallest edit turning ``text[a:b]`` into ``new``, or None if they are equal."""
    old = text[a:b]
    if old == new:
        return None
    p = 0
    limit = min(len(old), len(new))
    while p < limit and old[p] == new[p]:
        p += 1
    q = 0
    while q < limit - p and old[len(old) - 1 - q] == new[len(new) - 1 - q]:
        q += 1
    return TextEdit(a + p, b - q, new[p:len(new) - q])
