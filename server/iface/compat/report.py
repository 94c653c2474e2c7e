"""Rendering a report: text lines, JSON (see schema/compat.schema.json) and SARIF 2.1.0."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

from ..model.diagnostics import Severity
from .findings import Finding, Handover, Location, Report
from .rules import RULES

SCHEMA_ID = "iface-compat/1"
SCHEMA_PATH = Path(__file__).with_name("schema") / "compat.schema.json"
Display = Callable[[str], str]
_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFORMATION: "note", Severity.HINT: "note"}


def _where(loc: Location, display: Display) -> str:
    line, col, _, _ = loc.position()
    return f"{display(loc.source.path)}:{line}:{col}"


def finding_line(f: Finding, display: Display) -> str:
    """``new:l:c: severity[rule]: message — what breaks (old: old:l:c) [components]``."""
    text = f"{_where(f.new, display)}: {f.severity.label}[{f.rule}]: {f.subject}: {f.message}"
    if f.breaks:
        text += f"; breaks: {f.breaks}"
    if f.components:
        text += f"; affects: {', '.join(f.components)}"
    if f.satisfied_by:
        text += f"; provided by: {', '.join(f.satisfied_by)}"
    return text + f" (old: {_where(f.old, display)})"


def _handover_lines(h: Handover) -> list[str]:
    if not (h.carried or h.new or h.lost):
        return []
    lines = ["state hand-over:"]
    for v in h.carried:
        lines.append(f"  carried over: {v.name} ({v.type}{' → ' + v.new_type if v.new_type else ''})")
    for v in h.new:
        if v.initial is None:
            lines.append(f"  new, needs an initial value: {v.name} ({v.type})")
        else:
            lines.append(f"  new, starts at {v.initial}: {v.name} ({v.type})")
    for v in h.lost:
        lines.append(f"  lost: {v.name} ({v.type})")
    return lines


def verdict_reason(report: Report) -> str:
    """Why the verdict is what it is, in one phrase."""
    errors = report.count(Severity.ERROR)
    if report.verdict == "equivalent":
        return "same elements of the same types in every set"
    if report.verdict == "replaceable":
        return "NEW provides at least what OLD provided and requires no more"
    if report.verdict == "replaceable-if-unused":
        if report.with_system:
            return f"{errors} breaking change{'s' if errors != 1 else ''}, none used by the system"
        return (f"{errors} breaking change{'s' if errors != 1 else ''} that only matter{'' if errors != 1 else 's'}"
                " if other components use them: give --system to decide")
    return f"{errors} breaking change{'s' if errors != 1 else ''}"


def render_text(report: Report, display: Display) -> str:
    """The report as lines of text."""
    lines = [finding_line(f, display) for f in report.findings]
    lines.extend(_handover_lines(report.handover))
    counts = (f"{report.count(Severity.ERROR)} breaking, {report.count(Severity.WARNING)} to review, "
              f"{report.count(Severity.INFORMATION)} compatible")
    lines.append(f"verdict: {report.verdict} ({verdict_reason(report)}; {counts})")
    return "\n".join(lines) + "\n"


def _loc_json(loc: Location, display: Display) -> dict[str, Any]:
    return loc.to_json(display(loc.source.path))


def finding_json(f: Finding, display: Display) -> dict[str, Any]:
    """One finding as JSON data."""
    return {"rule": f.rule, "severity": f.severity.label, "subject": f.subject, "message": f.message,
            "breaks": f.breaks, "old": _loc_json(f.old, display), "new": _loc_json(f.new, display),
            "usage": list(f.usage), "requires": f.requires, "components": list(f.components),
            "satisfied_by": list(f.satisfied_by), "fix": f.fix}


def report_json(report: Report, display: Display) -> dict[str, Any]:
    """The report as JSON data (validated by ``schema/compat.schema.json``)."""
    h = report.handover

    def var(v: Any) -> dict[str, Any]:
        return {"name": v.name, "type": v.type, "initial": v.initial, "new_type": v.new_type}

    return {
        "schema": SCHEMA_ID,
        "old": display(report.old.path),
        "new": display(report.new.path),
        "system": [display(c.path) for c in report.system],
        "verdict": report.verdict,
        "exit_code": report.exit_code,
        "old_hash": report.old_hash,
        "new_hash": report.new_hash,
        "summary": {"errors": report.count(Severity.ERROR), "warnings": report.count(Severity.WARNING),
                    "information": report.count(Severity.INFORMATION)},
        "findings": [finding_json(f, display) for f in report.findings],
        "state": {"carried": [var(v) for v in h.carried], "new": [var(v) for v in h.new],
                  "lost": [var(v) for v in h.lost]},
    }


def render_json(report: Report, display: Display) -> str:
    """The report as indented JSON."""
    return json.dumps(report_json(report, display), indent=2, ensure_ascii=False) + "\n"


def _sarif_loc(loc: Location, display: Display, message: str | None = None) -> dict[str, Any]:
    line, col, eline, ecol = loc.position()
    out: dict[str, Any] = {"physicalLocation": {
        "artifactLocation": {"uri": display(loc.source.path)},
        "region": {"startLine": line, "startColumn": col, "endLine": eline, "endColumn": ecol}}}
    if message:
        out["message"] = {"text": message}
    return out


def render_sarif(report: Report, display: Display, version: str) -> str:
    """The report as SARIF 2.1.0."""
    used = sorted({f.rule for f in report.findings})
    rules = [{"id": code, "shortDescription": {"text": RULES[code].summary},
              "defaultConfiguration": {"level": _LEVEL[RULES[code].severity]}} for code in used]
    results = []
    for f in report.findings:
        text = f.message + (f"; breaks: {f.breaks}" if f.breaks else "")
        if f.components:
            text += f"; affects: {', '.join(f.components)}"
        results.append({"ruleId": f.rule, "ruleIndex": used.index(f.rule), "level": _LEVEL[f.severity],
                        "message": {"text": text}, "locations": [_sarif_loc(f.new, display)],
                        "relatedLocations": [dict(_sarif_loc(f.old, display, "in OLD"), id=0)],
                        "properties": {"subject": f.subject, "components": list(f.components)}})
    doc = {"$schema": "https://json.schemastore.org/sarif-2.1.0.json", "version": "2.1.0",
           "runs": [{"tool": {"driver": {"name": "iface-lsp compat", "version": version,
                                         "rules": rules}},
                     "properties": {"verdict": report.verdict},
                     "results": results}]}
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
