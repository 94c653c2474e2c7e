"""Rename with prepareRename: definitions, fields, constants and enum values, across files.

A new name that is not an identifier, is a keyword, or clashes with a name in
the same scope is refused with a message (an error answer, as LSP asks).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcInvalidRequest

from ..server import Refusal
from .navigation import home_of, locate, referring_interfaces

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import DocumentView


class RenameRefused(Refusal, JsonRpcInvalidRequest):
    """A rename the server refuses, with the reason as the message."""


def register(server: IfaceServer) -> None:
    """Register rename handlers."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_PREPARE_RENAME)
    async def prepare(ls: IfaceServer, params: lsp.PrepareRenameParams) -> lsp.PrepareRenamePlaceholder | None:
        pos = params.position

        def answer(view: DocumentView) -> lsp.PrepareRenamePlaceholder | None:
            from ...model import nodes as m
            from ...model.source import Span
            from ...semantics.query import local_name_span, renameable

            hit = locate(view, pos.line, pos.character)
            if hit is None or not renameable(hit):
                return None
            span = local_name_span(hit.node) if isinstance(hit.node, m.NamedType) else hit.span
            if hit.kind == "value":
                name = getattr(hit.target, "name", "")
                span = Span(span.end - len(name), span.end)
            rng = view.range(span)
            if rng is None:
                return None
            return lsp.PrepareRenamePlaceholder(range=rng, placeholder=view.text[
                view.index.offset(rng.start.line, rng.start.character):view.index.offset(rng.end.line, rng.end.character)])

        return await project.view(params.text_document.uri, answer, fresh=True)

    @server.feature(lsp.TEXT_DOCUMENT_RENAME)
    async def rename(ls: IfaceServer, params: lsp.RenameParams) -> lsp.WorkspaceEdit | None:
        pos = params.position
        if project.workspace_index is not None:
            await project.workspace_index.ready.wait()

        def answer(view: DocumentView) -> lsp.WorkspaceEdit | None:
            from ...semantics.query import references, rename_problem, renameable
            from .. import convert

            hit = locate(view, pos.line, pos.character)
            if hit is None or not renameable(hit) or view.iface is None:
                raise RenameRefused("there is nothing to rename here")
            home = view.iface if hit.kind == "field" else home_of(view, hit.target)
            if home is None:
                raise RenameRefused("the definition of this name is not found")
            problem = rename_problem(params.new_name, hit, home)
            if problem is not None:
                raise RenameRefused(problem)
            changes: dict[str, list[lsp.TextEdit]] = {}
            if hit.kind == "field":
                found = [(view.iface, hit.span)]
            else:
                users = referring_interfaces(view, home, getattr(hit.target, "name", ""))
                found = [(r.interface, r.span) for r in references(hit.target, home, users)]
            for iface, span in found:
                loc = view.location(iface.source, span)
                if loc is None:
                    continue
                changes.setdefault(loc.uri, []).append(lsp.TextEdit(range=loc.range, new_text=params.new_name))
            return convert.workspace_edit(changes) if changes else None

        return await project.view(params.text_document.uri, answer, fresh=True)
