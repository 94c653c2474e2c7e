"""Text → model items, chunk by chunk, with syntax-error recovery.

``parse_text`` reports every syntax error of independent chunks in one pass;
inside a chunk the parser skips the offending token and goes on, and a chunk
that ends inside an open body is closed so that what was written is still
modelled. A ``ChunkCache`` keeps one document's parsed chunks so that an edit
re-parses only the chunks whose text changed.
"""

from __future__ import annotations

import re
import threading
from dataclasses import dataclass, field
from typing import Any, cast

from lark import Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedInput, UnexpectedToken
from lark.parsers.lalr_analysis import Shift

from ..model import nodes as m
from ..model.source import ORIGIN, AnchoredSpan, Span
from .chunks import Chunk, split
from .driver import Driver
from .grammar import build_parser, terminal_descriptions
from .lexer import FastScanner, ScanError
from .transform import ModelBuilder

_CLOSERS = ("RBRACE", "RPAR", "RSQB", "MORETHAN")
_MAX_ERRORS_PER_CHUNK = 20
_MAX_MERGE = 16
#: Container keywords; the base types are one terminal, already described as "a type".
_TYPE_WORDS = frozenset({"'map'", "'set'", "'list'"})


@dataclass(slots=True, eq=False)
class Problem:
    """A syntax-level finding, before it is tied to a source file."""

    code: str
    message: str
    span: Span
    data: dict[str, Any] = field(default_factory=dict)


@dataclass(slots=True, eq=False)
class ChunkResult:
    """What one chunk of text parsed to: its model items and syntax problems.

    Every span of the result is relative to ``anchor``, which is moved with the ``Chunk`` it was parsed from
    (``move_with``): moving the chunk moves every span of the result. The chunk's text is not kept: it is the
    ``length`` characters at ``base`` of the text it is placed in.
    """

    length: int
    items: tuple[Any, ...] = ()
    problems: tuple[Problem, ...] = ()
    #: The chunk ends inside an open body (the parser closed it): what follows may belong to it.
    open_at_end: bool = False
    anchor: AnchoredSpan = field(default_factory=lambda: AnchoredSpan(0, 0, ORIGIN))

    @property
    def base(self) -> int:
        """Where the chunk starts in the text."""
        return self.anchor.start

    def move_with(self, chunk: Span) -> None:
        """Put every span of the result where ``chunk`` starts, and move them with ``chunk`` from now on."""
        self.anchor.move_to_start_of(chunk)


@dataclass(slots=True, eq=False)
class ParseResult:
    """All items of a text in order, and its syntax problems."""

    items: list[Any]
    problems: list[Problem]
    chunks: list[ChunkResult] = field(default_factory=list)

    def broken_ranges(self) -> list[tuple[int, int]]:
        """(start, end) offsets of the chunks that have a syntax error."""
        return [(c.base, c.base + c.length) for c in self.chunks
                if any(p.code == "syntax-error" for p in c.problems)]


class _ChunkParser:
    """The shared LALR parser with the model builder inline; one chunk at a time."""

    def __init__(self) -> None:
        self.builder = ModelBuilder()
        self.parser = build_parser(self.builder)
        self.lock = threading.Lock()
        self.driver: Driver | None = None

    def parse_clean(self, text: str, docs: dict[int, str], anchors: tuple[Span, ...] = ()) -> ChunkResult | None:
        """What a text that has no problem at all parses to, read by the fast scanner; else None. Its spans
        are relative to ``anchors`` (where its chunks start: they are never moved), else to the result."""
        with self.lock:
            return self._parse_clean(text, docs, anchors)

    def _parse_clean(self, text: str, docs: dict[int, str], anchors: tuple[Span, ...]) -> ChunkResult | None:
        if self.driver is None:
            self.driver = Driver(self.parser, self.builder, FastScanner(self.parser))
        b = self.builder
        result = ChunkResult(len(text))
        b.reset(docs, list(anchors) or [result.anchor])
        try:
            items = self.driver.parse(text)
        except (ScanError, UnexpectedInput, RecursionError):
            return None
        if b.problems or not isinstance(items, list):
            return None
        result.items = tuple(items)
        return result

    def parse(self, text: str, docs: dict[int, str]) -> ChunkResult:
        """Parse one chunk; its spans are kept relative to its table, so that it can be moved later.

        A chunk without a problem is read by the fast scanner, as a clean file is: in a file with one
        error every other chunk is clean. Only a chunk with a problem goes through lark's error recovery.
        """
        with self.lock:
            return self._parse_clean(text, docs, ()) or self._parse(text, docs)

    def parse_recovering(self, text: str, docs: dict[int, str]) -> ChunkResult:
        """Parse one chunk with lark's lexer and error recovery only (what ``parse`` falls back to)."""
        with self.lock:
            return self._parse(text, docs)

    def _parse(self, text: str, docs: dict[int, str]) -> ChunkResult:
        b = self.builder
        result = ChunkResult(len(text))
        b.reset(docs, [result.anchor])
        problems: list[Problem] = []
        open_at_end = False
        errors = 0

        def record(start: int, end: int, message: str, data: dict[str, Any] | None = None) -> None:
            nonlocal errors
            # one report per chunk: what follows inside it is usually an echo of the first
            if not problems:
                problems.append(Problem("syntax-error", message, b.span(start, max(end, start)), data or {}))
            errors += 1

        def on_error(e: UnexpectedInput) -> bool:
            nonlocal open_at_end
            if errors >= _MAX_ERRORS_PER_CHUNK:
                return False
            if isinstance(e, UnexpectedToken) and e.token.type == "$END":
                open_at_end = True
                record(len(text), len(text), _describe_eof(e))
                return _close(e, len(text))
            if isinstance(e, UnexpectedCharacters):
                pos = _char_pos(e)
                ros = ros_type_path(text, pos)
                if ros is not None:
                    start, end, package, name = ros
                    record(start, end, _describe_ros_type(package, name),
                           {"ros_type": f"{package}/{name}", "package": package, "replacement": f"{package}.{name}"})
                    return True
                record(pos, pos + 1, _describe_chars(text, e))
                return True
            assert isinstance(e, UnexpectedToken)
            tok = e.token
            record(tok.start_pos, tok.end_pos, _describe_token(e))
            _resync(e)
            return True

        # with the model builder inline, lark returns the builder's list of items, not a tree
        parsed: object
        try:
            parsed = self.parser.parse(text, on_error=on_error)
        except UnexpectedInput as e:
            parsed = []
            if not problems:
                pos = getattr(e, "pos_in_stream", None) or len(text)
                problems.append(Problem("syntax-error", "cannot parse this definition", b.span(pos, pos)))
        except RecursionError:
            parsed = []
            problems.append(Problem("nesting-too-deep", "the text is nested too deeply to read", b.span(0, 0)))
        for code, message, span in b.problems:
            problems.append(Problem(code, message, span))
        result.items = tuple(parsed) if isinstance(parsed, list) else ()
        result.problems = tuple(problems)
        result.open_at_end = open_at_end
        return result


def _unwind_to_body(ip: Any) -> bool:
    """Pop the parser's stacks back to just after the innermost open ``{``.

    The parser then expects the members of that body again, so what follows a
    broken member is still modelled. False when no body is open.
    """
    ps = ip.parser_state
    values = ps.value_stack
    for i in range(len(values) - 1, -1, -1):
        v = values[i]
        if isinstance(v, Token) and v.type == "LBRACE":
            keep = i + 1
            if keep < len(values) and _is_members(values[keep]):
                keep += 1  # the members parsed so far stay
            del values[keep:]
            del ps.state_stack[keep + 1:]
            return True
    return False


_MEMBER_TYPES = (m.Field, m.Const, m.Function, m.Section, m.EnumValue)


def _is_members(v: Any) -> bool:
    """True for a finished member, or the list of members lark builds for ``_member*``."""
    if isinstance(v, _MEMBER_TYPES):
        return True
    return isinstance(v, Tree) and str(v.data).startswith("__")


def _resync(e: UnexpectedToken) -> None:
    """Panic-mode recovery: drop the broken member; a ``}`` still closes its body."""
    ip = e.interactive_parser
    if not _unwind_to_body(ip):
        return
    if e.token.type == "RBRACE" and _would_accept(ip.parser_state, "RBRACE"):
        ip.feed_token(e.token)


def _close(e: UnexpectedToken, end: int) -> bool:
    """Feed closing tokens until the chunk can end; False when that is impossible."""
    ip = e.interactive_parser
    ps = ip.parser_state
    for _ in range(256):
        if _would_accept(ps, "$END"):
            return True
        for closer in _CLOSERS:
            if _would_accept(ps, closer):
                ip.feed_token(Token(closer, "", start_pos=end, end_pos=end))
                break
        else:
            if not _unwind_to_body(ip):
                return False
    return False


def _would_accept(ps: Any, terminal: str) -> bool:
    """Whether the parser would take ``terminal`` now (shift it, or end the input), after the reductions it
    causes; found on the state numbers alone, without copying the parser (lark's ``accepts()`` copies its
    stacks for each terminal: quadratic when an unclosed ``[`` × N leaves them N deep)."""
    states = ps.parse_conf.parse_table.states
    end_state = ps.parse_conf.end_state
    stack = ps.state_stack
    depth = len(stack)  # the states below ``depth`` are the parser's; ``pushed`` are the simulated ones above
    pushed: list[int] = []
    while True:
        action = states[pushed[-1] if pushed else stack[depth - 1]].get(terminal)
        if action is None:
            return False
        kind, arg = action
        if kind is Shift:
            return terminal != "$END"
        size = len(arg.expansion)
        if size <= len(pushed):
            del pushed[len(pushed) - size:]
        else:
            depth -= size - len(pushed)
            pushed.clear()
        if depth <= 0:
            return False
        _, goto = states[pushed[-1] if pushed else stack[depth - 1]][arg.origin.name]
        pushed.append(goto)
        if terminal == "$END" and goto == end_state:
            return True


def _expected(names: set[str] | frozenset[str]) -> str:
    desc = terminal_descriptions(chunk_parser().parser)
    words = {desc.get(n, n.lower()) for n in names}
    if "IDENTIFIER" in names:
        # LALR lookaheads merged from generic contexts; after a type a name is what is meant
        words -= {"'&'", "'>'", "','", "'<='"}
    if words & _TYPE_WORDS:
        words -= _TYPE_WORDS
        words.add("a type")
    if "a type" in words:
        words.discard("a name")
        words.discard("a type")
        words.add("a type or name")
    ordered = sorted(words)
    if len(ordered) > 8:
        ordered = ordered[:8] + ["…"]
    return ", ".join(ordered)


def _describe_token(e: UnexpectedToken) -> str:
    tok = e.token
    desc = terminal_descriptions(chunk_parser().parser).get(tok.type, tok.type.lower())
    shown = repr(str(tok)) if desc.startswith(("a ", "an ")) else desc
    return f"unexpected {shown}; expected {_expected(e.expected)}"


def _describe_eof(e: UnexpectedToken) -> str:
    closers = [terminal_descriptions(chunk_parser().parser)[c] for c in _CLOSERS if c in e.expected]
    if closers:
        return f"{closers[0]} expected: the body is still open here"
    return f"unexpected end of definition; expected {_expected(e.expected)}"


def _char_pos(e: UnexpectedCharacters) -> int:
    """Where the unlexable character is."""
    # lark declares ``pos_in_stream = None`` on UnexpectedInput; UnexpectedCharacters always sets the lexer position
    return cast(int, e.pos_in_stream)


def _describe_chars(text: str, e: UnexpectedCharacters) -> str:
    pos = _char_pos(e)
    c = text[pos]
    if c in "\"'":
        return "unterminated string: a string must close on the line it opens"
    if text.startswith("/*", pos):
        return "unterminated comment: '/*' has no closing '*/'"
    return f"unexpected character {c!r}"


_IDENT_BEFORE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*$")
_IDENT_AFTER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def ros_type_path(text: str, slash: int) -> tuple[int, int, str, str] | None:
    """``pkg/Type`` (ROS 2's spelling of another package's type) around a ``/`` at ``slash``:
    (start, end, pkg, Type), or None."""
    if not text.startswith("/", slash) or text.startswith(("//", "/*"), slash):
        return None
    before = _IDENT_BEFORE.search(text, 0, slash)
    after = _IDENT_AFTER.match(text, slash + 1)
    if before is None or after is None:
        return None
    return before.start(), after.end(), before.group(), after.group()


def _describe_ros_type(package: str, name: str) -> str:
    return (f"'{package}/{name}' is how ROS 2 writes a type of another package; .iface writes "
            f"`{package}.{name}`, with `include \"{package}.iface\"` (the package imported by "
            f"`iface-lsp import --from ros2`) or `external {package}` (a package iface does not describe)")


_parser: _ChunkParser | None = None


def chunk_parser() -> _ChunkParser:
    """The process-wide chunk parser, built on first use."""
    global _parser
    if _parser is None:
        _parser = _ChunkParser()
    return _parser


class ChunkCache:
    """Parsed chunks of one document, reused across its versions by their text."""

    def __init__(self) -> None:
        #: The last text and its chunks: the next version's text is cut again only around what changed.
        self.split: tuple[str, list[Chunk]] | None = None
        #: The last version's chunk results, placed in ``split``'s text.
        self.results: list[ChunkResult] = []

    def pool(self) -> dict[str, list[ChunkResult]]:
        """The last version's chunk results by their text (made when a whole text is parsed again)."""
        pool: dict[str, list[ChunkResult]] = {}
        if self.split is not None:
            last = self.split[0]
            for r in self.results:
                pool.setdefault(last[r.base:r.base + r.length], []).append(r)
        return pool


def parse_text(text: str, cache: ChunkCache | None = None) -> ParseResult:
    """Parse a whole text; with ``cache``, unchanged chunks are not parsed again.

    Without a cache the text is first parsed in one piece with the fast scanner
    (``lexer.py``; the path for a clean file); only if that finds a problem is it
    parsed chunk by chunk with lark's lexer, which keeps every independent syntax
    error and models the rest.
    """
    parser = chunk_parser()
    pool = cache.pool() if cache is not None else {}
    chunks = split(text, cache.split if cache is not None else None)
    if cache is not None:
        cache.split = (text, chunks)
    if cache is None and not chunks[-1].unterminated:
        docs: dict[int, str] = {}
        for ch in chunks:
            docs.update(ch.doc_map(ch.start))
        clean = parser.parse_clean(text, docs, tuple(Span(ch.start, ch.start) for ch in chunks))
        if clean is not None:
            return ParseResult(list(clean.items), [], [clean])
    results: list[ChunkResult] = []
    i = 0
    n = len(chunks)
    while i < n:
        ch = chunks[i]
        ctext = text[ch.start:ch.end]
        same = pool.get(ctext)
        r = same.pop() if same else None
        if r is None and ch.unterminated:
            r = ChunkResult(len(ctext))
            r.problems = (Problem("syntax-error", "unterminated comment: '/*' has no closing '*/', so the rest of "
                                  "the file is comment", AnchoredSpan.relative(0, 2, r.anchor)),)
        if r is None:
            r = parser.parse(ctext, ch.doc_map())
        # a chunk left open is joined with what follows it now, whether it was parsed now or in an
        # earlier version: what follows may have changed, and the answer must be a fresh parse's
        if r.open_at_end and i + 1 < n and not chunks[i + 1].unterminated:
            merged = _merge(parser, text, chunks, i)
            if merged is not None:
                r, i = merged
        r.move_with(ch)
        results.append(r)
        i += 1
    if cache is not None:
        cache.results = results
    items: list[Any] = []
    problems: list[Problem] = []
    for r in results:
        items.extend(r.items)
        problems.extend(r.problems)
    return ParseResult(items, problems, results)


def _merge(parser: _ChunkParser, text: str, chunks: list[Chunk], i: int) -> tuple[ChunkResult, int] | None:
    """Join chunk ``i`` with the following ones until the join parses cleanly."""
    first = chunks[i]
    docs = dict(first.doc_map())
    for j in range(i + 1, min(len(chunks), i + 1 + _MAX_MERGE)):
        nxt = chunks[j]
        if nxt.unterminated:
            return None
        docs.update(nxt.doc_map(nxt.start - first.start))
        r = parser.parse(text[first.start:nxt.end], docs)
        if not r.problems:
            return r, j
        if not r.open_at_end:
            return None
    return None

