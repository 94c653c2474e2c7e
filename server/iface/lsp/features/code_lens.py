"""Code lens on each message, service and action: who publishes/subscribes (provides/calls) it, and Generate."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import DocumentView

WORDS = {"publishes": "published by", "subscribes": "subscribed by", "provides": "provided by",
         "calls": "called by"}


def register(server: IfaceServer) -> None:
    """Register the code lens handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_CODE_LENS)
    async def code_lens(ls: IfaceServer, params: lsp.CodeLensParams) -> list[lsp.CodeLens] | None:
        def answer(view: DocumentView) -> list[lsp.CodeLens] | None:
            from ...model import nodes as m

            iface = view.iface
            if iface is None:
                return None
            index = project.workspace_index
            facts = index.all_facts() if index is not None else []
            users: dict[str, dict[str, list[str]]] = {}
            for f in facts:
                for w in f.wirings:
                    if w.target is not None and w.target[0] == view.ver.path:
                        users.setdefault(w.target[1], {}).setdefault(w.direction, []).append(w.component)
            out: list[lsp.CodeLens] = []
            for d in iface.definitions:
                if not isinstance(d, (m.Struct, m.Service, m.Action)) or d.kind in ("configuration", "state"):
                    continue
                rng = view.range(d.name_span)
                if rng is None:
                    continue
                who = users.get(d.name, {})
                parts = [f"{WORDS[k]} {', '.join(sorted(set(v)))}" for k, v in sorted(who.items())]
                title = " · ".join(parts) if parts else ("not wired in the workspace" if isinstance(d, m.Struct)
                                                         else "provided under its own name")
                out.append(lsp.CodeLens(range=rng, command=convert.command(title, "")))
                out.append(lsp.CodeLens(range=rng, command=convert.command("Generate", "iface.generate",
                                                                           [view.uri])))
            return out or None

        return await project.view(params.text_document.uri, answer, fresh=True)
