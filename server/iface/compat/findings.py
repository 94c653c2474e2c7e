"""What a comparison produces: findings located on both sides, state hand-over, the report."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

from ..model.diagnostics import Severity
from ..model.source import Source, Span
from ..semantics.compile import Compilation

Verdict = Literal["equivalent", "replaceable", "replaceable-if-unused", "incompatible"]
VERDICTS: tuple[Verdict, ...] = ("equivalent", "replaceable", "replaceable-if-unused", "incompatible")


@dataclass(frozen=True, slots=True)
class Location:
    """A span in a source file."""

    source: Source
    span: Span

    def position(self) -> tuple[int, int, int, int]:
        """1-based (line, column, end line, end column)."""
        line, col = self.source.position(self.span.start)
        eline, ecol = self.source.position(self.span.end)
        return line + 1, col + 1, eline + 1, ecol + 1

    def to_json(self, path: str) -> dict[str, Any]:
        """``{file, line, column, end_line, end_column}`` (1-based) with ``path`` as the file."""
        line, col, eline, ecol = self.position()
        return {"file": path, "line": line, "column": col, "end_line": eline, "end_column": ecol}


@dataclass(eq=False)
class Finding:
    """One difference between OLD and NEW, located on both sides.

    ``usage`` lists the endpoints through which the difference matters
    (``topic:/x``, ``service:/s``, ``action:/a``, ``type:Name``) or, for
    differences no other component can make harmless, ``parameter:…`` and
    ``state:…``. ``requires`` marks a finding where NEW needs something that
    another component must provide. ``components`` is filled from ``--system``.
    """

    rule: str
    severity: Severity
    subject: str
    message: str
    old: Location
    new: Location
    breaks: str = ""
    usage: tuple[str, ...] = ()
    requires: bool = False
    fix: dict[str, Any] | None = None
    components: list[str] = field(default_factory=list)
    satisfied_by: list[str] = field(default_factory=list)

    @property
    def usage_dependent(self) -> bool:
        """True when the finding is harmless if no other component uses its elements."""
        return bool(self.usage) and all(k.split(":", 1)[0] in ("topic", "service", "action", "type")
                                        for k in self.usage)


@dataclass(frozen=True, slots=True)
class StateVar:
    """A state variable in the hand-over: its name, type text and initial value text."""

    name: str
    type: str
    initial: str | None = None
    new_type: str | None = None


@dataclass
class Handover:
    """State hand-over from OLD to NEW."""

    carried: list[StateVar] = field(default_factory=list)
    new: list[StateVar] = field(default_factory=list)
    lost: list[StateVar] = field(default_factory=list)


@dataclass(eq=False)
class Report:
    """The result of ``compare``."""

    old: Compilation
    new: Compilation
    system: list[Compilation]
    findings: list[Finding]
    verdict: Verdict
    handover: Handover
    old_hash: str
    new_hash: str
    with_system: bool = False

    @property
    def exit_code(self) -> int:
        """0 for equivalent and replaceable (and replaceable-if-unused shown with --system), else 1."""
        if self.verdict in ("equivalent", "replaceable"):
            return 0
        if self.verdict == "replaceable-if-unused" and self.with_system:
            return 0
        return 1

    def count(self, severity: Severity) -> int:
        """How many findings have ``severity``."""
        return sum(1 for f in self.findings if f.severity == severity)
