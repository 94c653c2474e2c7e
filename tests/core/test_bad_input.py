"""Bad input gets a clear message with file:line:col and a code, never a traceback."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.conftest import run_main


def _check(tmp_path: Path, name: str, data: bytes):
    p = tmp_path / name
    p.write_bytes(data)
    return run_main("check", str(p))


def _assert_clean_failure(r, code: str, rc: int = 1) -> None:
    assert "Traceback" not in r.stderr and "Traceback" not in r.stdout
    assert r.returncode == rc, r.stdout + r.stderr
    assert f"[{code}]" in r.stdout, r.stdout


def test_binary_file(tmp_path: Path) -> None:
    r = _check(tmp_path, "blob.iface", b"struct A {}\n\x00\x01\x02\xff" * 10)
    _assert_clean_failure(r, "binary-file")
    assert "blob.iface:2:1:" in r.stdout


def test_five_megabyte_file(tmp_path: Path) -> None:
    r = _check(tmp_path, "huge.iface", b"// padding\n" * (5 * 1024 * 1024 // 11 + 1))
    _assert_clean_failure(r, "file-too-large")
    assert "huge.iface:1:1:" in r.stdout and "MB" in r.stdout


def test_thousand_levels_of_nesting(tmp_path: Path) -> None:
    text = "struct Deep {\n  1: " + "list<" * 1000 + "i32" + ">" * 1000 + " x\n}\n"
    r = _check(tmp_path, "deep.thrift", text.encode())
    _assert_clean_failure(r, "nesting-too-deep")
    assert "deep.thrift:2:" in r.stdout


def test_thousand_nested_const_lists(tmp_path: Path) -> None:
    text = "const list<i32> X = " + "[" * 1000 + "]" * 1000 + "\n"
    r = _check(tmp_path, "deepconst.thrift", text.encode())
    assert "Traceback" not in r.stderr
    assert r.returncode in (0, 1)


def test_empty_file(tmp_path: Path) -> None:
    r = _check(tmp_path, "empty.iface", b"")
    assert r.returncode == 0
    assert "empty.iface:1:1: information[empty-file]" in r.stdout


def test_invalid_utf8(tmp_path: Path) -> None:
    r = _check(tmp_path, "latin1.iface", "struct A {\n  1: string s = \"caf".encode() + b"\xe9\"\n}\n")
    _assert_clean_failure(r, "invalid-encoding")
    assert "latin1.iface:2:21:" in r.stdout


@pytest.mark.parametrize("name", ["missing.iface"])
def test_missing_file_is_an_io_error(tmp_path: Path, name: str) -> None:
    r = run_main("check", str(tmp_path / name))
    assert r.returncode == 2
    assert "missing.iface:1:1: error[cannot-read]: no such file" in r.stdout and "Traceback" not in r.stderr


def test_wrong_suffix_is_a_usage_error(tmp_path: Path) -> None:
    p = tmp_path / "x.txt"
    p.write_text("struct A {}")
    r = run_main("check", str(p))
    assert r.returncode == 2 and ".iface or .thrift" in r.stderr


def test_random_garbage_never_crashes() -> None:
    import random

    from iface.semantics.compile import Workspace

    rng = random.Random(7)
    pieces = ["struct", "{", "}", "(", ")", "<", ">", "[", "]", "=", ",", ";", "\"", "'", "/*", "*/", "//",
              "i32", "x", "1:", "service", "message", "list<", "map<", "publishes", "on", "0x", "-", "\n", "é",
              "request", "goal", "const", "enum", "include", "\"a.iface\"", "string<=", "[<=", "\x00"]
    ws = Workspace()
    for i in range(500):
        text = " ".join(rng.choice(pieces) for _ in range(rng.randint(1, 80)))
        comp = ws.compile_text(f"/virtual/g{i % 7}.iface", text)
        for d in comp.all_diagnostics():
            d.format()
