"""Go to definition and type definition, find references, document highlight (across included files)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lsprotocol import types as lsp

if TYPE_CHECKING:
    from ...model.nodes import Interface
    from ...model.source import Span
    from ..server import IfaceServer
    from ..versions import DocumentView


def locate(view: DocumentView, line: int, character: int) -> Any:
    """The hit under an LSP position of the current text, or None."""
    from ...semantics.query import locate as find

    iface = view.iface
    offset = view.offset(line, character)
    if iface is None or offset is None:
        return None
    return find(iface, offset)


def location(view: DocumentView, iface: Interface, span: Span) -> lsp.Location | None:
    """A location in the viewed document or in another file."""
    return view.location(iface.source, span)


def home_of(view: DocumentView, target: object) -> Interface | None:
    """The interface that defines ``target`` (this file, an included one, or one in the workspace)."""
    from ...semantics.query import defining_interface

    iface = view.iface
    if iface is None:
        return None
    found = defining_interface([iface, *iface.included.values()], target)
    if found is None:
        found = defining_interface(view.project.open_interfaces(), target)
    return found


def workspace_interfaces(view: DocumentView) -> list[Interface]:
    """Every interface the server knows: the workspace index and the open documents."""
    index = view.project.workspace_index
    if index is not None:
        return index.all_interfaces()
    return view.project.open_interfaces()


def referring_interfaces(view: DocumentView, home: Interface, name: str) -> list[Interface]:
    """The interfaces the server knows (the workspace index and the open documents) that may use ``name``
    defined in ``home``."""
    index = view.project.workspace_index
    if index is not None:
        return index.referring(home.path, name)
    return view.project.open_interfaces()


def register(server: IfaceServer) -> None:
    """Register navigation handlers."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls: IfaceServer, params: lsp.DefinitionParams) -> list[lsp.Location] | None:
        pos = params.position

        def answer(view: DocumentView) -> list[lsp.Location] | None:
            from ...model import nodes as m

            hit = locate(view, pos.line, pos.character)
            if hit is None:
                return None
            if hit.kind == "include" and isinstance(hit.node, m.Include) and hit.node.resolved:
                from ..documents import path_to_uri
                start = lsp.Position(line=0, character=0)
                return [lsp.Location(uri=path_to_uri(hit.node.resolved), range=lsp.Range(start=start, end=start))]
            target = hit.target
            if target is None or not hasattr(target, "name_span"):
                return None
            home = home_of(view, target)
            loc = location(view, home, target.name_span) if home is not None else None
            return [loc] if loc is not None else None

        return await project.view(params.text_document.uri, answer)

    @server.feature(lsp.TEXT_DOCUMENT_TYPE_DEFINITION)
    async def type_definition(ls: IfaceServer, params: lsp.TypeDefinitionParams) -> list[lsp.Location] | None:
        pos = params.position

        def answer(view: DocumentView) -> list[lsp.Location] | None:
            from ...model import nodes as m
            from ...model.walk import named_types, resolve_typedefs

            hit = locate(view, pos.line, pos.character)
            if hit is None:
                return None
            node = hit.target if hit.kind in ("field", "const", "definition") else hit.node
            t = getattr(node, "type", None) if not isinstance(node, m.NamedType) else node
            if isinstance(node, m.Typedef):
                t = node.type
            if t is None:
                return None
            out: list[lsp.Location] = []
            for named in named_types(resolve_typedefs(t)):
                target = named.target
                if isinstance(target, m.Typedef):
                    final = resolve_typedefs(named)
                    target = final.target if isinstance(final, m.NamedType) else target
                if target is None:
                    continue
                home = home_of(view, target)
                loc = location(view, home, target.name_span) if home is not None else None
                if loc is not None:
                    out.append(loc)
            return out or None

        return await project.view(params.text_document.uri, answer)

    @server.feature(lsp.TEXT_DOCUMENT_REFERENCES)
    async def references(ls: IfaceServer, params: lsp.ReferenceParams) -> list[lsp.Location] | None:
        pos = params.position
        if project.workspace_index is not None:
            await project.workspace_index.ready.wait()

        def answer(view: DocumentView) -> list[lsp.Location] | None:
            from ...semantics.query import references as refs

            hit = locate(view, pos.line, pos.character)
            if hit is None or hit.target is None or hit.kind in ("base-type", "topic", "section", "function"):
                return None
            home = home_of(view, hit.target)
            if home is None:
                return None
            name = getattr(hit.target, "name", "")
            found = refs(hit.target, home, referring_interfaces(view, home, name), params.context.include_declaration)
            out = [location(view, r.interface, r.span) for r in found]
            return [loc for loc in out if loc is not None] or None

        return await project.view(params.text_document.uri, answer)

    @server.feature(lsp.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    async def highlight(ls: IfaceServer, params: lsp.DocumentHighlightParams) -> list[lsp.DocumentHighlight] | None:
        pos = params.position

        def answer(view: DocumentView) -> list[lsp.DocumentHighlight] | None:
            from ...semantics.query import highlights

            hit = locate(view, pos.line, pos.character)
            if hit is None or view.iface is None:
                return None
            out = []
            for span in highlights(view.iface, hit):
                rng = view.range(span)
                if rng is not None:
                    kind = lsp.DocumentHighlightKind.Write if span == getattr(hit.target, "name_span", None) \
                        else lsp.DocumentHighlightKind.Read
                    out.append(lsp.DocumentHighlight(range=rng, kind=kind))
            return out or None

        return await project.view(params.text_document.uri, answer)
