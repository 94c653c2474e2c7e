"""Idempotence and meaning preservation, over every fixture and over random texts."""

from __future__ import annotations

from pathlib import Path

import pytest

from iface.text.formatter import format_document, format_range, format_text
from iface.text.formatter.lex import parse_strict

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
