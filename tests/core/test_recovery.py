"""Syntax errors: several per pass, each on its own line, and the rest still modelled."""

from __future__ import annotations

from iface.semantics.compile import Workspace

from .helpers import DATA, compile_file


def test_independent_errors_are_all_reported() -> None:
    comp = compile_file(DATA / "invalid" / "syntax-error_several.iface")
    lines = [d.location()[0] for d in comp.diagnostics if d.code == "syntax-error"]
    assert lines == [5, 11]
    names = [d.name for d in comp.interface.definitions]
    assert names == ["Good1", "Broken1", "Good2", "Broken2", "Good3"]


def _compile(text: str, name: str = "t.iface"):
    return Workspace().compile_text(f"/virtual/{name}", text)


def test_members_around_a_broken_one_are_kept() -> None:
    comp = _compile("struct A {\n  1: i32 x,\n  2: i32 = 3,\n  3: i32 y\n}\n")
    (a,) = comp.interface.definitions
    assert [f.name for f in a.fields] == ["x", "y"]
    assert [d.location()[:2] for d in comp.diagnostics if d.code == "syntax-error"] == [(3, 10)]


def test_unclosed_body_is_closed_and_the_next_definition_kept() -> None:
    comp = _compile("struct A {\n  1: i32 x\nstruct B {\n  1: i32 y\n}\n")
    assert [d.name for d in comp.interface.definitions] == ["A", "B"]
    (err,) = [d for d in comp.diagnostics if d.code == "syntax-error"]
    assert err.location()[:2] == (3, 1)
    assert "'}'" in err.message


def test_end_of_file_inside_a_body() -> None:
    comp = _compile("message M {\n  float64 x,\n  float64 ")
    assert [d.name for d in comp.interface.definitions] == ["M"]
    assert [f.name for f in comp.interface.definitions[0].fields] == ["x"]
    assert any(d.code == "syntax-error" for d in comp.diagnostics)


def test_semantic_findings_inside_a_broken_chunk_are_not_piled_on() -> None:
    comp = _compile("struct A {\n  1: Unknown x,\n  2: i32 = 3\n}\nstruct B {\n  1: Missing m\n}\n")
    codes = [(d.location()[0], d.code) for d in comp.diagnostics]
    assert (3, "syntax-error") in codes
    assert (6, "unknown-type") in codes
    assert (2, "unknown-type") not in codes


def test_errors_in_nested_sections_and_enums() -> None:
    comp = _compile("service S {\n  request { i32 a, i32 = }\n  response { bool ok }\n}\n"
                    "provides S on \"/s\"\nenum E { A = , B }\n")
    s = comp.interface.symbols["S"]
    assert [f.name for f in s.request.fields] == ["a"]
    assert [f.name for f in s.response.fields] == ["ok"]
    assert [v.name for v in comp.interface.symbols["E"].values] == ["B"]


def test_unterminated_string_and_comment_have_clear_messages() -> None:
    comp = _compile('const string S = "open\nstruct A {\n  1: i32 x\n}\n')
    msgs = [d.message for d in comp.diagnostics if d.code == "syntax-error"]
    assert any("unterminated string" in m for m in msgs)
    assert "A" in comp.interface.symbols
    comp = _compile("struct A {\n  1: i32 x\n}\n/* never closed\n")
    assert any("comment" in d.message for d in comp.diagnostics if d.code == "syntax-error")
