"""Chunks with syntax errors are kept byte for byte; the rest is formatted."""

from __future__ import annotations

from iface.text.formatter import format_document, format_text

BAD = "struct Bad {\r\n\t1: i32 x =   \r\n  2: whatever ===\r\n}\r\n"


def test_broken_chunk_is_kept_byte_for_byte() -> None:
    src = "struct Good{1:i32 a}\n" + BAD + "struct AlsoGood{1:i32 b}"
    result = format_document(src)
    assert BAD in result.text
    assert result.text == "struct Good {\n    1: i32 a\n}\n" + BAD + "struct AlsoGood {\n    1: i32 b\n}\n"
    assert [r.text for r in result.broken] == [BAD]
    assert format_text(result.text) == result.text


def test_broken_chunk_first_and_last() -> None:
    src = BAD + "struct A{}\n" + BAD.rstrip("\r\n")
    out = format_text(src)
    assert out == BAD + "struct A {}\n" + BAD.rstrip("\r\n")  # blank lines before it are the author's
    assert format_text(out) == out


def test_unterminated_comment_and_string_are_left_alone() -> None:
    for bad in ("struct S { 1: string s = \"open }\n", "struct S { /* never closed\n 1: i32 a }\n"):
        src = "struct A{}\n" + bad
        out = format_text(src)
        assert out == "struct A {}\n" + bad
        assert format_text(out) == out


def test_doc_comment_cut_mid_line_starts_a_new_line_after_a_broken_chunk() -> None:
    src = "struct Bad { 1: = }  /** doc */\nstruct B{}\n"
    out = format_text(src)
    assert out.startswith("struct Bad { 1: = }  ")
    assert format_text(out) == out
    assert "/** doc */\nstruct B {}\n" in out


def test_the_file_only_broken() -> None:
    assert format_text(BAD) == BAD
