"""Open editor buffers: their URIs, text versions, the edits made to them and offset mapping.

The event loop owns every ``Document``; a change replaces its ``DocState`` as a
whole, so a reader on another thread always sees one consistent version.
``EditLog`` keeps the edits since the last compiled version, so a request that
arrives before the newest text is compiled maps its offsets through them.
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import quote, unquote, urlparse

from .convert import LineIndex

_VIRTUAL: dict[str, str] = {}


def uri_to_path(uri: str) -> str:
    """The file system path of a ``file:`` URI; other schemes get a stable virtual ``.iface`` path."""
    parsed = urlparse(uri)
    if parsed.scheme == "file":
        path = unquote(parsed.path)
        if os.name == "nt" and path.startswith("/") and len(path) > 2 and path[2] == ":":
            path = path[1:]
        return os.path.abspath(path)
    path = os.path.join(os.sep, "__iface_virtual__", quote(uri, safe="") + ".iface")
    _VIRTUAL[path] = uri
    return path


def path_to_uri(path: str) -> str:
    """The ``file:`` URI of a path (or the URI a virtual path stands for)."""
    virtual = _VIRTUAL.get(path)
    if virtual is not None:
        return virtual
    return "file://" + quote(os.path.abspath(path).replace(os.sep, "/"), safe="/:")


# ---------------------------------------------------------------------------
# edits and offset mapping

Edit = tuple[int, int, int]  # (start, end) replaced in the older text, and the length of the new text


def map_back(edits: list[Edit], offset: int) -> int | None:
    """An offset in the newest text → the same place in the text before ``edits``; None if it is new text."""
    for start, end, length in reversed(edits):
        if offset < start:
            continue
        if offset >= start + length:
            offset += (end - start) - length
        elif offset == start:
            continue
        else:
            return None
    return offset


def map_forward(edits: list[Edit], offset: int) -> int | None:
    """An offset in the text before ``edits`` → the same place now; None if that text was replaced."""
    for start, end, length in edits:
        if offset < start or (offset == start and end > start):
            continue
        if offset >= end:
            offset += length - (end - start)
        else:
            return None
    return offset


class EditLog:
    """The edits applied to a document, numbered from its opening."""

    def __init__(self) -> None:
        self._base = 0
        self._edits: list[Edit] = []
        self._lock = threading.Lock()

    @property
    def seq(self) -> int:
        """The number of edits made so far."""
        return self._base + len(self._edits)

    def append(self, edit: Edit) -> None:
        """Record an edit."""
        with self._lock:
            self._edits.append(edit)

    def between(self, first: int, last: int) -> list[Edit]:
        """The edits numbered [first, last)."""
        with self._lock:
            lo = max(first - self._base, 0)
            return self._edits[lo:max(last - self._base, lo)]

    def kept(self, first: int, last: int, length: int) -> tuple[int, int] | None:
        """(head, tail): how many characters at its start and at its end the edits [first, last) left as
        they were in a text of ``length`` characters; None when some of those edits are forgotten, or when
        they kept nothing they can tell (a whole text sent again)."""
        with self._lock:
            if first < self._base or last - self._base > len(self._edits):
                return None
            head = tail = length
            for start, end, new in self._edits[first - self._base:last - self._base]:
                head = min(head, start)
                tail = min(tail, length - end)
                length += new - (end - start)
        # a whole text sent again says nothing of where it changed: the texts are compared then
        return (head, tail) if head or tail else None

    def forget_before(self, seq: int) -> None:
        """Drop edits older than ``seq`` (no compiled version needs them any more)."""
        with self._lock:
            k = seq - self._base
            if k > 0:
                del self._edits[:k]
                self._base = seq


@dataclass(frozen=True, slots=True, eq=False)
class DocState:
    """One version of a document's text; replaced as a whole on each change."""

    text: str
    version: int
    seq: int
    encoding: str
    _index: list[LineIndex] = field(default_factory=list)

    @property
    def index(self) -> LineIndex:
        """The line index of this text (built once, on first use)."""
        if not self._index:
            self._index.append(LineIndex(self.text, self.encoding))
        return self._index[0]


class Document:
    """An open editor buffer (owned by the event loop)."""

    def __init__(self, uri: str, text: str, version: int, encoding: str) -> None:
        self.uri = uri
        self.path = uri_to_path(uri)
        self.log = EditLog()
        self.state = DocState(text, version, 0, encoding)

    def apply(self, changes: list[Any], version: int) -> None:
        """Apply LSP content changes (ranged or whole-text) in order."""
        st = self.state
        text, index = st.text, st.index
        for change in changes:
            rng = getattr(change, "range", None)
            if rng is None:
                self.log.append((0, len(text), len(change.text)))
                text = change.text
            else:
                start = index.offset(rng.start.line, rng.start.character)
                end = max(start, index.offset(rng.end.line, rng.end.character))
                self.log.append((start, end, len(change.text)))
                text = text[:start] + change.text + text[end:]
                index = index.edited(start, end, change.text, text)
                continue
            index = LineIndex(text, st.encoding)
        self.state = DocState(text, version, self.log.seq, st.encoding, [index])


