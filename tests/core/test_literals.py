"""Literals no type can hold are check errors, never a traceback in a later command.

Lone surrogate escapes (``"\\uD800"``) cannot be written as UTF-8; integer
literals beyond 64 bits (5,000 digits exceed Python's int-from-string limit);
floats beyond float64 (``1e999``, infinity) or float32; NaN and infinite range
bounds; values nested deeper than types may be.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from iface.semantics.compile import Workspace
from iface.syntax.transform import decode_literal
from tests.conftest import run_main

TARGETS = ("ros2", "px4", "ardupilot", "idl", "json", "markdown")

SURROGATE = '''component sur version "1.0.0"
namespace ros2 sur_msgs
message M {
    string s = "\\uD800"
}
publishes M on "/m"
'''
HUGE = f'''component num version "1.0.0"
namespace ros2 num_msgs
message M {{
    float64 a = 1e999,
    i64 b = {"1" * 5000},
    float32 c = 1e39
}}
const i32 X = {"7" * 5000}
publishes M on "/m"
'''
RANGES = '''component rng version "1.0.0"
namespace ros2 rng_msgs
configuration params {
    float64 a = 1.0 (range = "0..inf"),
    float64 b = 1.0 (range = "nan..2"),
    float64 c = 1.0 (min = "-inf"),
    i32 d = 1 (range = "-1e400..5")
}
message M { i32 x }
subscribes M on "/m"
'''


def _codes(text: str, name: str = "x.iface") -> list[tuple[int, str]]:
    comp = Workspace().compile_text(f"/virtual/{name}", text)
    return sorted((d.location()[0], d.code) for d in comp.diagnostics if d.severity == 1)


def test_a_lone_surrogate_escape_is_an_error_at_the_escape() -> None:
    comp = Workspace().compile_text("/virtual/s.iface", SURROGATE)
    (d,) = [d for d in comp.diagnostics if d.severity == 1]
    assert d.code == "invalid-escape" and d.location() == (4, 17, 4, 23)
    assert "U+FFFD" not in d.message and "surrogate" in d.message
    value = comp.interface.definitions[0].fields[0].default.value
    assert value == "\ufffd"  # the model never holds a surrogate
    value.encode("utf-8")


def test_every_escape_that_names_no_character_is_refused() -> None:
    for escape in ("\\uD800", "\\uDBFF", "\\uDC00", "\\uDFFF", "\\uD83D\\u0041", "\\uDE00\\uD83D"):
        found: list[tuple[int, int, str]] = []
        value = decode_literal(f'"{escape}"', found)
        assert found, escape
        value.encode("utf-8")
    found = []
    assert decode_literal('"\\uD83D\\uDE00 \\u00e9"', found) == "\U0001F600 \u00e9" and found == []


def test_a_raw_surrogate_in_an_editor_buffer_is_an_error() -> None:
    comp = Workspace().compile_text("/virtual/raw.iface", 'message M { string s = "a\ud800" }\n')
    assert [d.code for d in comp.diagnostics if d.severity == 1] == ["invalid-encoding"]
    comp.interface.definitions[0].fields[0].default.value.encode("utf-8")


def test_numbers_beyond_every_type_are_errors() -> None:
    assert _codes(HUGE) == [(4, "number-out-of-range"), (5, "number-out-of-range"), (6, "number-out-of-range"),
                            (8, "number-out-of-range")]


def test_integer_literals_at_the_64_bit_edges() -> None:
    ok = "const u64 A = 18446744073709551615\nconst i64 B = -9223372036854775808\nconst i64 C = 0x7fffffffffffffff\n"
    assert _codes(ok) == []
    assert _codes("const u64 A = 18446744073709551616\n") == [(1, "number-out-of-range")]
    assert _codes("const i64 A = -9223372036854775809\n") == [(1, "number-out-of-range")]
    assert _codes("const u64 A = 0x10000000000000000\n") == [(1, "number-out-of-range")]
    assert _codes("const u64 A = 000000000000000000000000001\n") == []
    # one finding per literal: the type check does not repeat the parser's
    assert _codes("const u8 A = 18446744073709551616\n") == [(1, "number-out-of-range")]


@pytest.mark.parametrize("where", ["struct S { 1: string<=9999999999999999999999 s }",
                                   "struct S { 99999999999999999999999: i32 s }",
                                   "struct S { 1: i32[99999999999999999999999] s }",
                                   "enum E { A = 99999999999999999999999 }",
                                   "struct S { 1: i32 s (x = 99999999999999999999999) }"])
def test_a_huge_integer_anywhere_is_one_error(where: str) -> None:
    assert _codes(where + "\n", "x.thrift") == [(1, "number-out-of-range")]


def test_float32_range() -> None:
    assert _codes("const float32 A = 3.4028235e38\nconst float32 B = -3.4e38\n") == []
    assert _codes("const float32 A = 3.5e38\n") == [(1, "number-out-of-range")]
    assert _codes("const float64 A = 3.5e38\nconst float64 B = 1e-999\n") == []


def test_nan_and_infinite_range_bounds_are_errors() -> None:
    assert _codes(RANGES) == [(4, "number-out-of-range"), (5, "number-out-of-range"), (6, "number-out-of-range"),
                              (7, "number-out-of-range")]
    comp = Workspace().compile_text("/virtual/r.iface", RANGES)
    assert all(f.range is None for f in comp.interface.definitions[0].fields)


def test_values_nested_deeper_than_types_are_refused_and_kept_shallow() -> None:
    n = 5000
    text = "const list<i32> X = " + "[" * n + "]" * n + "\nconst map<i32, i32> Y = " + "{1: " * n + "2" + "}" * n + "\n"
    comp = Workspace().compile_text("/virtual/deep.iface", text)
    assert sorted(d.code for d in comp.diagnostics if d.severity == 1) == ["nesting-too-deep", "nesting-too-deep"]


@pytest.mark.parametrize("text", [SURROGATE, HUGE, RANGES], ids=["surrogate", "huge", "ranges"])
def test_every_command_answers_without_a_traceback(text: str, tmp_path: Path) -> None:
    src = tmp_path / "in.iface"
    src.write_text(text, encoding="utf-8")
    r = run_main("check", str(src))
    assert r.returncode == 1 and ("number-out-of-range" in r.stdout or "invalid-escape" in r.stdout), r.stdout
    for target in TARGETS:
        out = tmp_path / f"out-{target}"
        r = run_main("generate", str(src), "-t", target, "-o", str(out))
        assert r.returncode == 1, (target, r.stdout, r.stderr)
        assert "Traceback" not in r.stderr and not out.exists(), (target, r.stderr)
    for command in (["dump"], ["hash"], ["contract"], ["compat", str(src)], ["graph"], ["fmt", "--check"]):
        r = run_main(*command, str(src))
        assert r.returncode in (0, 1, 2), (command, r.stderr)
        assert "Traceback" not in r.stderr + r.stdout, (command, r.stderr)
