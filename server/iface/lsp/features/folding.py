"""Folding ranges: definitions, sections, block comments, runs of includes."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import DocumentView


def register(server: IfaceServer) -> None:
    """Register the folding range handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_FOLDING_RANGE)
    async def folding(ls: IfaceServer, params: lsp.FoldingRangeParams) -> list[lsp.FoldingRange] | None:
        def answer(view: DocumentView) -> list[lsp.FoldingRange] | None:
            from ...semantics.compile import too_large
            from ...semantics.query import folding_spans

            if view.iface is None or too_large(view.ver.text):
                return None
            out = [convert.folding_range(view.ver.index, span, kind)
                   for span, kind in folding_spans(view.iface, view.ver.text)]
            return [r for r in out if r is not None]

        return await project.view(params.text_document.uri, answer, fresh=True)
