"""Selection ranges: name → member → section → definition → file."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import DocumentView


def register(server: IfaceServer) -> None:
    """Register the selection range handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_SELECTION_RANGE)
    async def selection(ls: IfaceServer, params: lsp.SelectionRangeParams) -> list[lsp.SelectionRange] | None:
        def answer(view: DocumentView) -> list[lsp.SelectionRange] | None:
            from ...semantics.query import selection_chain

            if view.iface is None:
                return None
            out = []
            for pos in params.positions:
                offset = view.ver.index.offset(pos.line, pos.character)
                out.append(convert.selection_range(view.ver.index,
                                                   selection_chain(view.iface, offset, len(view.ver.text))))
            return out

        return await project.view(params.text_document.uri, answer, fresh=True)
