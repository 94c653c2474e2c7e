"""Thrift fixtures: our findings cover every failure and warning of ``thrift --audit OLD NEW``."""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest
from compat_support import DATA, compile_file

from iface.compat import compare

CASES = sorted(p.name for p in (DATA / "thrift").iterdir() if p.is_dir())
THRIFT = shutil.which("thrift")

#: audit message -> (severity, category, what the subject names)
AUDIT = [
    (r"Struct Field removed for Id = \d+ in (\S+)", "error", "field-removed"),
    (r"Struct Field Type Changed for Id = \d+ in (\S+)", "error", "field-type-changed"),
    (r"Struct Field Requiredness Changed for Id = \d+ in (\S+)", "error", "field-requiredness-changed"),
    (r"Required Struct Field Added for Id = \d+ in (\S+)", "error", "required-field-added"),
    (r"Struct field is added in the middle with Id = \d+ in (\S+)", "error", "field-id-inserted"),
    (r"Struct (\S+) not found in new thrift file", "error", "definition-removed"),
    (r"Enum value \d+ missing in (\S+)", "error", "enum-value-removed"),
    (r"New Thrift File has missing function (\S+)", "error", "function-removed"),
    (r"New Thrift file is missing a service (\S+)", "error", "service-removed"),
    (r"Return type changed for function (\S+)", "error", "return-type-changed"),
    (r"Oneway attribute changed for function (\S+)", "error", "oneway-changed"),
    (r"Change in Service inheritance for (\S+)", "error", "extends-changed"),
    (r"Language (\S+) not found in new thrift file", "warning", "namespace-removed"),
    (r"Namespace \S+ changed in new thrift file()", "warning", "namespace-changed"),
    (r"Default value changed for Id = \d+ in (\S+)", "warning", "default-changed"),
    (r"Struct field name changed for Id = \d+ in (\S+)", "warning", "field-renamed"),
    (r"Enum (\S+) not found in new thrift file", "warning", "enum-removed"),
    (r"Name of the value \d+ changed in enum (\S+)", "warning", "enum-value-renamed"),
    (r"Constants Missing (\S+)", "warning", "const-removed"),
    (r"Constant (\S+) is of different type", "warning", "const-type-changed"),
    (r"Constant (\S+) has different value", "warning", "const-value-changed"),
]
#: our rules that stand for one audit category
ALIASES = {"service-removed": {"service-removed", "definition-removed"}}


def audit(old: str, new: str) -> set[tuple[str, str, str]]:
    """(severity, category, owner) of every line ``thrift --audit`` prints."""
    assert THRIFT is not None
    done = subprocess.run([THRIFT, "--audit", old, new], capture_output=True, text=True, timeout=60, check=False)
    out: set[tuple[str, str, str]] = set()
    for line in (done.stdout + done.stderr).splitlines():
        text = re.sub(r"^\[Thrift Audit (Warning|Failure):[^\]]*\] ", "", line).strip()
        if not text:
            continue
        for pattern, severity, category in AUDIT:
            mt = re.fullmatch(pattern, text)
            if mt:
                out.add((severity, category, mt.group(1)))
                break
        else:
            raise AssertionError(f"unclassified audit line: {line!r}")
    return out


def owner(subject: str, rule: str) -> str:
    """What an audit message names for one of our findings: struct, args/exception list, function, …"""
    if rule.startswith("namespace-"):
        return subject.split()[-1] if rule == "namespace-removed" else ""
    if rule in ("service-removed",):
        return subject.split()[-1]
    if rule in ("function-removed", "return-type-changed", "oneway-changed"):
        return subject.rpartition(".")[2]
    mt = re.match(r"^[^.]+\.([^.(]+)\((args|throws)\)", subject)
    if mt:
        return f"{mt.group(1)}_{'args' if mt.group(2) == 'args' else 'exception'}"
    return subject.split(".")[0]


def ours(case: str) -> set[tuple[str, str, str]]:
    report = compare(compile_file(DATA / "thrift" / case / "old.thrift"),
                     compile_file(DATA / "thrift" / case / "new.thrift"))
    return {(f.severity.label, f.rule, owner(f.subject, f.rule)) for f in report.findings}


def covered(item: tuple[str, str, str], found: set[tuple[str, str, str]]) -> bool:
    severity, category, name = item
    rules = ALIASES.get(category, {category})
    return any(s == severity and r in rules and (o == name or category == "namespace-changed")
               for s, r, o in found)


@pytest.mark.parametrize("case", [c for c in CASES if c not in ("many", "equivalent")])
def test_case_names_its_rule(case: str) -> None:
    """Each Thrift fixture is named after the change it makes; that rule fires (no oracle needed)."""
    expected = {"container-type-changed": "field-type-changed", "struct-removed": "definition-removed",
                "argument-type-changed": "field-type-changed", "argument-removed": "field-removed",
                "exception-changed": "field-type-changed", "exception-removed": "field-removed",
                "optional-field-added": "field-added"}.get(case, case)
    assert expected in {r for _, r, _ in ours(case)}


@pytest.mark.skipif(THRIFT is None, reason="thrift (Debian thrift-compiler) is not installed")
@pytest.mark.parametrize("case", CASES)
def test_parity_with_thrift_audit(case: str) -> None:
    d = DATA / "thrift" / case
    expected = audit(str(d / "old.thrift"), str(d / "new.thrift"))
    found = ours(case)
    missing = {e for e in expected if not covered(e, found)}
    assert not missing, f"thrift --audit found {missing}; we found {found}"
    if case in ("equivalent", "optional-field-added", "function-added"):
        assert expected == set() and not any(s == "error" for s, _, _ in found)


@pytest.mark.skipif(THRIFT is None, reason="thrift (Debian thrift-compiler) is not installed")
def test_every_audit_message_kind_is_exercised() -> None:
    seen: set[str] = set()
    for case in CASES:
        d = DATA / "thrift" / case
        seen |= {c for _, c, _ in audit(str(d / "old.thrift"), str(d / "new.thrift"))}
    assert seen == {c for _, _, c in AUDIT}
