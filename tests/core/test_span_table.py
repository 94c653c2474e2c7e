"""Parsed nodes keep their spans in their chunk's table (``SpanTable``): every span read from them is a
span of the text, however the node was made, and setting one keeps the others."""

from __future__ import annotations

from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

import pytest

from iface.model import nodes as m
from iface.model.source import Span, SpanTable
from iface.semantics.compile import Workspace

TESTS = Path(__file__).parent.parent
FILES = sorted(p for p in TESTS.rglob("*") if p.suffix in (".iface", ".thrift") and p.stat().st_size < 200_000)


def _nodes(node: Any, out: list[Any], depth: int = 0) -> list[Any]:
    """Every model node under ``node``; cross references are not followed."""
    if isinstance(node, (list, tuple)):
        for x in node:
            _nodes(x, out, depth + 1)
    elif is_dataclass(node) and not isinstance(node, type) and depth < 60:
        out.append(node)
        for f in fields(node):
            if f.name not in ("target", "source", "included", "spliced", "_t", "final"):
                _nodes(getattr(node, f.name), out, depth + 1)
    return out


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(TESTS)))
def test_every_span_of_a_parsed_file_is_a_span_of_its_text(path: Path) -> None:
    text = path.read_text(encoding="utf-8", errors="replace")
    comp = Workspace([]).compile_text(str(path), text)
    nodes = _nodes(comp.interface.items, [])
    assert nodes or not comp.interface.items
    for node in nodes:
        for f in fields(node):
            if not f.name.endswith("span"):
                continue
            span = getattr(node, f.name)
            if span is None and f.name != "span":
                continue
            where = f"{type(node).__name__}.{f.name} in {path.name}"
            assert isinstance(span, Span), where  # an index without its table would be an int
            assert 0 <= span.start <= span.end <= len(text), where


def test_a_parsed_node_keeps_its_other_spans_when_one_is_set() -> None:
    comp = Workspace([]).compile_text("/t.iface", "message Pose {\n    float64 x\n}\n")
    struct = comp.interface.definitions[0]
    assert isinstance(struct, m.Struct) and isinstance(struct._t, SpanTable)
    name = struct.name_span
    struct.span = Span(0, 3)
    assert struct._t is None
    assert (struct.span.start, struct.span.end) == (0, 3)
    assert (struct.name_span.start, struct.name_span.end) == (name.start, name.end) == (8, 12)
    field = struct.fields[0]
    field.name_span = Span(1, 2)
    assert (field.span.start, field.span.end, field.name_span.start) == (19, 28, 1)


def test_a_span_read_from_a_parsed_node_moves_with_its_chunk() -> None:
    ws = Workspace([])
    text = "message A {\n    u8 a\n}\n\nmessage B {\n    u8 b\n}\n"
    b = ws.compile_text("/t.iface", text).interface.definitions[1]
    span = b.name_span
    assert text[span.start:span.end] == "B"
    longer = "// one more line\n" + text
    again = ws.compile_text("/t.iface", longer).interface.definitions[1]
    assert again is b  # the chunk was kept and moved
    assert longer[span.start:span.end] == longer[b.name_span.start:b.name_span.end] == "B"


def test_node_constructors_keep_the_dataclass_signature_and_fresh_defaults() -> None:
    """Spanned classes have their own ``__init__`` (spans stored in their slots): every field is set as the
    dataclass would set it, and a default list is a new one for each node."""
    a = m.Service("A", Span(0, 1), Span(2, 3))
    b = m.Service("B", Span(4, 5), name_span=Span(6, 7), form="flat", doc="d")
    assert a.functions == [] and a.functions is not b.functions and a.consts is not b.consts
    a.functions.append(None)  # type: ignore[arg-type]
    assert b.functions == [] and (b.form, b.doc, b.name_span.start) == ("flat", "d", 6)
    f = m.Field("x", m.BaseType("u8", Span(0, 2)), Span(0, 4), Span(3, 4), 7, reference=True)
    assert (f.id, f.reference, f.requiredness, f.annotations, f._t) == (7, True, None, (), None)
    assert repr(f).startswith("Field(name='x', type=BaseType(name='u8', span=Span(0, 2)")
