"""Document symbols (an outline grouped by the seven sets) and workspace symbols."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import DocumentView

MAX_WORKSPACE_SYMBOLS = 500


def register(server: IfaceServer) -> None:
    """Register symbol handlers."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def document_symbols(ls: IfaceServer, params: lsp.DocumentSymbolParams
                               ) -> list[lsp.DocumentSymbol] | list[lsp.SymbolInformation] | None:
        caps = ls.client_capabilities.text_document
        hierarchical = bool(caps and caps.document_symbol and caps.document_symbol.hierarchical_document_symbol_support)

        def answer(view: DocumentView) -> list[lsp.DocumentSymbol] | list[lsp.SymbolInformation] | None:
            from ...semantics.query import outline

            if view.iface is None:
                return None
            groups = outline(view.iface)
            if hierarchical:
                return [convert.document_symbol(view.ver.index, g) for g in groups]
            return convert.flat_symbols(view.uri, view.ver.index, groups)

        return await project.view(params.text_document.uri, answer, fresh=True)

    @server.feature(lsp.WORKSPACE_SYMBOL)
    async def workspace_symbols(ls: IfaceServer, params: lsp.WorkspaceSymbolParams) -> list[lsp.WorkspaceSymbol]:
        if project.workspace_index is not None:
            await project.workspace_index.ready.wait()
        matches = _matcher(params.query)

        def answer() -> list[lsp.WorkspaceSymbol]:
            from ..documents import path_to_uri
            from ..index import WorkspaceIndex

            index = project.workspace_index
            interfaces = index.all_interfaces() if isinstance(index, WorkspaceIndex) else project.open_interfaces()
            out: list[lsp.WorkspaceSymbol] = []
            for iface in interfaces:
                line_index = project.index_of(iface.source)
                for d in iface.definitions:
                    if not matches(d.name):
                        continue
                    out.append(convert.workspace_symbol(d.name, d.kind, path_to_uri(iface.path), line_index,
                                                        d.name_span, iface.name))
                    if len(out) >= MAX_WORKSPACE_SYMBOLS:
                        return out
            return out

        return await project.run(answer)


def _matcher(query: str) -> Callable[[str], bool]:
    """A test that the letters of ``query`` appear in a name in order, ignoring case (one regular expression:
    the workspace has thousands of names)."""
    if not query:
        return lambda name: True
    # "a[^b]*b[^c]*c": each letter is the first one after the previous, so nothing is tried twice
    parts = [re.escape(query[0])] + [f"[^{re.escape(c)}]*{re.escape(c)}" for c in query[1:]]
    pattern = re.compile("".join(parts), re.IGNORECASE)
    return lambda name: pattern.search(name) is not None
