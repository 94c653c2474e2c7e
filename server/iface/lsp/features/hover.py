"""Hover: what the name under the cursor is, and what it becomes on every target."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ...model import nodes as m
    from ...semantics.compile import Compilation
    from ..server import IfaceServer
    from ..versions import DocumentView


def register(server: IfaceServer) -> None:
    """Register the hover handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_HOVER)
    async def hover(ls: IfaceServer, params: lsp.HoverParams) -> lsp.Hover | None:
        pos = params.position

        def answer(view: DocumentView) -> lsp.Hover | None:
            from ...semantics.query import locate
            from ..describe import describe

            iface = view.iface
            offset = view.offset(pos.line, pos.character)
            if iface is None or offset is None:
                return None
            hit = locate(iface, offset)
            if hit is None:
                return None
            text = describe(hit, iface, view.ver.text, [])
            rng = view.range(hit.span)
            if text is None or rng is None:
                return None
            if hit.wiring is not None and view.comp is not None:
                text += _node_part(view.comp, hit.wiring)
            return lsp.Hover(contents=convert.markdown(text), range=rng)

        return await project.view(params.text_document.uri, answer)


def _node_part(comp: Compilation, wiring: m.Wiring) -> str:
    """What the generated component node (the rclpy target) makes of a wiring, as a hover section."""
    from ...nodes.component import handler_lines, node_spec

    spec = node_spec(comp)
    if spec is None:
        return ""
    lines = handler_lines(spec, wiring)
    if not lines:
        return ""
    return (f"\n\n**In the generated node** (`{spec.class_name}` in `{spec.package}/{spec.package}/node.py`, target rclpy)\n"
            + "\n".join(f"- {x}" for x in lines))
