"""Document sync and diagnostics: compile on open and change, publish what ``check`` finds.

Compiles run on the model thread after a short delay (edits in a burst are
compiled once); files that include a changed file are re-checked, and
diagnostics of included files are published on those files.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from ..documents import uri_to_path

if TYPE_CHECKING:
    from ..server import IfaceServer


def register(server: IfaceServer) -> None:
    """Register document sync handlers."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: IfaceServer, params: lsp.DidOpenTextDocumentParams) -> None:
        doc = params.text_document
        project.open(doc.uri, doc.text, doc.version)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: IfaceServer, params: lsp.DidChangeTextDocumentParams) -> None:
        project.change(params.text_document.uri, list(params.content_changes), params.text_document.version)

    @server.feature(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: IfaceServer, params: lsp.DidCloseTextDocumentParams) -> None:
        project.close(params.text_document.uri)

    @server.feature(lsp.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: IfaceServer, params: lsp.DidSaveTextDocumentParams) -> None:
        if project.workspace_index is not None:
            project.workspace_index.refresh(uri_to_path(params.text_document.uri))

    @server.feature(lsp.WORKSPACE_DID_CHANGE_WATCHED_FILES)
    def watched(ls: IfaceServer, params: lsp.DidChangeWatchedFilesParams) -> None:
        for change in params.changes:
            path = uri_to_path(change.uri)
            if change.uri in project.docs:
                continue
            project.file_changed_on_disk(path)
            if project.workspace_index is not None:
                project.workspace_index.refresh(path)

