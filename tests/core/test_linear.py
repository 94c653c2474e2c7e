"""Inputs that used to cost quadratic time or unbounded memory, measured by counting work or memory, never by
wall time: did-you-mean over many unknown names, unclosed brackets, an unterminated block comment, the
formatter's columns on one long line. ``bench/hardening_bench.py`` prints the timings."""

from __future__ import annotations

import difflib
import tracemalloc
from collections.abc import Callable

import pytest
from lark.parsers.lalr_parser_state import ParserState

from iface.model.source import Source
from iface.semantics.compile import compile_source
from iface.text.formatter import format_text


def _compile(text: str, name: str = "t.thrift"):
    return compile_source(Source(f"/virtual/{name}", text))


def _counting(monkeypatch: pytest.MonkeyPatch, owner: object, attr: str,
              weight: Callable[..., int] = lambda *a, **k: 1) -> dict[str, int]:
    """Count calls of ``owner.attr`` (each weighted), while still calling it."""
    count = {"n": 0}
    real = getattr(owner, attr)

    def counted(*args: object, **kwargs: object) -> object:
        count["n"] += weight(*args, **kwargs)
        return real(*args, **kwargs)

    monkeypatch.setattr(owner, attr, counted)
    return count


def _many_structs(n: int) -> str:
    """n one-field structs, each with its own unknown type, all names the same length (none filtered out)."""
    return "".join(f"struct S{i:05d} {{\n    1: U{i:05d} f\n}}\n" for i in range(n))


def _one_struct(n: int) -> str:
    return "struct S {\n" + "".join(f"    {i + 1}: T{i:05d} f{i},\n" for i in range(n)) + "}\n"


@pytest.mark.parametrize("shape", [_many_structs, _one_struct], ids=["many-structs", "one-struct"])
def test_did_you_mean_work_grows_linearly(shape: Callable[[int], str], monkeypatch: pytest.MonkeyPatch) -> None:
    comparisons = _counting(monkeypatch, difflib.SequenceMatcher, "set_seq1")
    work = []
    for n in (1000, 2000, 4000):
        comparisons["n"] = 0
        comp = _compile(shape(n))
        assert sum(d.code == "unknown-type" for d in comp.diagnostics) == n
        work.append(comparisons["n"])
    assert work[2] <= 2.5 * work[1] + 1000 and work[1] <= 2.5 * work[0] + 1000, work
    assert work[2] <= 100 * 4000, work


def test_did_you_mean_still_finds_typos_in_a_large_file() -> None:
    names = "".join(f"struct Record{i:05d} {{ 1: i32 x }}\n" for i in range(5000))
    typos = "struct Use {\n    1: Recrod00042 a,\n    2: Record00042x b,\n    3: record00043 c,\n    4: f64 d\n}\n"
    comp = _compile(names + typos)
    got = {d.data["name"]: d.data["suggestions"] for d in comp.diagnostics if d.code == "unknown-type"}
    assert got["Recrod00042"][:1] == ["Record00042"]
    assert got["Record00042x"][:1] == ["Record00042"]
    assert got["record00043"] == ["Record00043"]
    assert got["f64"] == ["float64"]


@pytest.mark.parametrize("spelling, meant", [
    ("f64", "float64"), ("f32", "float32"), ("Float64", "float64"), ("FLOAT32", "float32"), ("Int32", "int32"),
    ("UInt8", "uint8"), ("String", "string"), ("Bool", "bool"), ("boolean", "bool"), ("str", "string"),
    ("int32_t", "i32"), ("uint8_t", "u8"), ("uint64_t", "u64"), ("int", "i32"), ("long", "i64"),
    ("bytes", "binary"), ("usize", "u64"), ("sint64", "i64"),
])
def test_other_languages_spellings_lead_to_the_iface_type(spelling: str, meant: str) -> None:
    comp = _compile(f"struct S {{\n    1: {spelling} x\n}}\n")
    (d,) = [d for d in comp.diagnostics if d.code == "unknown-type"]
    assert d.data["suggestions"][0] == meant, d.message
    assert f"did you mean '{meant}'" in d.message


def test_ros_c_and_python_names_of_builtin_types_are_types() -> None:
    text = "struct S {\n" + "".join(f"    {i + 1}: {t} f{i},\n" for i, t in enumerate(
        ["float64", "float", "double", "int32", "uint8", "string", "bool", "byte", "char", "float32"])) + "}\n"
    assert [d.format() for d in _compile(text).diagnostics if d.severity == 1] == []


def _copied_states(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    return _counting(monkeypatch, ParserState, "copy", lambda self, *a, **k: len(self.state_stack))


def test_unclosed_brackets_cost_linear_parser_work(monkeypatch: pytest.MonkeyPatch) -> None:
    copied = _copied_states(monkeypatch)
    work = []
    for n in (2000, 4000, 8000):
        copied["n"] = 0
        comp = _compile("const list<i32> X = " + "[" * n + "\n")
        assert [d.code for d in comp.diagnostics] == ["syntax-error"]
        work.append(copied["n"])
    assert work[2] <= 2.5 * work[1] + 1000 and work[2] <= 20 * 8000, work


def _peak(fn: Callable[[], object]) -> tuple[object, int]:
    """What ``fn`` returns, and the most memory Python held while it ran (bytes).

    A small compile first builds what is built once per process (parser tables, the token pattern:
    about 3 MB), so that the figure is what ``fn`` needs, whichever test runs first.
    """
    _compile("struct Warm { 1: i32 w }\n/* c */\n")
    tracemalloc.start()
    try:
        return fn(), tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_an_unterminated_comment_holds_no_memory_per_character() -> None:
    text = "struct A { 1: i32 x }\n/*\n" + "struct S { 1: i32 x }\n" * 50_000  # 1.1 MB
    comp, peak = _peak(lambda: _compile(text, "c.iface"))
    assert peak < 2 * len(text), f"{peak / 1e6:.1f} MB for a {len(text) / 1e6:.1f} MB text"
    assert [(d.code, d.location()[:2]) for d in comp.diagnostics if d.severity == 1] == [("syntax-error", (2, 1))]
    assert "unterminated comment" in comp.diagnostics[0].message
    assert [d.name for d in comp.interface.definitions] == ["A"]  # nothing after the comment is modelled


def test_formatting_after_an_unterminated_comment_holds_no_memory_per_character() -> None:
    text = "struct A { 1: i32 x }\n/*\n" + "struct S { 1: i32 x }\n" * 50_000
    out, peak = _peak(lambda: format_text(text))
    assert isinstance(out, str)
    assert peak < 4 * len(text), f"{peak / 1e6:.1f} MB for a {len(text) / 1e6:.1f} MB text"
    assert out.endswith(text[text.index("/*"):])  # the comment is kept as written


def test_a_long_block_comment_is_read_without_memory_per_character() -> None:
    text = "/* " + "x * y / z\n" * 200_000 + "*/\nstruct A { 1: i32 x }\n"  # 2 MB, closed
    comp, peak = _peak(lambda: _compile(text, "c.iface"))
    assert peak < len(text) and [d.name for d in comp.interface.definitions] == ["A"], peak


def test_columns_of_comments_on_one_long_line_read_each_character_once(monkeypatch: pytest.MonkeyPatch) -> None:
    from iface.text.formatter import lex

    walked = _counting(monkeypatch, lex._GapScanner, "column", lambda self, offset: offset - self._at)
    text = "struct S { " + " ".join(f"{i + 1}: i32 f{i} /* c{i} */," for i in range(3000)) + " }\n"
    formatted = format_text(text)
    assert "/* c2999 */" in formatted
    assert 0 < walked["n"] <= 2 * len(text) + len(formatted), (walked["n"], len(text))


class _CountingList(list):
    """A list that counts the elements its iterators hand out."""

    handed = 0

    def __iter__(self):
        for x in super().__iter__():
            _CountingList.handed += 1
            yield x


def test_findings_inside_broken_definitions_are_filtered_in_linear_time(monkeypatch: pytest.MonkeyPatch) -> None:
    from iface.syntax.parse import ParseResult

    real = ParseResult.broken_ranges
    monkeypatch.setattr(ParseResult, "broken_ranges", lambda self: _CountingList(real(self)))
    work = []
    for n in (500, 1000, 2000):
        _CountingList.handed = 0
        text = "".join(f"struct S{i} {{\n    Unknown{i} x\n    i32 = \n}}\n" for i in range(n))
        comp = _compile(text, "b.iface")
        assert sum(d.code == "syntax-error" for d in comp.diagnostics) == n
        assert not any(d.code == "unknown-type" for d in comp.diagnostics)  # inside broken definitions
        work.append(_CountingList.handed)
    assert work[2] <= 2.5 * work[1] + 100 and work[2] <= 10 * 2000, work


def _count_reads(monkeypatch: pytest.MonkeyPatch, cls: type, attr: str) -> dict[str, int]:
    """Count reads of a slotted dataclass attribute (the slot's own descriptor still holds the value)."""
    slot = cls.__dict__[attr]
    count = {"n": 0}

    def read(self: object) -> object:
        count["n"] += 1
        return slot.__get__(self, cls)

    monkeypatch.setattr(cls, attr, property(read, slot.__set__))
    return count


def test_a_long_typedef_chain_is_followed_once_per_compile(monkeypatch: pytest.MonkeyPatch) -> None:
    from iface.model import nodes as m

    reads = _count_reads(monkeypatch, m.Typedef, "type")
    work = []
    for n in (500, 1000, 2000):
        reads["n"] = 0
        text = ("component c\ntypedef i32 T0\n" + "".join(f"typedef T{i} T{i + 1}\n" for i in range(n))
                + "message S {\n" + "".join(f"    T{n} f{i} = 1\n" for i in range(n)) + "}\npublishes S on \"/s\"\n")
        comp = _compile(text, "chain.iface")
        assert not [d for d in comp.diagnostics if d.severity == 1]
        work.append(reads["n"])
    assert work[2] <= 2.5 * work[1] + 100 and work[2] <= 40 * 2000, work


def test_enum_values_are_found_in_constant_time(monkeypatch: pytest.MonkeyPatch) -> None:
    from iface.model import nodes as m

    reads = _count_reads(monkeypatch, m.EnumValue, "name")
    work = []
    for n in (500, 1000, 2000):
        reads["n"] = 0
        text = ("enum E {\n" + "".join(f"    V{i}\n" for i in range(n)) + "}\nstruct S {\n"
                + "".join(f"    E f{i} = V{i}\n" for i in range(n)) + "}\n"
                + "".join(f"const E C{i} = E.V{i}\n" for i in range(n)))
        comp = _compile(text, "enums.iface")
        assert not [d for d in comp.diagnostics if d.severity == 1]
        work.append(reads["n"])
    assert work[2] <= 2.5 * work[1] + 100 and work[2] <= 40 * 2000, work
