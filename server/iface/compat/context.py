"""The comparison context: both sides and the findings collected so far."""

from __future__ import annotations

from typing import Any

from ..model.diagnostics import Severity
from .findings import Finding, Location
from .rules import RULES
from .side import RECEIVE, SEND, Side


def by_direction(dirs: set[str], send: Severity, receive: Severity) -> Severity:
    """The severity for data flowing in ``dirs``: the stricter of both when it flows both ways."""
    if dirs == {SEND}:
        return send
    if dirs == {RECEIVE}:
        return receive
    return min(send, receive)


class Context:
    """Collects findings while OLD and NEW are walked."""

    def __init__(self, old: Side, new: Side) -> None:
        self.old = old
        self.new = new
        self.findings: list[Finding] = []

    def add(self, code: str, subject: str, message: str, old: Location, new: Location, *,
            severity: Severity | None = None, breaks: str = "", usage: set[str] | tuple[str, ...] = (),
            requires: bool = False, fix: dict[str, Any] | None = None) -> Finding:
        """Record a finding of rule ``code`` (its severity defaults to the rule's)."""
        f = Finding(code, severity if severity is not None else RULES[code].severity, subject, message,
                    old, new, breaks, tuple(sorted(usage)), requires, fix)
        self.findings.append(f)
        return f
