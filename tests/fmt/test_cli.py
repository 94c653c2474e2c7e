"""``iface-lsp fmt`` end to end: the real CLI in a subprocess."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

UGLY = "struct A{1:i32 a}\n"
PRETTY = "struct A {\n    1: i32 a\n}\n"


def fmt(*args: str, cwd: Path, stdin: bytes | None = None) -> subprocess.CompletedProcess[bytes]:
    """Run ``python -m iface fmt ARGS`` with byte-exact input and output."""
    return subprocess.run([sys.executable, "-m", "iface", "fmt", *args], capture_output=True, cwd=cwd,
                          input=stdin, timeout=120)


@pytest.fixture
def files(tmp_path: Path) -> Path:
    (tmp_path / "ugly.iface").write_text(UGLY)
    (tmp_path / "pretty.thrift").write_text(PRETTY)
    return tmp_path


def test_rewrites_in_place(files: Path) -> None:
    r = fmt("ugly.iface", "pretty.thrift", cwd=files)
    assert r.returncode == 0, r.stderr
    assert (files / "ugly.iface").read_text() == PRETTY
    assert (files / "pretty.thrift").read_text() == PRETTY
    assert sorted(p.name for p in files.iterdir()) == ["pretty.thrift", "ugly.iface"]  # no temp files left


def test_rewrite_keeps_the_file_mode(files: Path) -> None:
    path = files / "ugly.iface"
    path.chmod(0o640)
    assert fmt("ugly.iface", cwd=files).returncode == 0
    assert stat.S_IMODE(path.stat().st_mode) == 0o640


def test_unchanged_file_is_not_rewritten(files: Path) -> None:
    path = files / "pretty.thrift"
    os.utime(path, ns=(1_000_000_000, 1_000_000_000))
    assert fmt("pretty.thrift", cwd=files).returncode == 0
    assert path.stat().st_mtime_ns == 1_000_000_000


def test_check_reports_and_writes_nothing(files: Path) -> None:
    r = fmt("--check", "ugly.iface", "pretty.thrift", cwd=files)
    assert r.returncode == 1
    assert r.stdout.decode() == "ugly.iface: would reformat\n"
    assert (files / "ugly.iface").read_text() == UGLY


def test_check_passes_on_formatted_files(files: Path) -> None:
    r = fmt("--check", "pretty.thrift", cwd=files)
    assert (r.returncode, r.stdout) == (0, b"")


def test_diff_prints_and_writes_nothing(files: Path) -> None:
    r = fmt("--diff", "ugly.iface", cwd=files)
    assert r.returncode == 0
    out = r.stdout.decode()
    assert "--- ugly.iface (original)" in out and "+++ ugly.iface (formatted)" in out
    assert "-struct A{1:i32 a}\n" in out and "+    1: i32 a\n" in out
    assert (files / "ugly.iface").read_text() == UGLY


def test_check_with_diff_exits_1(files: Path) -> None:
    r = fmt("--check", "--diff", "ugly.iface", cwd=files)
    assert r.returncode == 1
    assert b"+    1: i32 a" in r.stdout


def test_stdin_to_stdout(tmp_path: Path) -> None:
    r = fmt("-", cwd=tmp_path, stdin=b"struct A{1:i32 a}\r\n")
    assert (r.returncode, r.stdout) == (0, PRETTY.encode())


def test_stdin_check(tmp_path: Path) -> None:
    r = fmt("--check", "-", cwd=tmp_path, stdin=UGLY.encode())
    assert (r.returncode, r.stdout) == (1, b"-: would reformat\n")
    r = fmt("--check", "-", cwd=tmp_path, stdin=PRETTY.encode())
    assert (r.returncode, r.stdout) == (0, b"")


@pytest.mark.parametrize(("args", "message"), [
    (["missing.iface"], "missing.iface: no such file"),
    (["notes.txt"], "notes.txt: expected a .iface or .thrift file"),
    (["--indent", "0", "ugly.iface"], "--indent must be between 1 and 16"),
])
def test_usage_errors_exit_2_and_touch_nothing(files: Path, args: list[str], message: str) -> None:
    (files / "notes.txt").write_text("x")
    r = fmt(*args, "ugly.iface", cwd=files)
    assert r.returncode == 2
    err = r.stderr.decode()
    assert message in err and "Traceback" not in err
    assert (files / "ugly.iface").read_text() == UGLY


def test_invalid_utf8_is_reported_with_its_position(files: Path) -> None:
    bad = files / "bad.iface"
    bad.write_bytes(b"struct A {\n  1: string s = \"\xff\"\n}\n")
    r = fmt("bad.iface", "ugly.iface", cwd=files)
    assert r.returncode == 2
    err = r.stderr.decode()
    assert "bad.iface:2:18: byte 0xff is not valid UTF-8" in err and "Traceback" not in err
    assert bad.read_bytes() == b"struct A {\n  1: string s = \"\xff\"\n}\n"
    assert (files / "ugly.iface").read_text() == PRETTY  # the other files are still formatted


def test_binary_file_is_refused(files: Path) -> None:
    (files / "bin.iface").write_bytes(b"struct\0A")
    r = fmt("bin.iface", cwd=files)
    assert r.returncode == 2 and b"NUL bytes" in r.stderr


def test_syntax_errors_are_noted_and_kept(files: Path) -> None:
    src = "struct A{1:i32 a}\nstruct Bad {\n  1: i32 =\n}\n"
    (files / "mixed.iface").write_text(src)
    r = fmt("mixed.iface", cwd=files)
    assert r.returncode == 0
    assert "mixed.iface:2:1: note[fmt-syntax-error]" in r.stderr.decode()
    assert (files / "mixed.iface").read_text() == PRETTY + "struct Bad {\n  1: i32 =\n}\n"


def test_files_rewritten_are_named_and_quiet_silences(files: Path) -> None:
    r = fmt("ugly.iface", "pretty.thrift", cwd=files)
    assert (r.returncode, r.stdout, r.stderr.decode()) == (0, b"", "formatted ugly.iface\n")
    (files / "ugly.iface").write_text(UGLY)
    r = fmt("-q", "ugly.iface", cwd=files)
    assert (r.returncode, r.stdout, r.stderr) == (0, b"", b"")
    assert (files / "ugly.iface").read_text() == PRETTY
