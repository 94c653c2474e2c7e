"""The CLI's exit codes hold whatever happens: internal errors, a closed pipe, unreadable files, control
characters in the input."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.conftest import ROOT, run_cli

BAD = 'message M {\n    Unknown x\n}\npublishes M on "/m"\n'

#: Runs the CLI with one command's run() replaced by a function that raises: a stand-in for any bug.
_BROKEN_COMMAND = '''
import sys
import iface.commands.hash as command
def boom(args):
    raise RuntimeError("boom\\nsecond line")
command.run = boom
from iface.cli import main
sys.exit(main(sys.argv[1:]))
'''


def _bad(tmp_path: Path, n: int = 1) -> Path:
    p = tmp_path / "bad.iface"
    p.write_text(BAD * n if n == 1 else "".join(BAD.replace("M", f"M{i}") for i in range(n)))
    return p


def test_an_unexpected_exception_is_one_line_and_exit_3(tmp_path: Path) -> None:
    src = _bad(tmp_path)
    r = subprocess.run([sys.executable, "-c", _BROKEN_COMMAND, "hash", str(src)], capture_output=True, text=True,
                       cwd=ROOT, timeout=300)
    assert r.returncode == 3, r.stderr
    assert "Traceback" not in r.stderr
    (line,) = r.stderr.splitlines()
    assert line.startswith("iface-lsp hash: internal error: RuntimeError: boom second line")
    assert "--debug" in line


def test_debug_shows_the_traceback(tmp_path: Path) -> None:
    src = _bad(tmp_path)
    for args in (["--debug", "hash", str(src)], ["hash", str(src), "--debug"]):
        r = subprocess.run([sys.executable, "-c", _BROKEN_COMMAND, *args], capture_output=True, text=True,
                           cwd=ROOT, timeout=300)
        assert r.returncode == 3 and "Traceback (most recent call last)" in r.stderr, r.stderr
        assert "RuntimeError: boom" in r.stderr


#: Runs the CLI as if a dependency were not installed: importing it fails as a missing module does.
_WITHOUT = """
import sys
sys.modules[sys.argv.pop(1)] = None
from iface.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_a_missing_dependency_is_one_line_that_says_how_to_install_and_exit_3(tmp_path: Path) -> None:
    src = _bad(tmp_path)
    good = str(ROOT / "examples" / "robot_arm.iface")
    for missing, args, prog in (("lark", ["check", str(src)], "iface-lsp check"), ("pygls", ["--stdio"], "iface-lsp"),
                                ("jinja2", ["generate", good, "--target", "rclpy", "--out", str(tmp_path / "out")],
                                 "iface-lsp generate")):
        r = subprocess.run([sys.executable, "-c", _WITHOUT, missing, *args], capture_output=True, text=True, cwd=ROOT,
                           timeout=300, stdin=subprocess.DEVNULL, check=False)
        assert r.returncode == 3 and "Traceback" not in r.stderr, r.stderr
        (line,) = r.stderr.splitlines()
        assert line.startswith(f"{prog}: internal error: ModuleNotFoundError: "), line
        assert missing in line and "pip install ." in line and "a bug in iface" not in line, line
    r = subprocess.run([sys.executable, "-c", _WITHOUT, "lark", "--debug", "check", str(src)], capture_output=True,
                       text=True, cwd=ROOT, timeout=300, check=False)
    assert r.returncode == 3 and "Traceback (most recent call last)" in r.stderr, r.stderr


def test_findings_and_usage_keep_their_codes(tmp_path: Path) -> None:
    assert run_cli("check", str(_bad(tmp_path))).returncode == 1
    assert run_cli("check", "--nonsense", str(_bad(tmp_path))).returncode == 2
    assert run_cli("--version").returncode == 0


def _into_closed_pipe(*args: str) -> subprocess.CompletedProcess[bytes]:
    """Run the CLI with stdout a pipe whose reader is gone, as in ``iface-lsp check bad.iface | head -c0``."""
    read, write = os.pipe()
    os.close(read)
    try:
        return subprocess.run([sys.executable, "-m", "iface", *args], stdout=write, stderr=subprocess.PIPE,
                              timeout=300)
    finally:
        os.close(write)


def test_a_closed_stdout_keeps_the_findings_exit_status(tmp_path: Path) -> None:
    for n in (1, 2000):  # a few bytes (lost at the last flush) and far more than a pipe holds (lost midway)
        r = _into_closed_pipe("check", str(_bad(tmp_path, n)))
        assert r.returncode == 1, r.stderr
        assert len(r.stderr.decode().splitlines()) <= 1 and b"Traceback" not in r.stderr, r.stderr


def test_a_closed_stdout_keeps_a_clean_exit_status(tmp_path: Path) -> None:
    good = tmp_path / "good.iface"
    good.write_text('message M { i32 x }\npublishes M on "/m"\n')
    r = _into_closed_pipe("dump", str(good))
    assert r.returncode == 0 and len(r.stderr.splitlines()) <= 1, r.stderr


def test_a_missing_file_is_one_io_diagnostic_beside_the_others(tmp_path: Path) -> None:
    bad = _bad(tmp_path)
    missing = tmp_path / "missing.iface"
    r = run_cli("check", str(bad), str(missing), cwd=tmp_path)
    assert r.returncode == 2, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    assert "bad.iface:2:5: error[unknown-type]: unknown type 'Unknown'" in lines
    assert [line for line in lines if "missing.iface" in line] == ["missing.iface:1:1: error[cannot-read]: no such file"]
    assert lines[-1].startswith("failed: 2 errors in 2 files (1 not read), "), lines[-1]
    r = run_cli("check", "--format", "json", str(bad), str(missing), cwd=tmp_path)
    found = [(d["file"], d["code"]) for d in json.loads(r.stdout)["diagnostics"]]
    assert ("bad.iface", "unknown-type") in found and ("missing.iface", "cannot-read") in found
    assert r.returncode == 2


def test_a_folder_is_an_io_diagnostic(tmp_path: Path) -> None:
    (tmp_path / "dir.iface").mkdir()
    r = run_cli("check", str(tmp_path / "dir.iface"), cwd=tmp_path)
    assert r.returncode == 2 and "dir.iface:1:1: error[cannot-read]: is a folder, not a file" in r.stdout


CONTROLS = ('component ctl\nmessage M { i32 x }\npublishes M on "/a\\u001b[2J\\u001b]0;pwned\\u0007"\n'
            'subscribes M on "/b\\u0085\\u202e\\u0008x"\n')


def test_control_characters_from_the_input_are_escaped_in_terminal_output(tmp_path: Path) -> None:
    src = tmp_path / "ctl.iface"
    src.write_text(CONTROLS)
    outputs = []
    for args in (["check", str(src)], ["graph", str(src)], ["contract", str(src)], ["compat", str(src), str(src)],
                 ["generate", str(src), "-t", "markdown", "-o", str(tmp_path / "o")]):
        r = subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, timeout=300)
        outputs.append((args[0], r.stdout + r.stderr))
    check = outputs[0][1].decode()
    assert "\\u001b[2J" in check, check  # shown, escaped
    for name, out in outputs:
        text = out.decode("utf-8")
        bad = [c for c in text if (ord(c) < 32 and c not in "\n\t") or 0x7F <= ord(c) <= 0x9F or c == "\u202e"]
        assert not bad, (name, bad, text)


def test_json_output_stays_valid_and_keeps_the_characters(tmp_path: Path) -> None:
    src = tmp_path / "ctl.iface"
    src.write_text(CONTROLS)
    r = run_cli("check", "--format", "json", str(src))
    messages = [d["message"] for d in json.loads(r.stdout)["diagnostics"]]
    assert any("\x1b[2J" in m for m in messages)
    r = run_cli("dump", str(src))
    assert "\u0085" in json.dumps(json.loads(r.stdout), ensure_ascii=False)


def test_json_import_of_numbers_and_nesting_no_parser_takes(tmp_path: Path) -> None:
    (tmp_path / "digits.json").write_text('{"format": "iface-json/1", "items": [], "id": ' + "9" * 5000 + "}")
    (tmp_path / "deep.json").write_text("[" * 100_000 + "]" * 100_000)
    for name in ("digits.json", "deep.json"):
        r = run_cli("import", "--from", "json", str(tmp_path / name), "--out", str(tmp_path / "out"))
        assert r.returncode == 1, r.stderr
        assert "Traceback" not in r.stderr and "internal error" not in r.stderr
        assert f"{name}: not the iface JSON form" in r.stderr
