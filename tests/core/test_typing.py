"""The package type-checks: ``mypy server/iface`` (pyproject's configuration) finds no error in it."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "server/iface"
#: Path prefixes (relative to the repository, ``/``-separated) whose errors are not counted.
EXCLUDED: tuple[str, ...] = ()

# ``path:line: error: message``; ``:column`` (and end positions) may follow the line
_ERROR = re.compile(r"^(?P<path>.+?):(?P<line>\d+)(?::\d+)*: error: (?P<message>.*)$")
_FOUND = re.compile(r"^Found (?P<errors>\d+) errors? in \d+ files? \(checked (?P<checked>\d+) source files?\)$")
_SUCCESS = re.compile(r"^Success: no issues found in (?P<checked>\d+) source files?$")


def _relative(path: str) -> str:
    """A reported path relative to the repository, with ``/`` separators."""
    p = Path(path)
    if p.is_absolute():
        try:
            p = p.relative_to(ROOT)
        except ValueError:
            pass
    return p.as_posix()


def error_lines(output: str) -> list[tuple[str, str]]:
    """(repository-relative path, whole line) of every error in mypy's output; notes are not errors."""
    out = []
    for line in output.splitlines():
        m = _ERROR.match(line)
        if m:
            out.append((_relative(m.group("path")), line))
    return out


def counted(errors: list[tuple[str, str]], excluded: tuple[str, ...] = EXCLUDED) -> list[str]:
    """The error lines outside the ``excluded`` path prefixes."""
    return [line for path, line in errors if not path.startswith(excluded)]


def summary(output: str) -> tuple[int, int]:
    """(errors, source files checked) from mypy's last line; AssertionError when it has none."""
    last = output.strip().splitlines()[-1] if output.strip() else ""
    found = _FOUND.match(last)
    if found:
        return int(found.group("errors")), int(found.group("checked"))
    success = _SUCCESS.match(last)
    assert success, f"mypy did not finish checking the package; its last line: {last!r}"
    return 0, int(success.group("checked"))


def test_error_lines_are_read_and_filtered() -> None:
    lines = [
        "server/iface/parse.py:113: error: Argument 1 has incompatible type \"None\"  [arg-type]",
        "server/iface/parse.py:113: note: See https://mypy.readthedocs.io",
        "server/iface/emit/base.py:7:5: error: List item 0 has incompatible type  [list-item]",
        "server/iface/commands/generate.py:40: error: Name \"x\" already defined  [no-redef]",
        "server/iface/commands/generate_more.py:3: error: Missing return statement  [return]",
        f"{ROOT / 'server' / 'iface' / 'lsp' / 'server.py'}:48:1:48:9: error: No overload variant  [call-overload]",
        "Found 5 errors in 5 files (checked 123 source files)",
    ]
    output = "\n".join(lines)
    errors = error_lines(output)
    assert [path for path, _ in errors] == [
        "server/iface/parse.py", "server/iface/emit/base.py", "server/iface/commands/generate.py",
        "server/iface/commands/generate_more.py", "server/iface/lsp/server.py"]
    assert counted(errors, ("server/iface/emit/", "server/iface/commands/generate.py")) == [
        lines[0], lines[4], lines[5]]
    assert counted(errors, ()) == [lines[0], lines[2], lines[3], lines[4], lines[5]]
    assert summary(output) == (5, 123)
    assert summary("Success: no issues found in 9 source files\n") == (0, 9)
    with pytest.raises(AssertionError, match="did not finish"):
        summary("server/iface/x.py:1: error: invalid syntax  [syntax]\n"
                "Found 1 error in 1 file (errors prevented further checking)\n")


def mypy_cache() -> Path:
    """mypy's incremental cache, in the test cache (tests/ros_harness/cache.py), one for every checkout: mypy
    checks each module's source (by its digest where the path or time differ) against what it keeps, so a run
    from another clone reads again only what changed, and the folder stays one (about 20 MB). The folders of
    one per checkout that came before it are removed."""
    from tests.ros_harness.cache import root

    for old in root().glob("mypy-*"):
        shutil.rmtree(old, ignore_errors=True)
    return root() / "mypy"


def test_every_checkout_shares_one_mypy_cache(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """A folder per checkout grew the test cache by 20 MB for each clean clone (one per CI run), outside its bound."""
    monkeypatch.setenv("IFACE_TEST_CACHE", str(tmp_path))
    here = mypy_cache()
    (here.parent / "mypy-0123456789abcdef").mkdir()
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path / "another" / "clone")
    assert mypy_cache() == here
    assert [p.name for p in here.parent.glob("mypy*")] == []


def test_mypy_finds_no_error_outside_the_excluded_modules() -> None:
    pytest.importorskip("mypy", reason="mypy is not installed (it comes with pip install -e '.[test]')")
    env = {k: v for k, v in os.environ.items() if k not in ("MYPY_FORCE_COLOR", "FORCE_COLOR")}
    proc = subprocess.run(
        [sys.executable, "-m", "mypy", "--no-pretty", "--no-color-output", "--error-summary", "--cache-dir",
         str(mypy_cache()), PACKAGE], cwd=ROOT, capture_output=True, text=True, timeout=600, env=env, check=False)
    output = proc.stdout
    assert proc.returncode in (0, 1), f"mypy failed to run (exit {proc.returncode}):\n{output}{proc.stderr}"
    total, checked = summary(output)
    errors = error_lines(output)
    assert checked > 0
    assert len(errors) == total, f"read {len(errors)} error lines but mypy reports {total}:\n{output}"
    found = counted(errors)
    assert found == [], (f"mypy finds {len(found)} type error(s) in {PACKAGE} outside {', '.join(EXCLUDED)}:\n"
                         + "\n".join(found))
