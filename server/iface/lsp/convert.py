"""The one place where model values become LSP values.

Positions: the model counts code points; LSP ends lines at ``\\n``, ``\\r\\n``
or ``\\r`` and counts characters in the negotiated encoding (UTF-16 code units
unless the client agreed to UTF-32 or UTF-8). ``LineIndex`` converts both ways,
astral characters included; every builder below takes one.
"""

from __future__ import annotations

import re
from array import array
from bisect import bisect_right
from itertools import repeat
from operator import sub

UTF8, UTF16, UTF32 = "utf-8", "utf-16", "utf-32"
_BREAK = re.compile(r"\r\n|\r|\n")


#: Line starts are kept in blocks of about this many lines, each an array of the starts relative to the block's
#: first one (2 bytes each while a block spans less than 64 KiB of text) and the offset of that first line: an
#: edit copies one block and moves the later ones by their offsets alone.
_BLOCK = 1024
_REST = range(_BLOCK - 1)


def _pack(starts: list[int]) -> array[int]:
    """Starts of one block, already relative to its first line, in as few bytes each as they fit."""
    last = starts[-1]
    return array("H" if last < 1 << 16 else "I" if last < 1 << 32 else "q", starts)


def _block(starts: list[int], base: int) -> array[int]:
    """The starts of one block relative to ``base`` (its first start), as small as they fit."""
    return _pack([x - base for x in starts] if base else starts)


def _blocked(text: str) -> tuple[list[array[int]], list[int]]:
    """The line starts of ``text`` in blocks (``LineIndex._blocks``) and where each block starts (``_shift``),
    made block by block: no int object per line of the whole text is held at once (but for a text with
    ``\r`` line breaks, read by a regular expression)."""
    blocks: list[array[int]] = []
    shift: list[int] = []
    if "\r" in text:
        ends = [m.end() for m in _BREAK.finditer(text)]
        starts = [0, *ends[:_BLOCK - 1]]
        blocks.append(_block(starts, 0))
        shift.append(0)
        for k in range(_BLOCK - 1, len(ends), _BLOCK):
            blocks.append(_block(ends[k:k + _BLOCK], ends[k]))
            shift.append(ends[k])
        return blocks, shift
    find = text.find
    i = -1  # the line break before the first line of a block (-1 for the text's first line)
    while True:
        first = i
        block = [i]  # line breaks, made starts relative to the block's first line once it is full
        append = block.append
        for _ in _REST:
            i = find("\n", i + 1)
            if i < 0:
                break
            append(i)
        blocks.append(_pack(list(map(sub, block, repeat(first)))))
        shift.append(first + 1)
        if i >= 0:
            i = find("\n", i + 1)
        if i < 0:
            return blocks, shift


class LineIndex:
    """Line starts of one text, and conversions between offsets and (line, units).

    An edited text's index is made from the last one (``edited``) in time that follows the edit: the
    starts are blocks of lines, and the blocks after the edit are shared, moved by a number each.
    ``_blocks[k]`` holds the starts of block ``k`` relative to its first line, which starts at ``_shift[k]``
    and is line ``_lines[k]``.
    """

    __slots__ = ("text", "encoding", "ascii", "_blocks", "_shift", "_lines")

    def __init__(self, text: str, encoding: str = UTF16) -> None:
        self.text = text
        self.encoding = encoding
        self.ascii = text.isascii()
        self._blocks, self._shift = _blocked(text)
        self._lines = list(range(0, _BLOCK * len(self._blocks), _BLOCK))

    @property
    def starts(self) -> list[int]:
        """Offsets at which each line starts."""
        return [x + d for b, d in zip(self._blocks, self._shift) for x in b]

    @property
    def line_count(self) -> int:
        """The number of lines (a text ending with a newline has an empty last line)."""
        return self._lines[-1] + len(self._blocks[-1])

    def _start(self, line: int) -> int:
        k = bisect_right(self._lines, line) - 1
        return self._blocks[k][line - self._lines[k]] + self._shift[k]

    def _line_of(self, offset: int) -> tuple[int, int]:
        """(line, its start) of an offset inside the text."""
        k = bisect_right(self._shift, offset) - 1
        d = self._shift[k]
        block = self._blocks[k]
        i = bisect_right(block, offset - d) - 1
        return self._lines[k] + i, block[i] + d

    def edited(self, start: int, end: int, new: str, text: str) -> LineIndex:
        """The index of ``text``: this index's text with [start, end) replaced by ``new``."""
        if "\r" in new or not self.ascii and "\r" in text or len(self._blocks) < 2:
            return LineIndex(text, self.encoding)
        if "\r" in self.text[max(start - 1, 0):end + 1]:
            return LineIndex(text, self.encoding)
        out = LineIndex.__new__(LineIndex)
        out.text = text
        out.encoding = self.encoding
        out.ascii = self.ascii and new.isascii()
        first, _ = self._line_of(start)
        last, _ = self._line_of(end)
        k1 = bisect_right(self._lines, first) - 1
        k2 = bisect_right(self._lines, last) - 1
        delta = len(new) - (end - start)
        # the starts of blocks k1..k2 relative to block k1's first line (which the edit does not move)
        base = self._shift[k1]
        merged = list(self._blocks[k1])
        for k in range(k1 + 1, k2 + 1):
            merged.extend(x + (self._shift[k] - base) for x in self._blocks[k])
        lo = first - self._lines[k1] + 1
        hi = last - self._lines[k1] + 1
        added = []
        i = new.find("\n")
        while i >= 0:
            added.append(start - base + i + 1)
            i = new.find("\n", i + 1)
        merged[lo:hi] = added
        merged[lo + len(added):] = [x + delta for x in merged[lo + len(added):]]
        heads = [base + merged[i] for i in range(0, len(merged), _BLOCK)]
        pieces = [_block(merged[i:i + _BLOCK], merged[i]) for i in range(0, len(merged), _BLOCK)]
        out._blocks = [*self._blocks[:k1], *pieces, *self._blocks[k2 + 1:]]
        out._shift = [*self._shift[:k1], *heads, *(d + delta for d in self._shift[k2 + 1:])]
        lines = self._lines[:k1]
        n = self._lines[k1]
        for p in pieces:
            lines.append(n)
            n += len(p)
        moved = n - (self._lines[k2] + len(self._blocks[k2]))
        lines.extend(x + moved for x in self._lines[k2 + 1:])
        out._lines = lines
        return out

    def line_end(self, line: int) -> int:
        """Offset of the end of ``line``, before its line break."""
        if line + 1 < self.line_count:
            end = self._start(line + 1) - 1
            if end > self._start(line) and self.text[end] == "\n" and self.text[end - 1] == "\r":
                end -= 1
            return end
        return len(self.text)

    def units(self, chars: str) -> int:
        """Length of ``chars`` in the negotiated encoding."""
        if self.encoding == UTF32 or chars.isascii():
            return len(chars)
        if self.encoding == UTF16:
            return len(chars) + sum(1 for c in chars if ord(c) > 0xFFFF)
        return len(chars.encode("utf-8", errors="surrogatepass"))

    def position(self, offset: int) -> tuple[int, int]:
        """(line, character in the negotiated encoding) of a code point offset."""
        offset = max(0, min(offset, len(self.text)))
        line, start = self._line_of(offset)
        if self.ascii or self.encoding == UTF32:
            return line, offset - start
        return line, self.units(self.text[start:offset])

    def offset(self, line: int, character: int) -> int:
        """Code point offset of an LSP position, clamped to its line."""
        if line < 0:
            return 0
        if line >= self.line_count:
            return len(self.text)
        start = self._start(line)
        end = self.line_end(line)
        character = max(character, 0)
        if self.ascii or self.encoding == UTF32:
            return min(start + character, end)
        used = 0
        i = start
        while i < end and used < character:
            used += self.units(self.text[i])
            if used > character:  # inside a surrogate pair or a multi-byte character
                break
            i += 1
        return i


class LineIndexes:
    """Line indexes of other files' texts, by source, at most ``limit`` of them (find references
    answers from every file of a workspace)."""

    def __init__(self, limit: int = 4096) -> None:
        self.limit = limit
        self._by_id: dict[int, tuple[Source, LineIndex]] = {}

    def __len__(self) -> int:
        return len(self._by_id)

    def get(self, source: Source, encoding: str) -> LineIndex:
        """The line index of ``source``'s text, built on first use."""
        cached = self._by_id.get(id(source))
        if cached is not None and cached[0] is source and cached[1].encoding == encoding:
            return cached[1]
        if len(self._by_id) >= self.limit:
            self._by_id.clear()
        index = LineIndex(source.text, encoding)
        self._by_id[id(source)] = (source, index)
        return index

    def retain(self, paths: set[str]) -> None:
        """Keep only the indexes of files in ``paths``."""
        self._by_id = {k: v for k, v in self._by_id.items() if v[0].path in paths}


# ---------------------------------------------------------------------------
# lsprotocol builders (imported here only: the rest of iface never sees them)

from typing import TYPE_CHECKING, Any  # noqa: E402

from lsprotocol import types as lsp  # noqa: E402

if TYPE_CHECKING:
    from ..model.diagnostics import Diagnostic
    from ..model.source import Source, Span
    from ..semantics.query import Symbol

ENCODINGS = {UTF8: lsp.PositionEncodingKind.Utf8, UTF16: lsp.PositionEncodingKind.Utf16,
             UTF32: lsp.PositionEncodingKind.Utf32}


def position(index: LineIndex, offset: int) -> lsp.Position:
    """The LSP position of a code point offset."""
    line, character = index.position(offset)
    return lsp.Position(line=line, character=character)


def offset(index: LineIndex, pos: lsp.Position) -> int:
    """The code point offset of an LSP position."""
    return index.offset(pos.line, pos.character)


def range_(index: LineIndex, start: int, end: int) -> lsp.Range:
    """The LSP range of [start, end)."""
    return lsp.Range(start=position(index, start), end=position(index, end))


def span_range(index: LineIndex, span: Span) -> lsp.Range:
    """The LSP range of a model span."""
    return range_(index, span.start, span.end)


def location(uri: str, index: LineIndex, span: Span) -> lsp.Location:
    """An LSP location."""
    return lsp.Location(uri=uri, range=span_range(index, span))


_SEVERITY = {1: lsp.DiagnosticSeverity.Error, 2: lsp.DiagnosticSeverity.Warning,
             3: lsp.DiagnosticSeverity.Information, 4: lsp.DiagnosticSeverity.Hint}


def _jsonable(value: Any) -> Any:
    if isinstance(value, (str, int, float, bool)) or value is None:
        return value
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return str(value)


def diagnostic(d: Diagnostic, index: LineIndex, uri_of: Any, index_of: Any) -> lsp.Diagnostic:
    """An LSP diagnostic; ``uri_of(path)`` and ``index_of(source)`` place related locations."""
    related = [
        lsp.DiagnosticRelatedInformation(
            location=lsp.Location(uri=uri_of(r.source.path), range=span_range(index_of(r.source), r.span)),
            message=r.message)
        for r in d.related
    ]
    data = _jsonable({**d.data, "code": d.code}) if d.data else None
    tags = [lsp.DiagnosticTag.Deprecated] if d.code == "deprecated-syntax" else None
    return lsp.Diagnostic(range=span_range(index, d.span), message=d.message, severity=_SEVERITY[int(d.severity)],
                          code=d.code, source="iface", related_information=related or None, data=data, tags=tags)


def live_finding(code: str, severity: str, message: str, index: LineIndex, start: int, end: int) -> lsp.Diagnostic:
    """A finding of ``verify`` (the running system against the file) at ``start..end``."""
    return lsp.Diagnostic(range=range_(index, start, end), message=message, code=code, source="iface verify",
                          severity=lsp.DiagnosticSeverity.Error if severity == "error"
                          else lsp.DiagnosticSeverity.Warning)


def internal_error(message: str) -> lsp.Diagnostic:
    """A diagnostic at the top of a file saying the server failed on it."""
    return lsp.Diagnostic(range=lsp.Range(start=lsp.Position(line=0, character=0), end=lsp.Position(line=0, character=0)),
                          message=message, severity=lsp.DiagnosticSeverity.Error, code="internal-error",
                          source="iface")


def markdown(text: str) -> lsp.MarkupContent:
    """Markdown content."""
    return lsp.MarkupContent(kind=lsp.MarkupKind.Markdown, value=text)


def hover(text: str, index: LineIndex, span: Span) -> lsp.Hover:
    """A Markdown hover over ``span``."""
    return lsp.Hover(contents=markdown(text), range=span_range(index, span))


def text_edit(index: LineIndex, start: int, end: int, new_text: str) -> lsp.TextEdit:
    """Replace [start, end) with ``new_text``."""
    return lsp.TextEdit(range=range_(index, start, end), new_text=new_text)


def workspace_edit(changes: dict[str, list[lsp.TextEdit]]) -> lsp.WorkspaceEdit:
    """Text edits by document URI."""
    return lsp.WorkspaceEdit(changes=changes)


_SYMBOL_KINDS = {
    "group": lsp.SymbolKind.Namespace, "struct": lsp.SymbolKind.Struct, "message": lsp.SymbolKind.Struct,
    "union": lsp.SymbolKind.Struct, "exception": lsp.SymbolKind.Class, "configuration": lsp.SymbolKind.Object,
    "state": lsp.SymbolKind.Object, "service": lsp.SymbolKind.Interface, "action": lsp.SymbolKind.Interface,
    "enum": lsp.SymbolKind.Enum, "senum": lsp.SymbolKind.Enum, "typedef": lsp.SymbolKind.TypeParameter,
    "const": lsp.SymbolKind.Constant, "field": lsp.SymbolKind.Field, "enum-value": lsp.SymbolKind.EnumMember,
    "section": lsp.SymbolKind.Module, "function": lsp.SymbolKind.Method, "publishes": lsp.SymbolKind.Event,
    "subscribes": lsp.SymbolKind.Event, "provides": lsp.SymbolKind.Event, "calls": lsp.SymbolKind.Event,
    "instance": lsp.SymbolKind.Object,
}


def symbol_kind(kind: str) -> lsp.SymbolKind:
    """The LSP symbol kind of a model kind."""
    return _SYMBOL_KINDS.get(kind, lsp.SymbolKind.Variable)


def document_symbol(index: LineIndex, s: Symbol) -> lsp.DocumentSymbol:
    """A hierarchical outline entry."""
    rng = span_range(index, s.span)
    sel = span_range(index, s.name_span)
    if not (s.span.start <= s.name_span.start and s.name_span.end <= s.span.end):
        sel = lsp.Range(start=rng.start, end=rng.start)
    return lsp.DocumentSymbol(name=s.name or "?", kind=symbol_kind(s.kind), range=rng, selection_range=sel,
                              detail=s.detail or None,
                              children=[document_symbol(index, c) for c in s.children] or None)


def flat_symbols(uri: str, index: LineIndex, symbols: list[Symbol], container: str | None = None) -> list[lsp.SymbolInformation]:
    """The outline as flat SymbolInformation (clients without hierarchy support)."""
    out: list[lsp.SymbolInformation] = []
    for s in symbols:
        if s.kind != "group":
            out.append(lsp.SymbolInformation(name=s.name, kind=symbol_kind(s.kind),
                                             location=location(uri, index, s.span), container_name=container))
        out.extend(flat_symbols(uri, index, s.children, s.name if s.kind != "group" else container))
    return out


def workspace_symbol(name: str, kind: str, uri: str, index: LineIndex, span: Span, container: str) -> lsp.WorkspaceSymbol:
    """A workspace-wide symbol."""
    return lsp.WorkspaceSymbol(name=name, kind=symbol_kind(kind), location=location(uri, index, span),
                               container_name=container)


_FOLD = {"comment": lsp.FoldingRangeKind.Comment, "imports": lsp.FoldingRangeKind.Imports, "region": None}


def folding_range(index: LineIndex, span: Span, kind: str) -> lsp.FoldingRange | None:
    """A folding range over whole lines (None for a one-line span)."""
    first, _ = index.position(span.start)
    last, _ = index.position(max(span.start, span.end - 1))
    if last <= first:
        return None
    return lsp.FoldingRange(start_line=first, end_line=last, kind=_FOLD.get(kind))


def selection_range(index: LineIndex, chain: list[Span]) -> lsp.SelectionRange:
    """A selection range from the innermost span out."""
    parent: lsp.SelectionRange | None = None
    for s in reversed(chain):
        parent = lsp.SelectionRange(range=span_range(index, s), parent=parent)
    assert parent is not None
    return parent


COMPLETION_KINDS = {
    "keyword": lsp.CompletionItemKind.Keyword, "snippet": lsp.CompletionItemKind.Snippet,
    "base-type": lsp.CompletionItemKind.TypeParameter, "struct": lsp.CompletionItemKind.Struct,
    "message": lsp.CompletionItemKind.Struct, "union": lsp.CompletionItemKind.Struct,
    "exception": lsp.CompletionItemKind.Class, "configuration": lsp.CompletionItemKind.Struct,
    "state": lsp.CompletionItemKind.Struct, "enum": lsp.CompletionItemKind.Enum,
    "senum": lsp.CompletionItemKind.Enum, "typedef": lsp.CompletionItemKind.TypeParameter,
    "service": lsp.CompletionItemKind.Interface, "action": lsp.CompletionItemKind.Interface,
    "const": lsp.CompletionItemKind.Constant, "annotation": lsp.CompletionItemKind.Property,
    "topic": lsp.CompletionItemKind.Value, "field": lsp.CompletionItemKind.Field,
    "enum-value": lsp.CompletionItemKind.EnumMember, "section": lsp.CompletionItemKind.Module,
    "external": lsp.CompletionItemKind.Module,
}


def completion_item(label: str, kind: str, detail: str = "", doc: str = "", insert: str | None = None,
                    snippet: bool = False, sort: str | None = None, edit: tuple[LineIndex, int, int] | None = None
                    ) -> lsp.CompletionItem:
    """One completion; ``snippet`` only when the client accepts snippets; ``edit`` replaces a range."""
    text_edit_: lsp.TextEdit | None = None
    if edit is not None:
        index, start, end = edit
        text_edit_ = lsp.TextEdit(range=range_(index, start, end), new_text=insert if insert is not None else label)
        insert = None
    return lsp.CompletionItem(
        label=label, kind=COMPLETION_KINDS.get(kind, lsp.CompletionItemKind.Text), detail=detail or None,
        documentation=markdown(doc) if doc else None, insert_text=insert, text_edit=text_edit_,
        insert_text_format=lsp.InsertTextFormat.Snippet if snippet else None, sort_text=sort)


def completion_list(items: list[lsp.CompletionItem], incomplete: bool = False) -> lsp.CompletionList:
    """The completion answer."""
    return lsp.CompletionList(is_incomplete=incomplete, items=items)


def command(title: str, name: str, arguments: list[Any] | None = None) -> lsp.Command:
    """A command reference."""
    return lsp.Command(title=title, command=name, arguments=arguments)


def code_lens(index: LineIndex, span: Span, cmd: lsp.Command) -> lsp.CodeLens:
    """A code lens above ``span``."""
    return lsp.CodeLens(range=span_range(index, span), command=cmd)


def code_action(title: str, kind: str, edit: lsp.WorkspaceEdit | None = None, cmd: lsp.Command | None = None,
                diagnostics: list[lsp.Diagnostic] | None = None, preferred: bool = False) -> lsp.CodeAction:
    """A quick fix, refactoring or source action."""
    return lsp.CodeAction(title=title, kind=kind, edit=edit, command=cmd, diagnostics=diagnostics or None,
                          is_preferred=preferred or None)


def semantic_tokens(data: list[int]) -> lsp.SemanticTokens:
    """Encoded semantic tokens."""
    return lsp.SemanticTokens(data=data)
