"""The baseline for lsp_bench.py: a minimal pygls server that re-parses the whole text with lark on every change.

It is what a first language server would do: the change handler parses the
document with the repository grammar (LALR, as iface does) and publishes the
syntax error, if any, before it returns, so a request sent behind an edit waits
for the parse. Run: ``python bench/naive_server.py`` (stdio).
"""

from __future__ import annotations

import sys
from pathlib import Path

from lark import Lark
from lark.exceptions import UnexpectedInput
from lsprotocol import types as lsp
from pygls.lsp.server import LanguageServer

GRAMMAR = Path(__file__).resolve().parents[1] / "grammar.lark"
KEYWORDS = ["message", "struct", "enum", "service", "action", "publishes", "subscribes", "u8", "float64", "string"]

server = LanguageServer("naive-iface", "0")
parser = Lark(GRAMMAR.read_text(encoding="utf-8"), parser="lalr", lexer="contextual", propagate_positions=True)


def check(uri: str, version: int | None) -> None:
    """Parse the whole document and publish its first syntax error."""
    doc = server.workspace.get_text_document(uri)
    diagnostics: list[lsp.Diagnostic] = []
    try:
        parser.parse(doc.source)
    except UnexpectedInput as e:
        line, col = max(e.line - 1, 0), max(e.column - 1, 0)
        pos = lsp.Position(line=line, character=col)
        diagnostics.append(lsp.Diagnostic(range=lsp.Range(start=pos, end=pos), message=str(e).splitlines()[0]))
    server.text_document_publish_diagnostics(
        lsp.PublishDiagnosticsParams(uri=uri, diagnostics=diagnostics, version=version))


@server.feature(lsp.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: LanguageServer, params: lsp.DidOpenTextDocumentParams) -> None:
    check(params.text_document.uri, params.text_document.version)


@server.feature(lsp.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: LanguageServer, params: lsp.DidChangeTextDocumentParams) -> None:
    check(params.text_document.uri, params.text_document.version)


@server.feature(lsp.TEXT_DOCUMENT_COMPLETION)
def completion(ls: LanguageServer, params: lsp.CompletionParams) -> lsp.CompletionList:
    return lsp.CompletionList(is_incomplete=False, items=[lsp.CompletionItem(label=k) for k in KEYWORDS])


@server.feature(lsp.TEXT_DOCUMENT_HOVER)
def hover(ls: LanguageServer, params: lsp.HoverParams) -> lsp.Hover | None:
    doc = ls.workspace.get_text_document(params.text_document.uri)
    word = doc.word_at_position(params.position)
    return lsp.Hover(contents=lsp.MarkupContent(kind=lsp.MarkupKind.Markdown, value=f"`{word}`")) if word else None


if __name__ == "__main__":
    server.start_io()
    sys.exit(0)
