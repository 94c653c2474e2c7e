"""Formatting, document and range: the formatter of ``iface-lsp fmt`` (``iface.format``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcInternalError

from .. import convert

if TYPE_CHECKING:
    from ...text.formatter import TextEdit
    from ..server import IfaceServer


class _Formatter(Protocol):
    """What this feature uses of ``iface.format``."""

    def format_text(self, text: str) -> str: ...

    def format_range(self, text: str, start: int, end: int) -> list[TextEdit]: ...


def _formatter() -> _Formatter:
    try:
        from ...text import formatter as fmt
    except ImportError as e:
        raise JsonRpcInternalError(message="the formatter is not installed (iface.format)") from e
    return fmt


def whole(text: str, index: convert.LineIndex) -> list[lsp.TextEdit]:
    """One edit covering what the formatter changed (the common head and tail are kept).

    A document over the file size limit is left as it is (its one diagnostic says why).
    """
    from ...semantics.compile import too_large

    if too_large(text):
        return []
    fmt = _formatter()
    new = fmt.format_text(text)
    if new == text:
        return []
    head = 0
    limit = min(len(text), len(new))
    while head < limit and text[head] == new[head]:
        head += 1
    tail = 0
    while tail < limit - head and text[len(text) - 1 - tail] == new[len(new) - 1 - tail]:
        tail += 1
    return [convert.text_edit(index, head, len(text) - tail, new[head:len(new) - tail])]


def register(server: IfaceServer) -> None:
    """Register formatting handlers."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_FORMATTING)
    async def formatting(ls: IfaceServer, params: lsp.DocumentFormattingParams) -> list[lsp.TextEdit] | None:
        doc = project.docs.get(params.text_document.uri)
        if doc is None:
            return None
        state = doc.state
        return await project.run(whole, state.text, state.index) or None

    @server.feature(lsp.TEXT_DOCUMENT_RANGE_FORMATTING)
    async def range_formatting(ls: IfaceServer, params: lsp.DocumentRangeFormattingParams
                               ) -> list[lsp.TextEdit] | None:
        doc = project.docs.get(params.text_document.uri)
        if doc is None:
            return None
        state = doc.state
        index = state.index
        start = convert.offset(index, params.range.start)
        end = convert.offset(index, params.range.end)

        def run() -> list[lsp.TextEdit]:
            from ...semantics.compile import too_large

            if too_large(state.text):
                return []
            fmt = _formatter()
            edits = fmt.format_range(state.text, start, end)
            return [convert.text_edit(index, e.start, e.end, e.new_text) for e in edits]

        return await project.run(run) or None
