"""Every command and every target over every file ``check`` accepts: never a traceback, never an internal error.

Inputs: the ``.iface`` and ``.thrift`` files of tests/, the Thrift files of the shared corpus and its ROS 2
packages imported to ``.iface`` (when the corpus is present: ``IFACE_CORPUS``, else ``../shared/corpus``),
and the edge cases of ``edge_cases.py`` (hand-written limits and seeded random interfaces). A file with an
error is left out: the promise is that whatever passes ``check`` works with every command.

The commands run in this process (``iface.cli.main``), so the whole run costs a few seconds per hundred files.
"""

from __future__ import annotations

import io
import os
import sys
from collections.abc import Iterator
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from iface.cli import main
from iface.emit.registry import targets
from iface.semantics.compile import Workspace
from tests.conftest import ROOT

from .edge_cases import HAND_WRITTEN, HOSTILE, random_cases

TESTS = ROOT / "tests"
TARGETS = sorted(targets())


def corpus() -> Path | None:
    """The shared corpus of real interface files, when this machine has it."""
    for candidate in (os.environ.get("IFACE_CORPUS"), ROOT.parent / "shared" / "corpus",
                      ROOT.parents[1] / "shared" / "corpus"):
        if candidate and Path(candidate).is_dir():
            return Path(candidate)
    return None


def accepted(path: Path) -> bool:
    """True when ``check`` finds no error in the file or what it includes."""
    comp = Workspace().compile_path(str(path))
    return not any(d.severity == 1 for d in comp.all_diagnostics())


def _test_inputs() -> list[Path]:
    files = sorted(p for p in TESTS.rglob("*") if p.suffix in (".iface", ".thrift") and p.is_file())
    seen: set[bytes] = set()
    out = []
    for p in files:
        data = p.read_bytes()
        if data not in seen and accepted(p):  # the same text twice is tried once
            seen.add(data)
            out.append(p)
    return out


INPUTS = _test_inputs()


def run(*argv: str, stdin: bytes = b"") -> tuple[int, str]:
    """``iface-lsp ARGV`` in this process: (exit code, stdout and stderr)."""
    out, err = io.StringIO(), io.StringIO()
    saved = sys.stdin
    sys.stdin = io.TextIOWrapper(io.BytesIO(stdin), encoding="utf-8")
    try:
        with redirect_stdout(out), redirect_stderr(err):
            code = main(list(argv))
    finally:
        sys.stdin = saved
    return code, out.getvalue() + err.getvalue()


def every_command(path: Path, work: Path) -> Iterator[tuple[list[str], int, str]]:
    """Run each command over ``path`` (outputs under ``work``); yields (arguments, exit code, output)."""
    f = str(path)
    commands: list[list[str]] = [
        ["check", f], ["check", "--format", "json", f], ["dump", f], ["hash", f], ["contract", f],
        ["graph", f], ["graph", "--format", "json", f], ["compat", f, f], ["compat", "--format", "json", f, f],
        ["impact", "--system", f, "--replace", f, f], ["fmt", "--check", f], ["fmt", "--diff", f],
        ["handover", "/old", "/new", "--old", f, "--new", f, "--timeout", "1"],
        ["sign", str(work), "--verify", "--trust-store", str(work)],
        ["manager", f, "--state-dir", str(work / "state")], ["system", "status", f, "--manager-timeout", "1"],
    ]
    for argv in commands:
        yield (argv, *run(*argv))
    yield (["fmt", "-"], *run("fmt", "-", stdin=path.read_bytes()))
    for target in TARGETS:
        out = work / target
        for argv in (["generate", f, "-t", target, "-o", str(out)],
                     ["generate", f, "-t", target, "-o", str(out), "--check"],
                     ["generate", f, "-t", target, "-o", str(out), "--dry-run"]):
            yield (argv, *run(*argv))
    exported = sorted((work / "json").glob("*.json"))
    if exported:
        argv = ["import", "--from", "json", *map(str, exported), "--out", str(work / "imported")]
        yield (argv, *run(*argv))
        for imported in sorted((work / "imported").glob("*.iface")):
            yield (["check", str(imported)], *run("check", str(imported)))
        argv = ["roundtrip", "--from", "json", *map(str, exported)]
        yield (argv, *run(*argv))


def assert_every_command_answers(path: Path, work: Path) -> None:
    """No traceback, no internal error, no exit code 3, for any command over ``path``."""
    for argv, code, output in every_command(path, work):
        shown = " ".join(argv)
        assert code in (0, 1, 2), f"iface-lsp {shown}: exit {code}\n{output[-3000:]}"
        assert "Traceback" not in output, f"iface-lsp {shown}:\n{output[-3000:]}"
        assert "internal error" not in output and "internal-error" not in output, \
            f"iface-lsp {shown}:\n{output[-3000:]}"


@pytest.mark.parametrize("path", INPUTS, ids=lambda p: str(p.relative_to(TESTS)))
def test_every_command_over_the_test_files(path: Path, tmp_path: Path) -> None:
    assert_every_command_answers(path, tmp_path)


def _cases(cases: list[tuple[str, str]]) -> list:
    return [pytest.param(name, text, id=name) for name, text in cases]


@pytest.mark.parametrize("name, text", _cases(HAND_WRITTEN + random_cases(15, 40)))
def test_every_command_over_edge_cases(name: str, text: str, tmp_path: Path) -> None:
    src = tmp_path / "in" / name
    src.parent.mkdir()
    src.write_text(text, encoding="utf-8")
    if not accepted(src):
        comp = Workspace().compile_path(str(src))
        errors = [d.format() for d in comp.all_diagnostics() if d.severity == 1]
        assert name.startswith("random_"), f"a hand-written edge case must pass check: {errors}"
        pytest.skip(f"check refuses this random interface ({errors[0]})")
    assert_every_command_answers(src, tmp_path / "work")


@pytest.mark.parametrize("name, text", _cases(HOSTILE))
def test_every_command_over_hostile_input_check_accepts(name: str, text: str, tmp_path: Path) -> None:
    """Surrogates, infinities, 5,000 digits, control characters…: refused by check, or fine everywhere."""
    src = tmp_path / "in" / name
    src.parent.mkdir()
    src.write_text(text, encoding="utf-8")
    code, output = run("check", str(src))
    assert code in (0, 1) and "Traceback" not in output, output[-3000:]
    if code == 0:
        assert_every_command_answers(src, tmp_path / "work")


def test_the_edge_cases_are_accepted() -> None:
    """Most random cases pass check, so that the test above really exercises the commands."""
    cases = random_cases(15, 40)
    kept = 0
    for name, text in cases:
        comp = Workspace().compile_text(f"/virtual/{name}", text)
        kept += not any(d.severity == 1 for d in comp.all_diagnostics())
    assert kept >= 30, f"only {kept} of {len(cases)} random cases pass check"


CORPUS = corpus()


@pytest.mark.skipif(CORPUS is None, reason="the shared corpus (IFACE_CORPUS or ../shared/corpus) is not here")
def test_every_command_over_the_corpus(tmp_path: Path) -> None:
    assert CORPUS is not None
    tried = 0
    for path in sorted(CORPUS.rglob("*.thrift")):
        if accepted(path):
            assert_every_command_answers(path, tmp_path / f"t{tried}")
            tried += 1
    packages = sorted({p.parent.parent for p in CORPUS.rglob("*.msg")} | {p.parent.parent for p in
                                                                          CORPUS.rglob("*.srv")})
    imported = tmp_path / "ros2"
    code, output = run("import", "--from", "ros2", *map(str, packages), "--out", str(imported), "-q")
    assert code in (0, 1) and "Traceback" not in output, output[-3000:]
    for path in sorted(imported.rglob("*.iface")):
        if accepted(path):
            assert_every_command_answers(path, tmp_path / f"r{tried}")
            tried += 1
    assert tried > 20
