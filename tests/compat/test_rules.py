"""One fixture pair per rule: the rule fires with its severity, located on both sides."""

from __future__ import annotations

import json

import pytest
from compat_support import DATA, compile_file

from iface.compat import RULES, compare

RULE_CASES = json.loads((DATA / "rules" / "expected.json").read_text())
THRIFT_CASES = sorted(p.name for p in (DATA / "thrift").iterdir() if p.is_dir())
#: rules tested elsewhere: system-conflict needs --system (test_system), other-change is the safety net
ELSEWHERE = {"system-conflict", "other-change"}


@pytest.mark.parametrize("rule", sorted(RULE_CASES))
def test_rule_fires(rule: str) -> None:
    old = compile_file(DATA / "rules" / rule / "old.iface")
    new = compile_file(DATA / "rules" / rule / "new.iface")
    assert not old.has_errors and not new.has_errors
    report = compare(old, new)
    hits = [f for f in report.findings if f.rule == rule]
    assert hits, [f.rule for f in report.findings]
    f = hits[0]
    assert f.severity.label == RULE_CASES[rule]
    assert f.old.source.path == old.path and f.new.source.path == new.path
    assert 0 <= f.old.span.start <= f.old.span.end <= len(old.source.text)
    assert 0 <= f.new.span.start <= f.new.span.end <= len(new.source.text)


def test_every_rule_has_a_case() -> None:
    covered = set(RULE_CASES) | ELSEWHERE
    assert set(RULES) - covered == set()


def test_same_file_has_no_findings() -> None:
    old = compile_file(DATA / "rules" / "field-added" / "old.iface")
    report = compare(old, compile_file(DATA / "rules" / "field-added" / "old.iface"))
    assert report.findings == [] and report.verdict == "equivalent"


def test_direction_decides_severity() -> None:
    """Removing an optional field: a warning where the component sends it, harmless where it receives it."""
    old = compile_file(DATA / "rules" / "field-added" / "old.iface")
    text = old.source.text
    from iface.semantics.compile import Workspace
    sent = Workspace().compile_text(str(DATA / "rules" / "x_send.iface"), text.replace("  2: optional string tag\n", ""))
    received = Workspace().compile_text(str(DATA / "rules" / "x_recv.iface"),
                                        text.replace('  2: optional string note = "x"\n', ""))
    by_sent = {f.subject: f for f in compare(old, sent).findings}
    by_received = {f.subject: f for f in compare(old, received).findings}
    assert by_sent["Beat.tag"].severity.label == "warning"
    assert by_received["Order.note"].severity.label == "information"
    assert compare(old, received).verdict == "replaceable"


def test_positional_field_added_breaks_the_ros_type() -> None:
    old = compile_file(DATA / "rules" / "field-added" / "old.iface")
    from iface.semantics.compile import Workspace
    new = Workspace().compile_text(str(DATA / "rules" / "x_pos.iface"),
                                   old.source.text.replace("  Level level\n", "  Level level\n  bool fresh\n"))
    f = next(f for f in compare(old, new).findings if f.subject == "Reading.fresh")
    assert (f.rule, f.severity.label) == ("field-added", "error")


def test_docs_name_every_rule_and_check() -> None:
    from iface.compat.graph import CHECKS
    doc = (DATA.parent.parent.parent / "docs" / "compat.md").read_text()
    missing = [code for code in [*RULES, *CHECKS] if f"`{code}`" not in doc]
    assert not missing
