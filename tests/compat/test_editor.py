"""The editor API: findings as diagnostics in NEW, fixes that work, baselines from files and git."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from compat_support import DATA, compile_file

from iface.compat import baseline_diagnostics, compare, load_baseline
from iface.model.diagnostics import Severity
from iface.semantics.compile import Workspace


def _apply(text: str, edits: list[dict]) -> str:
    for e in sorted(edits, key=lambda e: e["start"], reverse=True):
        text = text[:e["start"]] + e["text"] + text[e["end"]:]
    return text


def test_diagnostics_are_located_in_new() -> None:
    old = compile_file(DATA / "verdicts" / "arm_v1.iface")
    new = compile_file(DATA / "verdicts" / "arm_v3.iface")
    diags = baseline_diagnostics(old, new)
    assert diags and all(d.path == new.path for d in diags)
    assert {d.code for d in diags} == {"compat-field-removed", "compat-definition-removed",
                                       "compat-published-removed"}
    removed = next(d for d in diags if d.code == "compat-published-removed")
    assert removed.severity == Severity.ERROR
    assert removed.related[0].source.path == old.path
    assert removed.data["fix"]["kind"] == "restore"


@pytest.mark.parametrize(("rule", "kind"), [
    ("required-field-added", "make-optional"),
    ("field-requiredness-changed", "make-optional"),
    ("parameter-added-required", "add-default"),
    ("state-needs-initial", "add-default"),
    ("field-removed", "restore"),
    ("published-removed", "restore"),
    ("service-removed", "restore"),
    ("definition-removed", "restore"),
    ("function-removed", "restore"),
    ("enum-value-removed", "restore"),
    ("namespace-removed", "restore"),
])
def test_fix_removes_the_finding(rule: str, kind: str, tmp_path: Path) -> None:
    case = DATA / "rules" / rule
    old, new = compile_file(case / "old.iface"), compile_file(case / "new.iface")
    diag = next(d for d in baseline_diagnostics(old, new) if d.code == f"compat-{rule}")
    fix = diag.data["fix"]
    assert fix["kind"] == kind
    fixed_text = _apply(new.source.text, fix["edits"])
    fixed = Workspace().compile_text(str(tmp_path / "fixed.iface"), fixed_text)
    assert not fixed.has_errors, [d.format() for d in fixed.diagnostics]
    assert rule not in {f.rule for f in compare(old, fixed).findings if f.severity == Severity.ERROR or
                        f.severity == Severity.WARNING}


def test_load_baseline_from_a_file(tmp_path: Path) -> None:
    base = load_baseline(str(DATA / "verdicts" / "arm_v3.iface"), "arm_v1.iface")
    assert base is not None and base.path.endswith("arm_v1.iface")
    assert load_baseline(str(DATA / "verdicts" / "arm_v3.iface"), "nope.iface") is None


@pytest.mark.skipif(shutil.which("git") is None, reason="git is not installed")
def test_load_baseline_from_git(tmp_path: Path) -> None:
    def git(*args: str) -> None:
        subprocess.run(["git", "-C", str(tmp_path), *args], check=True, capture_output=True, timeout=30)

    git("init", "-q")
    git("config", "user.email", "t@example.invalid")
    git("config", "user.name", "t")
    f = tmp_path / "arm.iface"
    f.write_text((DATA / "verdicts" / "arm_v1.iface").read_text())
    git("add", "arm.iface")
    git("commit", "-q", "-m", "v1")
    f.write_text((DATA / "verdicts" / "arm_v3.iface").read_text())
    base = load_baseline(str(f), "git:HEAD")
    assert base is not None and "Status" in base.source.text
    new = Workspace().compile_path(str(f))
    assert compare(base, new).verdict == "replaceable-if-unused"
    assert load_baseline(str(f), "git:no-such-rev") is None
    assert load_baseline(str(f), "git:--output=x") is None
