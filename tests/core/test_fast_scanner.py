"""The fast scanner (whole clean files) and lark's lexer (chunks, recovery) read files alike."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from iface.forms.dump import dump_interface
from iface.model.source import Source
from iface.semantics.compile import compile_source
from iface.syntax.chunks import split
from iface.syntax.parse import ChunkCache, chunk_parser, parse_text

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted(p for suffix in ("*.iface", "*.thrift") for p in (ROOT / "tests").rglob(suffix)) + sorted(
    (ROOT / "examples").glob("*.iface"))


def _picture(items: list[object], text: str) -> str:
    from iface.semantics.compile import build_interface

    return json.dumps(dump_interface(build_interface(Source("x.iface", text), items)), default=str)


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_both_lexers_give_the_same_model(path: Path) -> None:
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        pytest.skip("not UTF-8 (a bad-input fixture)")
    chunked = parse_text(text, ChunkCache())  # lark's lexer, chunk by chunk
    docs: dict[int, str] = {}
    for ch in split(text):
        docs.update(ch.doc_map(ch.start))
    fast = chunk_parser().parse_clean(text, docs)
    if chunked.problems:
        assert fast is None, "the fast scanner read a file that has syntax problems"
        return
    assert fast is not None, "the fast scanner refused a file lark reads without a problem"
    assert _picture(list(fast.items), text) == _picture(chunked.items, text)


def test_keywords_are_names_where_only_a_name_fits() -> None:
    text = "struct message { 1: i8 i8, 2: string state, 3: map<string, i32> service }\nenum E { A, message }\n"
    comp = compile_source(Source("k.thrift", text))
    assert [d.format() for d in comp.diagnostics] == []
    s = comp.interface.symbols["message"]
    assert [f.name for f in s.fields] == ["i8", "state", "service"]
    assert [v.name for v in comp.interface.symbols["E"].values] == ["A", "message"]
