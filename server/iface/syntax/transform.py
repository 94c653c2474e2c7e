"""Parse tree → model, run inline by the LALR parser (no tree is built).

Each method receives the children of one grammar rule (tokens and the model
objects made for sub-rules) and returns a model object. Offsets come straight
from the tokens; every Span made is relative to its chunk's anchor, so that a
cached chunk can be moved later by moving the anchor.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from typing import Any

from lark import Token

from ..model import nodes as m
from ..model.source import AnchoredSpan, Span, SpanTable

#: Containers nested deeper than this are refused (and not modelled).
MAX_TYPE_DEPTH = 64

_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "\\": "\\", '"': '"', "'": "'", "0": "\0"}
_HEX = frozenset("0123456789abcdefABCDEF")
#: What stands in a string for an escape that names no character.
REPLACEMENT = "\ufffd"

#: A literal problem: (offset in the literal's text, length, message).
LiteralProblem = tuple[int, int, str]


def decode_literal(text: str, problems: list[LiteralProblem] | None = None) -> str:
    """The value of a quoted Thrift literal, with backslash escapes decoded.

    ``\\uD83D\\uDE00`` (a UTF-16 surrogate pair) is one character. A lone surrogate
    escape stands for no character: it becomes U+FFFD and is reported in ``problems``
    (offsets into ``text``). A raw surrogate becomes U+FFFD too, so that no value
    of the model holds text that cannot be written as UTF-8.
    """
    body = text[1:-1]
    if "\\" not in body and not _has_surrogate(body):
        return body
    out: list[str] = []
    i, n = 0, len(body)
    while i < n:
        c = body[i]
        if c == "\\" and i + 1 < n:
            e = body[i + 1]
            if e in _ESCAPES:
                out.append(_ESCAPES[e])
                i += 2
                continue
            if e == "u" and i + 6 <= n and _HEX.issuperset(body[i + 2:i + 6]):
                code = int(body[i + 2:i + 6], 16)
                if 0xD800 <= code <= 0xDBFF and body.startswith("\\u", i + 6) and i + 12 <= n \
                        and _HEX.issuperset(body[i + 8:i + 12]) and 0xDC00 <= int(body[i + 8:i + 12], 16) <= 0xDFFF:
                    low = int(body[i + 8:i + 12], 16)
                    out.append(chr(0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00)))
                    i += 12
                    continue
                if 0xD800 <= code <= 0xDFFF:
                    if problems is not None:
                        half = "high" if code <= 0xDBFF else "low"
                        problems.append((i + 1, 6, f"'\\u{body[i + 2:i + 6]}' is a lone {half} UTF-16 surrogate: "
                                         "it stands for no character and cannot be written as UTF-8 "
                                         "(a character above U+FFFF is written as a pair, "
                                         "like '\\uD83D\\uDE00')"))
                    out.append(REPLACEMENT)
                else:
                    out.append(chr(code))
                i += 6
                continue
        elif "\ud800" <= c <= "\udfff":
            c = REPLACEMENT  # a raw surrogate in the text: reported once for the whole text by compile
        out.append(c)
        i += 1
    return "".join(out)


def _has_surrogate(text: str) -> bool:
    return any("\ud800" <= c <= "\udfff" for c in text) if not text.isascii() else False


def parse_int(text: str) -> int | None:
    """An INT token's value (decimal or hex, optionally signed); None beyond 64 bits (see ``m.INT_LITERAL``)."""
    if len(text) < 19 and text.isdigit():  # plain decimal (the INT pattern's digits are ASCII): within 64 bits
        return int(text)
    negative = text.startswith("-")
    digits = text.lstrip("+-")
    hexa = digits[:2].lower() == "0x"
    digits = (digits[2:] if hexa else digits).lstrip("0") or "0"
    # longer than 2**64 in its base: refused before int() (Python limits int-from-str to 4300 digits)
    if len(digits) > (16 if hexa else 20):
        return None
    value = int(digits, 16 if hexa else 10)
    value = -value if negative else value
    lo, hi = m.INT_LITERAL
    return value if lo <= value <= hi else None


def parse_double(text: str) -> float | None:
    """A DOUBLE token's value; None when it is beyond float64 (it would be infinity)."""
    value = float(text)
    return value if math.isfinite(value) else None


def shorten(text: str, limit: int = 24) -> str:
    """A long literal cut in the middle for a message, with its length."""
    if len(text) <= limit:
        return text
    return f"{text[:limit // 2]}…{text[-limit // 2:]} ({len(text)} characters)"


def _text(tok: Token) -> str:
    """A token's text as a plain string, one object for every equal one (names and keywords repeat a lot)."""
    return sys.intern(str(tok))


class _Tagged(tuple):
    """A (tag, payload, span) triple passed up from helper rules."""


class ModelBuilder:
    """Callbacks for every rule of grammar.lark; see ``parse.ChunkParser``."""

    def __init__(self) -> None:
        self.docs: dict[int, str] = {}
        self.problems: list[tuple[str, str, Span]] = []
        self._depth: dict[int, int] = {}
        self.reset({}, SpanTable())

    def reset(self, docs: dict[int, str], table: SpanTable) -> None:
        """Start a new chunk whose doc comments are ``docs`` (by the offset they document).

        Every node's spans go to ``table``, new and empty, relative to where the chunk starts.
        """
        self.table = table
        self._offsets: list[int] = table.offsets
        #: ``span(start, end)``: record a node's span [start, end) in the table; its index, which the node keeps
        self.span: Callable[[int, int], Any] = table.add
        self.docs = docs
        self.problems = []
        self._depth = {}

    def tok_span(self, tok: Token) -> Any:
        """Record the span of one token of a node; its index."""
        return self.span(tok.start_pos, tok.end_pos)

    def _start(self, x: Any) -> int:
        """Where a token or a node made for this chunk starts (read from the table: no span is made)."""
        return x.start_pos if type(x) is Token else self._offsets[2 * x._k]

    def _end(self, x: Any) -> int:
        """Where a token or a node made for this chunk ends."""
        return x.end_pos if type(x) is Token else self._offsets[2 * x._k + 1]

    def anchored(self, start: int, end: int) -> AnchoredSpan:
        """A span object of its own (a problem's, a field id's), relative to the chunk likewise."""
        return AnchoredSpan(start, end, self.table)

    # ---- document ----------------------------------------------------------
    def start(self, children: list[Any]) -> list[Any]:
        return children

    # ---- headers ---------------------------------------------------------------
    def include(self, c: list[Any]) -> m.Include:
        lit = c[1]
        return m.Include(self._decode(lit), self.span(c[0].start_pos, lit.end_pos), self.tok_span(lit), _t=self.table)

    def cpp_include(self, c: list[Any]) -> m.Include:
        inc = self.include(c)
        inc.cpp = True
        return inc

    def namespace(self, c: list[Any]) -> m.Namespace:
        scope, name = c[1], c[2]
        ann = c[3] if len(c) > 3 else ()
        value = self._decode(name) if name.type == "LITERAL" else _text(name)
        end = self._end(ann[-1]) if ann else name.end_pos
        return m.Namespace(_text(scope), value, self.span(c[0].start_pos, end), ann, _t=self.table)

    def component(self, c: list[Any]) -> m.ComponentDecl:
        name = c[1]
        version = None
        ann: Sequence[m.Annotation] = ()
        end = name.end_pos
        for x in c[2:]:
            if isinstance(x, Token) and x.type == "LITERAL":
                version = self._decode(x)
                end = x.end_pos
            elif isinstance(x, list):
                ann = x
                end = self._ann_end
        return m.ComponentDecl(_text(name), self.span(c[0].start_pos, end), self.tok_span(name),
                               version, ann, self.docs.get(c[0].start_pos), _t=self.table)

    def system(self, c: list[Any]) -> m.SystemDecl:
        name = c[1]
        version = None
        ann: Sequence[m.Annotation] = ()
        end = name.end_pos
        for x in c[2:]:
            if isinstance(x, Token) and x.type == "LITERAL":
                version = self._decode(x)
                end = x.end_pos
            elif isinstance(x, list):
                ann = x
                end = self._ann_end
        return m.SystemDecl(_text(name), self.span(c[0].start_pos, end), self.tok_span(name),
                            version, ann, self.docs.get(c[0].start_pos), _t=self.table)

    def instance(self, c: list[Any]) -> m.Instance:
        name, component = c[1], c[3]
        ann = c[4] if len(c) > 4 else ()
        end = self._ann_end if ann else component.end_pos
        return m.Instance(_text(name), _text(component), self.span(c[0].start_pos, end), self.tok_span(name),
                          self.tok_span(component), ann, self.docs.get(c[0].start_pos), _t=self.table)

    def external(self, c: list[Any]) -> m.External:
        return m.External(_text(c[1]), self.span(c[0].start_pos, c[1].end_pos), _t=self.table)

    def wiring(self, c: list[Any]) -> m.Wiring:
        d, name, topic = c[0], c[1], c[2]
        ann = c[3] if len(c) > 3 else ()
        end = self._ann_end if ann else topic.end_pos
        return m.Wiring(_text(d), m.NamedType(_text(name), self.tok_span(name), _t=self.table), self._decode(topic),
                        self.span(d.start_pos, end), self.tok_span(topic), ann,
                        self.docs.get(d.start_pos), _t=self.table)

    # ---- definitions -------------------------------------------------------------
    def const(self, c: list[Any]) -> m.Const:
        kw, ftype, name = c[0], self._type(c[1]), c[2]
        value = c[4]
        return m.Const(_text(name), ftype, value, self.span(kw.start_pos, self._end(value)),
                       self.tok_span(name), (), self.docs.get(kw.start_pos), _t=self.table)

    member_const = const

    def typedef(self, c: list[Any]) -> m.Typedef:
        kw, ftype, name = c[0], self._type(c[1]), c[2]
        ann = c[3] if len(c) > 3 and isinstance(c[3], list) else ()
        end = self._ann_end if ann else name.end_pos
        return m.Typedef(_text(name), ftype, self.span(kw.start_pos, end), self.tok_span(name), ann,
                         self.docs.get(kw.start_pos), _t=self.table)

    def enum_value(self, c: list[Any]) -> m.EnumValue:
        name = c[0]
        value = None
        ann: Sequence[m.Annotation] = ()
        end = name.end_pos
        for x in c[1:]:
            if isinstance(x, Token) and x.type == "INT":
                value = self._int(x)
                end = x.end_pos
            elif isinstance(x, list):
                ann = x
                end = self._ann_end
        ev = m.EnumValue(_text(name), value if value is not None else 0, self.span(name.start_pos, end),
                         self.tok_span(name), value is not None, ann, self.docs.get(name.start_pos), _t=self.table)
        return ev

    def enum(self, c: list[Any]) -> m.Enum:
        kw, name = c[0], c[1]
        values = [x for x in c if isinstance(x, m.EnumValue)]
        nxt = 0
        for v in values:
            if not v.explicit:
                v.value = nxt
            nxt = v.value + 1
        ann, end = self._body_tail(c)
        return m.Enum(_text(name), self.span(kw.start_pos, end), self.tok_span(name), values, ann,
                      self.docs.get(kw.start_pos), _t=self.table)

    def senum(self, c: list[Any]) -> m.Senum:
        kw, name = c[0], c[1]
        values = [m.Value("string", sys.intern(self._decode(t)), self.tok_span(t), _text(t), _t=self.table)
                  for t in c[3:] if isinstance(t, Token) and t.type == "LITERAL"]
        ann, end = self._body_tail(c)
        return m.Senum(_text(name), self.span(kw.start_pos, end), self.tok_span(name), values, ann,
                       self.docs.get(kw.start_pos), _t=self.table)

    def struct(self, c: list[Any]) -> m.Struct:
        kw, name = c[0], c[1]
        fields = [x for x in c if isinstance(x, m.Field)]
        consts = [x for x in c if isinstance(x, m.Const)]
        ann, end = self._body_tail(c)
        return m.Struct(_text(kw), _text(name), self.span(kw.start_pos, end), self.tok_span(name),
                        fields, consts, ann, self.docs.get(kw.start_pos), _t=self.table)

    def section(self, c: list[Any]) -> m.Section:
        name = c[0]
        fields = [x for x in c if isinstance(x, m.Field)]
        consts = [x for x in c if isinstance(x, m.Const)]
        end = next(x.end_pos for x in reversed(c) if isinstance(x, Token) and x.type == "RBRACE")
        return m.Section(_text(name), self.span(name.start_pos, end), self.tok_span(name), fields, consts,
                         False, self.docs.get(name.start_pos), _t=self.table)

    def service(self, c: list[Any]) -> m.Service:
        kw, name = c[0], c[1]
        at = self.span(0, 0)
        svc = m.Service(_text(name), at, self.tok_span(name), doc=self.docs.get(kw.start_pos), _t=self.table)
        if len(c) > 3 and isinstance(c[2], Token) and c[2].type == "EXTENDS":
            svc.extends = m.NamedType(_text(c[3]), self.tok_span(c[3]), _t=self.table)
        for x in c:
            if isinstance(x, m.Function):
                svc.functions.append(x)
            elif isinstance(x, m.Field):
                svc.flat_fields.append(x)
            elif isinstance(x, m.Section):
                svc.sections.append(x)
            elif isinstance(x, m.Const):
                svc.consts.append(x)
        svc.annotations, end = self._body_tail(c)
        self.table.put(at, kw.start_pos, end)
        return svc

    def action(self, c: list[Any]) -> m.Action:
        kw, name = c[0], c[1]
        at = self.span(0, 0)
        act = m.Action(_text(name), at, self.tok_span(name), doc=self.docs.get(kw.start_pos), _t=self.table)
        for x in c:
            if isinstance(x, m.Field):
                act.flat_fields.append(x)
            elif isinstance(x, m.Section):
                act.sections.append(x)
            elif isinstance(x, m.Const):
                act.consts.append(x)
        act.annotations, end = self._body_tail(c)
        self.table.put(at, kw.start_pos, end)
        return act

    def throws(self, c: list[Any]) -> _Tagged:
        return _Tagged(("throws", [x for x in c if isinstance(x, m.Field)]))

    def function(self, c: list[Any]) -> m.Function:
        i = 0
        oneway = False
        first = c[0]
        if isinstance(first, Token) and first.type == "ONEWAY":
            oneway = True
            i = 1
        ret = c[i]
        returns = None if isinstance(ret, Token) and ret.type == "VOID" else self._type(ret)
        name = c[i + 1]
        params: list[m.Field] = []
        throws: list[m.Field] = []
        ann: Sequence[m.Annotation] = ()
        end = name.end_pos
        for x in c[i + 2:]:
            if isinstance(x, m.Field):
                params.append(x)
            elif isinstance(x, Token) and x.type == "RPAR":
                end = x.end_pos
            elif isinstance(x, _Tagged):
                throws = x[1]
            elif isinstance(x, list):
                ann = x
                end = self._ann_end
        start = self._start(first)
        return m.Function(_text(name), returns, self.span(start, end), self.tok_span(name), params,
                          throws, oneway, ann, self.docs.get(start), _t=self.table)

    # ---- fields --------------------------------------------------------------------
    def field(self, c: list[Any]) -> m.Field:
        # [id INT] [requiredness] type [&] name [default Value] [annotations]
        i = 0
        first = c[0]
        fid = fid_span = None
        if type(first) is Token and first.type == "INT":
            fid = self._int(first)
            fid_span = self.anchored(first.start_pos, first.end_pos)
            i = 1
        start = self._start(first)
        req = None
        x = c[i]
        if type(x) is Token and (x.type == "REQUIRED" or x.type == "OPTIONAL"):
            req = _text(x)
            i += 1
        ftype = self._type(c[i])
        i += 1
        reference = False
        if type(c[i]) is Token and c[i].type == "AMP":
            reference = True
            i += 1
        name = c[i]
        end = name.end_pos
        default = None
        ann: Sequence[m.Annotation] = ()
        for x in c[i + 1:]:
            if type(x) is list:
                ann = x
                end = self._ann_end
            else:
                default = x
                end = self._end(x)
        return m.Field(_text(name), ftype, self.span(start, end), self.tok_span(name), fid, fid_span,
                       req, default, ann, self.docs.get(start), reference, _t=self.table)

    flat_field = field

    # ---- types ---------------------------------------------------------------------
    def _type(self, x: Any) -> Any:
        """The model type of a type child: lone BASE_TYPE and IDENTIFIER tokens arrive as tokens."""
        if type(x) is not Token:
            return x
        if x.type == "BASE_TYPE":
            return m.BaseType(m.BASE_ALIASES[str(x)], self.tok_span(x), _text(x), _t=self.table)
        return m.NamedType(_text(x), self.tok_span(x), _t=self.table)

    def bounded_string(self, c: list[Any]) -> m.BaseType:
        kw, bound = c[0], c[1]
        t = m.BaseType(m.BASE_ALIASES[str(kw)], self.span(kw.start_pos, bound.end_pos), _text(kw),
                       self._int(bound), _t=self.table)
        if t.name not in m.STRING_TYPES:
            self.problems.append(("bounds-misuse", f"only string and wstring take a bound, not {kw}", t.span))
        return t

    def cpp_type(self, c: list[Any]) -> None:
        return None

    def _container(self, t: Any, *elements: Any) -> Any:
        depth = max(self._depth.get(id(e), 0) for e in elements) + 1
        if depth > MAX_TYPE_DEPTH:
            if depth == MAX_TYPE_DEPTH + 1:
                self.problems.append(("nesting-too-deep",
                                      f"containers are nested more than {MAX_TYPE_DEPTH} levels deep",
                                      t.span))
            # keep the model shallow: the too-deep type stands for its innermost part
            inner = elements[0]
            while getattr(inner, "element", None) is not None:
                inner = inner.element
            self._depth[id(inner)] = depth
            return inner
        self._depth[id(t)] = depth
        return t

    def _element_types(self, c: list[Any]) -> list[Any]:
        """The type children of a container rule (its keyword and brackets left out)."""
        return [self._type(x) for x in c
                if x is not None and (not isinstance(x, Token) or x.type in ("BASE_TYPE", "IDENTIFIER"))]

    def map_type(self, c: list[Any]) -> Any:
        types = self._element_types(c)
        end = next(x.end_pos for x in reversed(c) if isinstance(x, Token) and x.type == "MORETHAN")
        t = m.MapType(types[0], types[1], self.span(c[0].start_pos, end), _t=self.table)
        return self._container(t, types[0], types[1])

    def set_type(self, c: list[Any]) -> Any:
        types = self._element_types(c)
        end = next(x.end_pos for x in reversed(c) if isinstance(x, Token) and x.type == "MORETHAN")
        t = m.SetType(types[0], self.span(c[0].start_pos, end), _t=self.table)
        return self._container(t, types[0])

    def list_type(self, c: list[Any]) -> Any:
        types = self._element_types(c)
        end = next(x.end_pos for x in reversed(c) if isinstance(x, Token) and x.type == "MORETHAN")
        t = m.ArrayType(types[0], self.span(c[0].start_pos, end), "unbounded", None, True, _t=self.table)
        return self._container(t, types[0])

    def unbounded_array(self, c: list[Any]) -> _Tagged:
        return _Tagged(("unbounded", None, c[-1].end_pos))

    def fixed_array(self, c: list[Any]) -> _Tagged:
        return _Tagged(("fixed", self._int(c[1]), c[-1].end_pos))

    def bounded_array(self, c: list[Any]) -> _Tagged:
        return _Tagged(("bounded", self._int(c[1]), c[-1].end_pos))

    def field_type(self, c: list[Any]) -> Any:
        t = self._type(c[0])
        if len(c) == 1:
            return t
        for x in c[1:]:
            if isinstance(x, list):
                t.annotations = x
            else:
                kind, size, end = x
                arr = m.ArrayType(t, self.span(self._start(t), end), kind, size, _t=self.table)
                t = self._container(arr, t)
        return t

    # ---- values --------------------------------------------------------------------
    def int_value(self, c: list[Any]) -> m.Value:
        tok = c[0]
        return m.Value("int", self._int(tok), self.tok_span(tok), _text(tok), _t=self.table)

    def double_value(self, c: list[Any]) -> m.Value:
        tok = c[0]
        return m.Value("double", self._double(tok), self.tok_span(tok), _text(tok), _t=self.table)

    def string_value(self, c: list[Any]) -> m.Value:
        tok = c[0]
        # annotation values repeat (units, ranges, qos settings): one string for each distinct value and spelling
        return m.Value("string", sys.intern(self._decode(tok)), self.tok_span(tok), _text(tok), _t=self.table)

    def name_value(self, c: list[Any]) -> m.Value:
        tok = c[0]
        return m.Value("name", _text(tok), self.tok_span(tok), _text(tok), _t=self.table)

    def list_value(self, c: list[Any]) -> m.Value:
        items = [x for x in c if isinstance(x, m.Value)]
        return self._nested(m.Value("list", items, self.span(c[0].start_pos, c[-1].end_pos), _t=self.table), items)

    def map_value(self, c: list[Any]) -> m.Value:
        items = [x for x in c if isinstance(x, m.Value)]
        pairs = list(zip(items[0::2], items[1::2]))
        return self._nested(m.Value("map", pairs, self.span(c[0].start_pos, c[-1].end_pos), _t=self.table), items)

    def _nested(self, v: m.Value, items: list[m.Value]) -> m.Value:
        """A list or map value; nested deeper than types may be, it is refused and kept empty."""
        depth = max((self._depth.get(id(x), 0) for x in items), default=0) + 1
        if depth > MAX_TYPE_DEPTH:
            if depth == MAX_TYPE_DEPTH + 1:
                self.problems.append(("nesting-too-deep", f"values are nested more than {MAX_TYPE_DEPTH} levels "
                                      "deep", v.span))
            v.value = []
        self._depth[id(v)] = depth
        return v

    # ---- annotations ---------------------------------------------------------------
    _ann_end = 0

    def annotation(self, c: list[Any]) -> m.Annotation:
        key = c[0]
        value = c[1] if len(c) > 1 else None
        end = self._end(value) if value is not None else key.end_pos
        return m.Annotation(_text(key), value, self.span(key.start_pos, end), _t=self.table)

    def annotations(self, c: list[Any]) -> list[m.Annotation]:
        # the end of the last annotation list seen, read by the enclosing rule
        self._ann_end = c[-1].end_pos
        return [x for x in c if isinstance(x, m.Annotation)]

    # ---- literals ---------------------------------------------------------------------
    def _decode(self, tok: Token) -> str:
        """The value of a LITERAL token; escapes that name no character are reported."""
        found: list[LiteralProblem] = []
        value = decode_literal(str(tok), found)
        for offset, length, message in found:
            start = (tok.start_pos or 0) + offset
            self.problems.append(("invalid-escape", message, self.anchored(start, start + length)))
        return value

    def _int(self, tok: Token) -> int:
        """The value of an INT token; one beyond 64 bits is reported and stands as the nearest out-of-range value."""
        value = parse_int(str(tok))
        if value is not None:
            return value
        lo, hi = m.INT_LITERAL
        self.problems.append(("number-out-of-range", f"the integer {shorten(str(tok))} is beyond every integer type "
                              f"(the widest, i64 and u64, span {lo}..{hi})", self.anchored(tok.start_pos, tok.end_pos)))
        return lo - 1 if str(tok).startswith("-") else hi + 1

    def _double(self, tok: Token) -> float:
        """The value of a DOUBLE token; one beyond float64 is reported and stands as the largest float64."""
        value = parse_double(str(tok))
        if value is not None:
            return value
        self.problems.append(("number-out-of-range", f"the number {shorten(str(tok))} is beyond float64 "
                              f"(at most ±{m.FLOAT64_MAX:.6g}): it would be infinity", self.anchored(tok.start_pos, tok.end_pos)))
        return -m.FLOAT64_MAX if str(tok).startswith("-") else m.FLOAT64_MAX

    # ---- helpers ---------------------------------------------------------------------
    def _body_tail(self, c: list[Any]) -> tuple[Sequence[m.Annotation], int]:
        """Annotations after a closing brace, and where the definition ends."""
        last = c[-1]
        if isinstance(last, list):
            return last, self._ann_end
        return (), self._end(last)
