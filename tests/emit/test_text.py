"""The shared text helpers (iface.emit.text): what every target writes untrusted text with."""

from __future__ import annotations

import codecs

import pytest
import yaml

from iface.emit.idl.render import idl_string
from iface.emit.text import (
    comment_lines,
    compact_number,
    cpp_string,
    doc_lines,
    header_name,
    line_comment,
    number,
    one_line,
    quote,
    summary,
    yaml_string,
)

#: Characters that break naive escaping: every control character, quotes, backslash, Unicode line breaks,
#: format characters, a non-BMP character.
NASTY = "".join(chr(c) for c in range(0x20)) + "\x7f\x85\xa0\u2028\u2029\u200b\ufeff\"'\\?#*/<>&-- é\U0001f600"


def test_doc_lines_split_every_line_break_and_trim_blank_ends() -> None:
    assert doc_lines("\n\n  first  \nsecond\u2028third\x85fourth\n\n") == ["  first", "second", "third", "fourth"]
    assert doc_lines(None) == [] and doc_lines("\n \n") == []


def test_comment_lines_are_safe_after_a_line_comment() -> None:
    lines = comment_lines("a\x00b\tc \\\\\nnext \\ \n*/ end")
    assert lines == ["a b c", "next", "*/ end"]
    for line in comment_lines(NASTY):
        assert not line.endswith("\\")
        assert all(c.isprintable() or c == " " or c in "\u200b\ufeff" for c in line), repr(line)


def test_one_line_and_summary() -> None:
    assert one_line("  Max   speed.\n\nSecond  paragraph ") == "Max speed. Second paragraph"
    assert summary("Max speed. Applies\nto both arms.\n\nDetails.") == "Max speed."
    assert summary("No full stop\nhere\n\nnot this") == "No full stop here"
    assert summary(None) == ""


def test_line_comment() -> None:
    assert line_comment("text") == "# text"
    assert line_comment("") == "#"
    assert line_comment("x", "//") == "// x"


@pytest.mark.parametrize("path, name", [
    ("/a/b/robot.iface", "robot.iface"),
    ("C:\\work\\robot.iface", "robot.iface"),
    ("/a/x--y\n<z>&'\".iface", "x__y__z____.iface"),
    ("/a/", "interface"),
])
def test_header_name_is_safe_in_every_comment_syntax(path: str, name: str) -> None:
    got = header_name(path)
    assert got == name
    assert "--" not in got and all(c.isprintable() for c in got) and not got.endswith("\\")


def test_quote_uses_the_table_then_keep_then_escape() -> None:
    assert quote('a"b\x01', {'"': "Q"}, lambda c: f"<{ord(c)}>") == '"aQb<1>"'
    assert quote("ab", {}, lambda c: "?", keep=lambda c: c == "a") == '"a?"'


def _decode_cpp(literal: str) -> str:
    assert literal[0] == literal[-1] == '"'
    body = literal[1:-1].replace("\\?", "?")
    return codecs.decode(body.encode("latin-1", "backslashreplace"), "unicode_escape")


def test_cpp_string_holds_exactly_the_text() -> None:
    literal = cpp_string(NASTY)
    assert _decode_cpp(literal) == NASTY
    assert "??" not in literal  # no trigraphs
    assert not any(ord(c) < 0x20 or c == "\x7f" for c in literal)


@pytest.mark.parametrize("text", [NASTY, "", " lead", "trail ", "on", "yes", "- x", "a: b", "1e5", "~", "'q'"])
def test_yaml_string_loads_back_exactly(text: str) -> None:
    written = yaml_string(text)
    assert "\n" not in written
    assert yaml.safe_load(f"key: {written}\n") == {"key": text}


def test_idl_string_escapes_and_comment_backslash() -> None:
    assert idl_string('a"b\\c\n') == '"a\\"b\\\\c\\n"'
    assert idl_string("a\\b", comment=True) == '"a\\134b"'
    assert idl_string("\x01\u2028") == '"\\x01\\u2028"'


def test_numbers() -> None:
    assert number(1e-05) == "0.00001"
    assert number(3) == "3" and number(True) == "1" and number(2.0) == "2.0"
    assert compact_number(3.0) == "3" and compact_number(0.5) == "0.5"
    with pytest.raises(ValueError):
        number(float("inf"))
