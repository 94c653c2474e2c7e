"""A formatted item that would not give back the same tokens is kept as written."""

from __future__ import annotations

import pytest

from iface.text.formatter import document, format_document

SRC = "struct A{1:i32 a}\nstruct B{1:i32 b}\n"


def test_a_lossy_layout_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    real = document.render

    def lossy(doc, width=100, unit=4):  # type: ignore[no-untyped-def]
        text, mark = real(doc, width, unit)
        return text.replace("i32 b", "i64 b"), mark

    monkeypatch.setattr(document, "render", lossy)
    result = format_document(SRC)
    assert result.text == "struct A {\n    1: i32 a\n}\nstruct B{1:i32 b}\n"
    assert [r.content_start for r in result.unsafe] == [SRC.index("struct B")]
    assert "differs" in result.unsafe[0].unsafe


def test_an_unparsable_layout_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    real = document.render

    def broken(doc, width=100, unit=4):  # type: ignore[no-untyped-def]
        text, mark = real(doc, width, unit)
        return text.replace("}", ""), mark

    monkeypatch.setattr(document, "render", broken)
    result = format_document(SRC)
    assert result.text == SRC.rstrip("\n") + "\n"
    assert len(result.unsafe) == 2
    assert "does not parse" in result.unsafe[0].unsafe
