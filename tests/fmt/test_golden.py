"""Golden files: every ``NAME.in.iface`` formats to ``NAME.out.iface`` byte for byte."""

from __future__ import annotations

from pathlib import Path

import pytest

from iface.text.formatter import format_document, format_text

from .canon import comments_of, model_of, tokens_of

GOLDEN = Path(__file__).parent / "data" / "golden"
CASES = sorted(p.name[:-len(".in.iface")] for p in GOLDEN.glob("*.in.iface"))


def _read(name: str) -> str:
    return (GOLDEN / name).read_bytes().decode("utf-8")


def test_there_are_golden_cases() -> None:
    assert len(CASES) >= 10
    for name in CASES:
        assert (GOLDEN / f"{name}.out.iface").is_file(), name


@pytest.mark.parametrize("name", CASES)
def test_formats_to_expected(name: str) -> None:
    src, want = _read(f"{name}.in.iface"), _read(f"{name}.out.iface")
    result = format_document(src)
    assert result.text == want
    assert result.unsafe == []


@pytest.mark.parametrize("name", CASES)
def test_expected_is_a_fixed_point(name: str) -> None:
    want = _read(f"{name}.out.iface")
    assert format_text(want) == want


@pytest.mark.parametrize("name", [n for n in CASES if n != "broken"])
def test_meaning_and_comments_are_kept(name: str) -> None:
    src, out = _read(f"{name}.in.iface"), _read(f"{name}.out.iface")
    assert model_of(out) == model_of(src)
    assert tokens_of(out) == tokens_of(src)
    assert comments_of(out) == comments_of(src)
