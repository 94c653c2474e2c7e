"""Verify findings as text lines, JSON and SARIF 2.1.0 (the formats of ``iface-lsp verify``)."""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from .verify import CODES, Finding

Display = Callable[[str], str]


def render_text(findings: list[Finding], display: Display, checked: int) -> str:
    """``path:line:col: severity[code]: message [node]`` per finding, then a summary line."""
    lines = []
    for f in findings:
        where = f"{display(f.path)}:{f.line}:{f.column}" if f.path else "<graph>"
        lines.append(f"{where}: {f.severity}[{f.code}]: {f.message} [{f.node}]")
    errors = sum(f.severity == "error" for f in findings)
    warnings = len(findings) - errors
    if findings:
        lines.append(f"verify: {checked} node{'s' if checked != 1 else ''}: {errors} error"
                     f"{'s' if errors != 1 else ''}, {warnings} warning{'s' if warnings != 1 else ''}")
    else:
        lines.append(f"verify: {checked} node{'s' if checked != 1 else ''} conform to their interfaces")
    return "\n".join(lines) + "\n"


def as_data(f: Finding, display: Display) -> dict[str, Any]:
    """One finding as JSON data."""
    return {"code": f.code, "severity": f.severity, "message": f.message, "node": f.node,
            "path": display(f.path) if f.path else None, "line": f.line, "column": f.column}


def render_json(findings: list[Finding], display: Display, checked: int) -> str:
    """``{"nodes": N, "errors": E, "warnings": W, "findings": [...]}``."""
    errors = sum(f.severity == "error" for f in findings)
    doc = {"nodes": checked, "errors": errors, "warnings": len(findings) - errors,
           "findings": [as_data(f, display) for f in findings]}
    return json.dumps(doc, indent=2, sort_keys=True) + "\n"


def render_sarif(findings: list[Finding], display: Display, version: str) -> str:
    """SARIF 2.1.0: one rule per code, one result per finding."""
    rules = [{"id": code, "shortDescription": {"text": text},
              "defaultConfiguration": {"level": "error" if sev == "error" else "warning"}}
             for code, (sev, text) in sorted(CODES.items())]
    results = []
    for f in findings:
        result: dict[str, Any] = {"ruleId": f.code, "level": f.severity,
                                  "message": {"text": f"{f.message} [{f.node}]"}}
        if f.path:
            result["locations"] = [{"physicalLocation": {
                "artifactLocation": {"uri": display(f.path)},
                "region": {"startLine": f.line, "startColumn": f.column,
                           "endLine": f.end_line or f.line, "endColumn": f.end_column or f.column}}}]
        results.append(result)
    doc = {"$schema": "https://json.schemastore.org/sarif-2.1.0.json", "version": "2.1.0",
           "runs": [{"tool": {"driver": {"name": "iface-lsp verify", "version": version,
                                         "informationUri": "https://example.invalid/iface", "rules": rules}},
                     "results": results}]}
    return json.dumps(doc, indent=2, sort_keys=True) + "\n"
