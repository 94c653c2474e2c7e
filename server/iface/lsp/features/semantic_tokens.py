"""Semantic tokens: keywords, comments, strings and numbers from the text; names from the model.

Names are coloured by what they are (a message, an enum, a field, a constant),
which a TextMate grammar cannot know; clients without a grammar (Neovim) get
keywords and literals too.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert

if TYPE_CHECKING:
    from ...model.nodes import Interface
    from ..server import IfaceServer
    from ..versions import DocumentView

TOKEN_TYPES = ["namespace", "type", "struct", "enum", "interface", "enumMember", "property", "variable",
               "keyword", "comment", "string", "number", "decorator", "function"]
TOKEN_MODIFIERS = ["declaration", "readonly", "documentation", "defaultLibrary"]
_T = {name: i for i, name in enumerate(TOKEN_TYPES)}
_M = {name: 1 << i for i, name in enumerate(TOKEN_MODIFIERS)}
LEGEND = lsp.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=TOKEN_MODIFIERS)

_LEX = re.compile(r"""
    (?P<comment>//[^\n]*|\#[^\n]*|/\*.*?(?:\*/|\Z))
  | (?P<string>"(?:[^"\\\n]|\\.)*"?|'(?:[^'\\\n]|\\.)*'?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<number>[+-]?(?:0x[0-9A-Fa-f]+|[0-9]+\.?[0-9]*(?:[eE][+-]?[0-9]+)?))
""", re.S | re.X)

KIND_TOKEN = {"struct": "struct", "message": "struct", "union": "struct", "exception": "struct",
              "configuration": "struct", "state": "struct", "enum": "enum", "senum": "enum",
              "service": "interface", "action": "interface", "typedef": "type", "const": "variable"}


def _keywords() -> tuple[frozenset[str], frozenset[str]]:
    from ...model.nodes import BASE_ALIASES
    from ...semantics.query import RESERVED

    return RESERVED - frozenset(BASE_ALIASES), frozenset(BASE_ALIASES)


def tokens(iface: Interface, text: str) -> dict[int, tuple[int, int, int]]:
    """start → (end, token type, modifiers) for the whole text."""
    from ...model import nodes as m
    from ...model.walk import bodies
    from ...semantics.query import local_name_span, named_references, value_references

    keywords, base = _keywords()
    out: dict[int, tuple[int, int, int]] = {}
    for mt in _LEX.finditer(text):
        kind = mt.lastgroup
        s, e = mt.start(), mt.end()
        if kind == "comment":
            doc = _M["documentation"] if text.startswith("/**", s) else 0
            out[s] = (e, _T["comment"], doc)
        elif kind == "string":
            out[s] = (e, _T["string"], 0)
        elif kind == "number":
            out[s] = (e, _T["number"], 0)
        else:
            word = mt.group()
            if word in base:
                out[s] = (e, _T["type"], _M["defaultLibrary"])
            elif word in keywords:
                out[s] = (e, _T["keyword"], 0)

    def put(span: m.Span, token: str, mods: int = 0) -> None:
        s, e = span.start, span.end
        if e > s:
            out[s] = (e, _T[token], mods)

    decl = _M["declaration"]
    definitions = (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const)
    for item in iface.items:
        if isinstance(item, (m.ComponentDecl, m.SystemDecl)):
            put(item.name_span, "namespace", decl)
        elif isinstance(item, m.Instance):
            put(item.name_span, "variable", decl)
            put(item.component_span, "namespace")
            for a in item.annotations:
                put(m.Span(a.span.start, a.span.start + len(a.key)), "decorator")
        elif isinstance(item, m.Wiring):
            for a in item.annotations:
                put(m.Span(a.span.start, a.span.start + len(a.key)), "decorator")
        if not isinstance(item, definitions):
            continue
        d = item
        put(d.name_span, KIND_TOKEN.get(d.kind, "type"), decl | (_M["readonly"] if d.kind == "const" else 0))
        for a in getattr(d, "annotations", ()):
            put(m.Span(a.span.start, a.span.start + len(a.key)), "decorator")
        if isinstance(d, m.Enum):
            for v in d.values:
                put(v.name_span, "enumMember", decl | _M["readonly"])
        if isinstance(d, m.Service):
            for fn in d.functions:
                put(fn.name_span, "function", decl)
        if isinstance(d, (m.Service, m.Action)):
            for sec in d.sections:
                put(sec.name_span, "keyword")
        for _, fields, consts in bodies(d):
            for f in fields:
                put(f.name_span, "property", decl)
                for a in f.annotations:
                    put(m.Span(a.span.start, a.span.start + len(a.key)), "decorator")
            for c in consts:
                put(c.name_span, "variable", decl | _M["readonly"])
    for t in named_references(iface):
        target = t.target
        token = KIND_TOKEN.get(getattr(target, "kind", ""), "type")
        local = local_name_span(t)
        if t.qualifier:
            put(m.Span(t.span.start, local.start - 1), "namespace")
        put(local, token)
    for ref in value_references(iface):
        out[ref.span.start] = (ref.span.end, _T["enumMember"] if "." in str(ref.value) else _T["variable"],
                               _M["readonly"])
    return out


def encode(found: dict[int, tuple[int, int, int]], index: convert.LineIndex, text: str,
           start: int = 0, end: int | None = None) -> list[int]:
    """LSP relative encoding, one token per line piece (multi-line comments are split)."""
    end = len(text) if end is None else end
    data: list[int] = []
    prev_line = prev_col = 0
    last_end = -1
    for s in sorted(found):
        e, ttype, mods = found[s]
        if s < last_end or e <= start or s >= end:
            continue
        last_end = e
        while s < e:
            nl = text.find("\n", s, e)
            piece_end = e if nl < 0 else nl
            if piece_end > s:
                line, col = index.position(s)
                length = index.units(text[s:piece_end].rstrip("\r"))
                if length > 0:
                    data.extend((line - prev_line, col - prev_col if line == prev_line else col, length, ttype, mods))
                    prev_line, prev_col = line, col
            if nl < 0:
                break
            s = nl + 1
    return data


def register(server: IfaceServer) -> None:
    """Register semantic token handlers (full and range); none for a document over the file size limit."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, LEGEND)
    async def full(ls: IfaceServer, params: lsp.SemanticTokensParams) -> lsp.SemanticTokens | None:
        def answer(view: DocumentView) -> lsp.SemanticTokens | None:
            from ...semantics.compile import too_large

            if view.iface is None or too_large(view.ver.text):
                return None
            return convert.semantic_tokens(encode(tokens(view.iface, view.ver.text), view.ver.index, view.ver.text))

        return await project.view(params.text_document.uri, answer, fresh=True)

    @server.feature(lsp.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE, LEGEND)
    async def in_range(ls: IfaceServer, params: lsp.SemanticTokensRangeParams) -> lsp.SemanticTokens | None:
        def answer(view: DocumentView) -> lsp.SemanticTokens | None:
            from ...semantics.compile import too_large

            if view.iface is None or too_large(view.ver.text):
                return None
            index = view.ver.index
            a = convert.offset(index, params.range.start)
            b = convert.offset(index, params.range.end)
            return convert.semantic_tokens(encode(tokens(view.iface, view.ver.text), index, view.ver.text, a, b))

        return await project.view(params.text_document.uri, answer, fresh=True)
