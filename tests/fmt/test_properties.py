"""Idempotence and meaning preservation, over every fixture and over random texts."""

from __future__ import annotations

from pathlib import Path

import pytest
from lark import Token, Tree
from lark.exceptions import LarkError

from iface.text.formatter import format_document, format_range, format_text
from iface.text.formatter.lex import parse_strict, tree_parser

from .canon import comments_of, model_of, tokens_of
from .randomtext import RandomText

DATA = Path(__file__).parent / "data"
FIXTURES = sorted(p for p in DATA.rglob("*") if p.suffix in (".iface", ".thrift"))
SEEDS = range(60)


def _check_formatted(src: str) -> str:
    result = format_document(src)
    out = result.text
    assert result.unsafe == []
    assert format_text(out) == out, "not idempotent"
    if not result.broken:
        assert tokens_of(out) == tokens_of(src)
        assert comments_of(out) == comments_of(src)
        assert model_of(out) == model_of(src)
        assert all(line == line.rstrip() for line in out.split("\n"))
        assert out == "" or out.endswith("\n") and not out.endswith("\n\n")
        assert "\r" not in out
    return out


@pytest.mark.parametrize("path", FIXTURES, ids=lambda p: p.name)
def test_fixture_is_idempotent_and_meaning_preserving(path: Path) -> None:
    _check_formatted(path.read_bytes().decode("utf-8"))


@pytest.mark.parametrize("seed", SEEDS)
def test_random_text(seed: int) -> None:
    src = RandomText(seed).text(items=4)
    assert parse_strict(src) is not None, "the generator made an invalid text"
    out = _check_formatted(src)
    # a range format followed by a full format ends where a full format does
    gen = RandomText(seed + 1000)
    start = gen.rng.randrange(len(src) + 1)
    end = min(len(src), start + gen.rng.randrange(80))
    edited = src
    for e in reversed(format_range(src, start, end)):
        edited = edited[:e.start] + e.new_text + edited[e.end:]
    assert format_text(edited) == out


def test_random_texts_cover_the_templates() -> None:
    words = set()
    for seed in SEEDS:
        words |= set(RandomText(seed).text(items=4).split())
    assert {"struct", "enum", "senum", "service", "action", "const", "typedef", "throws", "request",
            "goal", "publishes", "//", "#", "/*", "/**"} <= words


def _shape(node: object) -> object:
    """A tree as nested tuples: rule names, token types, values and offsets."""
    if isinstance(node, Tree):
        return (node.data, [_shape(c) for c in node.children])
    assert isinstance(node, Token), type(node)
    return (node.type, str(node), node.start_pos, node.end_pos)


ROOT = Path(__file__).resolve().parents[2]
TREE_CASES = [*((str(p.relative_to(ROOT)), p.read_bytes().decode("utf-8", errors="replace"))
                for p in [*FIXTURES, *sorted((ROOT / "examples").glob("*.iface"))]),
              *((f"random-{seed}", RandomText(seed).text(items=4)) for seed in SEEDS[:20])]


@pytest.mark.parametrize("name, text", TREE_CASES, ids=[n for n, _ in TREE_CASES])
def test_the_formatters_tree_is_larks_tree(name: str, text: str) -> None:
    """``parse_strict`` reads a clean text with the compiler's fast path: the tree is the one lark builds,
    every token at its offsets; a text lark refuses is refused."""
    try:
        expected = _shape(tree_parser().parse(text))
    except LarkError:
        expected = None
    got = parse_strict(text)
    assert (None if got is None else _shape(got)) == expected
