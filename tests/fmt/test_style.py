"""Style rules one by one, and the whitespace and encoding rules."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from iface.text.formatter import format_text

from .canon import comments_of, model_of

DOCS = Path(__file__).resolve().parents[2] / "docs" / "formatting.md"


@pytest.mark.parametrize(("src", "want"), [
    ("", ""),
    ("   \n\n\t\n", ""),
    ("// only a comment", "// only a comment\n"),
    ("struct A {}", "struct A {}\n"),
    ("struct A {}\n\n\n", "struct A {}\n"),
    ("\n\n\nstruct A {}", "struct A {}\n"),
])
def test_file_edges(src: str, want: str) -> None:
    assert format_text(src) == want


def test_crlf_tabs_and_trailing_whitespace_are_normalised() -> None:
    src = "struct A {\t\r\n\t1: i32 a,   \r\n\t2: i32 b // note   \r\n}\r\n"
    out = format_text(src)
    assert out == "struct A {\n    1: i32 a,\n    2: i32 b // note\n}\n"
    assert "\r" not in out and "\t" not in out


def test_crlf_inside_block_comments_is_normalised() -> None:
    src = "/**\r\n * doc\r\n */\r\nstruct A {}\r\n"
    assert format_text(src) == "/**\n * doc\n */\nstruct A {}\n"


def test_byte_order_mark_is_dropped() -> None:
    assert format_text("\ufeffstruct A {}\n") == "struct A {}\n"


@pytest.mark.parametrize("indent", [2, 3, 8])
def test_indent_width(indent: int) -> None:
    src = "service S { request { i32 a } response { i32 b } }"
    out = format_text(src, indent=indent)
    pad = " " * indent
    assert out == (f"service S {{\n{pad}request {{\n{pad * 2}i32 a\n{pad}}}\n"
                   f"{pad}response {{\n{pad * 2}i32 b\n{pad}}}\n}}\n")


def test_indent_out_of_range_is_refused() -> None:
    with pytest.raises(ValueError):
        format_text("struct A {}", indent=0)


def test_lists_break_exactly_past_one_hundred_columns() -> None:
    # "const list<string> L = [" is 24 columns, each element '"x…x", ' adds its length
    def line(n: int) -> str:
        return f'const list<string> L = ["{"x" * n}"]'
    fits = line(100 - len(line(0)))
    assert len(fits) == 100
    assert format_text(fits) == fits + "\n"
    too_long = line(101 - len(line(0)))
    assert format_text(too_long).count("\n") == 3


def test_trailing_line_comment_does_not_break_a_list() -> None:
    src = 'typedef i32 T (a = "b", c) // a comment long enough to pass the hundredth column of the line ......'
    assert format_text(src) == src + "\n"


def test_comment_inside_a_member_forces_a_continuation_line() -> None:
    out = format_text("struct A {\n  1: // the id\n  i32 a\n}\n")
    assert out == "struct A {\n    1: // the id\n        i32 a\n}\n"
    assert format_text(out) == out


@pytest.mark.parametrize(("src", "want"), [
    ("/** A */# c", "/** A */ # c\n"),
    ("/* A */ /* B */ // c\nstruct S { 1: i32 a }\n", "/* A */ /* B */ // c\nstruct S {\n    1: i32 a\n}\n"),
    ("struct S { 1: i32 a }\n/** A */# c\n", "struct S {\n    1: i32 a\n}\n/** A */ # c\n"),
    ("struct S {\n  /* a */ // b\n  1: i32 x\n}\n", "struct S {\n    /* a */ // b\n    1: i32 x\n}\n"),
])
def test_comments_on_one_line_before_an_item_stay_on_it(src: str, want: str) -> None:
    """A block comment and a comment after it on its line stay on one line, at the item's indent; the item
    after them is not indented (it was, as a continuation line, and a second format moved it back)."""
    assert format_text(src) == want
    assert format_text(want) == want


def test_comment_between_header_and_brace() -> None:
    src = "struct A\n// about the body\n{\n1: i32 a\n}\n"
    out = format_text(src)
    assert format_text(out) == out
    assert comments_of(out) == comments_of(src)
    assert model_of(out) == model_of(src)


def test_semicolon_after_top_level_items_is_dropped() -> None:
    assert format_text("const i32 X = 1;\ntypedef i32 T;\nstruct A {};\n") == \
        "const i32 X = 1\ntypedef i32 T\n\nstruct A {}\n"


def test_the_documented_example_is_formatted() -> None:
    example = re.search(r"```thrift\n(.*?)```", DOCS.read_text(encoding="utf-8"), re.S)
    assert example is not None
    assert format_text(example.group(1)) == example.group(1)


def test_map_type_separator_is_normalised() -> None:
    assert format_text("typedef map<i32;string> M") == "typedef map<i32, string> M\n"
    assert format_text("typedef map < i32 /* key */ , string > M") == "typedef map<i32, /* key */ string> M\n"


def test_doc_comment_before_a_separator_documents_the_next_member() -> None:
    src = "enum E {\n  A\n  /** about B */\n  , B\n}\n"
    assert format_text(src) == "enum E {\n    A,\n    /** about B */\n    B\n}\n"
