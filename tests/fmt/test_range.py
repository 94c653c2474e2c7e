"""format_range: only the top-level definitions a range touches, as minimal edits."""

from __future__ import annotations

from iface.text.formatter import TextEdit, format_range, format_text

SRC = (
    "struct A{1:i32 a}\n"       # 0..18
    "struct B{1:i32 b}\n"       # 18..36
    "struct C{1:i32 c}\n"       # 36..54
)


def apply(text: str, edits: list[TextEdit]) -> str:
    for e in sorted(edits, reverse=True):
        text = text[:e.start] + e.new_text + text[e.end:]
    return text


def test_only_the_touched_definition_changes() -> None:
    b = SRC.index("struct B")
    edits = format_range(SRC, b + 3, b + 5)
    out = apply(SRC, edits)
    assert out == "struct A{1:i32 a}\n\nstruct B {\n    1: i32 b\n}\nstruct C{1:i32 c}\n"
    assert all(b - 1 <= e.start and e.end <= SRC.index("struct C") for e in edits)


def test_empty_range_selects_the_definition_around_it() -> None:
    c = SRC.index("i32 c")
    out = apply(SRC, format_range(SRC, c, c))
    assert out.startswith("struct A{1:i32 a}\nstruct B{1:i32 b}\n")
    assert out.endswith("struct C {\n    1: i32 c\n}\n")


def test_whole_lines_selection_does_not_spill_into_the_next_definition() -> None:
    b, c = SRC.index("struct B"), SRC.index("struct C")
    out = apply(SRC, format_range(SRC, b, c))
    assert out.endswith("struct C{1:i32 c}\n")
    assert "struct B {\n" in out


def test_whole_text_range_equals_format_text() -> None:
    assert apply(SRC, format_range(SRC, 0, len(SRC))) == format_text(SRC)


def test_edits_are_minimal() -> None:
    src = "struct A {\n    1: i32 a,\n    2: i32  b\n}\n"
    two_spaces = src.index("  b")
    assert format_range(src, 0, len(src)) == [TextEdit(two_spaces + 1, two_spaces + 2, "")]


def test_formatted_text_gives_no_edits() -> None:
    out = format_text(SRC)
    assert format_range(out, 0, len(out)) == []


def test_broken_definitions_get_no_edits() -> None:
    src = "struct A{1:i32 a}\nstruct Bad {\n  1: i32 = \n}\nstruct C{1:i32 c}\n"
    bad = src.index("Bad")
    assert format_range(src, bad, bad + 2) == []
    edits = format_range(src, 0, len(src))
    assert edits
    assert all(e.end <= src.index("struct Bad") or e.start >= src.index("struct C") for e in edits)


def test_range_includes_leading_comments_of_the_definition() -> None:
    src = "struct A {}\n  // about B\nstruct B{1:i32 b}\n"
    b = src.index("i32 b")
    out = apply(src, format_range(src, b, b))
    assert out == "struct A {}\n\n// about B\nstruct B {\n    1: i32 b\n}\n"


def test_offsets_are_clamped_and_ordered() -> None:
    assert format_range(SRC, 10**6, -5) == format_range(SRC, 0, len(SRC))


def test_range_over_the_end_fixes_the_final_newline() -> None:
    src = "struct A {}\n\n\n"
    assert apply(src, format_range(src, len(src), len(src))) == "struct A {}\n"
