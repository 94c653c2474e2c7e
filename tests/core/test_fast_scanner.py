"""The fast scanner (whole clean files) and lark's lexer (chunks, recovery) read files alike."""

from __future__ import annotations

import json
import random
from pathlib import Path

import pytest

from iface.forms.dump import dump_interface
from iface.model.source import Source
from iface.semantics.compile import compile_source
from iface.syntax.chunks import split
from iface.syntax.parse import chunk_parser

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
    parser = chunk_parser()
    chunks = split(text)
    docs: dict[int, str] = {}
    items: list[object] = []
    problems = False
    for ch in chunks:  # lark's lexer, chunk by chunk
        docs.update(ch.doc_map(ch.start))
        r = parser.parse_recovering(text[ch.start:ch.end], ch.doc_map())
        r.move_with(ch)
        items.extend(r.items)
        problems = problems or bool(r.problems) or ch.unterminated
    fast = parser.parse_clean(text, docs)
    if problems:
        assert fast is None, "the fast scanner read a file that has syntax problems"
        return
    assert fast is not None, "the fast scanner refused a file lark reads without a problem"
    assert _picture(list(fast.items), text) == _picture(items, text)


def _broken_versions() -> list[str]:
    """A long file after each of 60 random line edits: many chunks broken, most of them clean."""
    rng = random.Random(5)
    lines: list[str] = []
    for i in range(30):
        lines += [f"/** Reading {i}. */", f"message Reading{i} {{", "    u8 count", f"    Mode{i} mode = 1",
                  "    string<=8 label (unit = \"m\")", "}", f"enum Mode{i} {{", "    IDLE = 0,", "}",
                  f"service S{i} {{ void go(1: i32 x) throws (1: E e) }}", ""]
    versions = []
    for _ in range(60):
        at = rng.randrange(len(lines))
        roll = rng.random()
        if roll < 0.5:
            lines.insert(at, rng.choice(["    u8 extra", "/** doc */", "message X {", "}", "const u8 K = 1",
                                         "struct T { 1: i32 a,", "    u8 = 3", "enum F { A = }", "@"]))
        elif len(lines) > 10:
            del lines[at]
        versions.append("\n".join(lines))
    return versions


CHUNK_CASES = [*((str(p.relative_to(ROOT)), p.read_text(encoding="utf-8", errors="replace")) for p in FILES),
               *((f"broken-{k}", t) for k, t in enumerate(_broken_versions()))]


@pytest.mark.parametrize("name, text", CHUNK_CASES, ids=[name for name, _ in CHUNK_CASES])
def test_each_chunk_reads_alike_with_the_fast_scanner_and_with_lark(name: str, text: str) -> None:
    """``parse`` reads a chunk with the fast scanner and falls back to lark only for a chunk that has a
    problem: for every chunk it gives what lark gives, and the fast scanner refuses just the broken ones."""
    parser = chunk_parser()
    for ch in split(text):
        if ch.unterminated:
            continue
        ctext = text[ch.start:ch.end]
        lark = parser.parse_recovering(ctext, ch.doc_map())
        got = parser.parse(ctext, ch.doc_map())
        assert _picture(list(got.items), ctext) == _picture(list(lark.items), ctext), ctext
        assert [(p.code, p.message) for p in got.problems] == [(p.code, p.message) for p in lark.problems], ctext
        assert got.open_at_end == lark.open_at_end, ctext
        fast = parser.parse_clean(ctext, ch.doc_map())
        assert (fast is None) == bool(lark.problems), ctext


def test_keywords_are_names_where_only_a_name_fits() -> None:
    text = "struct message { 1: i8 i8, 2: string state, 3: map<string, i32> service }\nenum E { A, message }\n"
    comp = compile_source(Source("k.thrift", text))
    assert [d.format() for d in comp.diagnostics] == []
    s = comp.interface.symbols["message"]
    assert [f.name for f in s.fields] == ["i8", "state", "service"]
    assert [v.name for v in comp.interface.symbols["E"].values] == ["A", "message"]
