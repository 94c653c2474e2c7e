"""Compatibility: can NEW replace OLD, and what does the replacement touch?

``compare(old, new, system)`` compares the seven sets of two compiled
interfaces and the definitions they use, and decides a verdict:
equivalent, replaceable, replaceable-if-unused or incompatible.
``baseline_diagnostics`` turns the findings into editor diagnostics located in
NEW, and ``load_baseline`` reads a baseline from a file or a git revision.

May import: ``model``, ``syntax``, ``semantics``.
"""

from __future__ import annotations

from ..model.diagnostics import Severity
from ..semantics.compile import Compilation
from .baseline import baseline_diagnostics, load_baseline
from .canon import canonical, first_difference, interface_hash
from .context import Context
from .defs import compare_definitions
from .findings import VERDICTS, Finding, Handover, Location, Report, StateVar, Verdict
from .rules import RULES, Rule
from .sets import (
    compare_diagnostics,
    compare_endpoints,
    compare_namespaces,
    compare_parameters,
    compare_state,
)
from .side import Side
from .system import System, apply

__all__ = ["compare", "baseline_diagnostics", "load_baseline", "interface_hash", "canonical", "Report",
           "Finding", "Location", "Handover", "StateVar", "Verdict", "VERDICTS", "RULES", "Rule", "System"]


def compare(old: Compilation, new: Compilation, system: list[Compilation] | None = None) -> Report:
    """Compare OLD with NEW; with ``system``, decide usage from the other components."""
    o, n = Side(old), Side(new)
    ctx = Context(o, n)
    compare_namespaces(ctx)
    reported = compare_endpoints(ctx)
    compare_parameters(ctx)
    handover = compare_state(ctx)
    reported |= compare_diagnostics(ctx)
    compare_definitions(ctx, reported)
    old_canon, new_canon = canonical(old), canonical(new)
    if not ctx.findings and old_canon != new_canon:
        where = first_difference(old_canon, new_canon) or "/"
        ctx.add("other-change", where, f"the interfaces differ at {where} of their canonical forms",
                o.anchor(), n.anchor())
    findings = ctx.findings
    if system is not None:
        findings = findings + apply(findings, o, n, System.of(system, exclude=(old, new)))
    findings.sort(key=_order)
    return Report(old, new, list(system or []), findings, _verdict(findings, system is not None), handover,
                  interface_hash(old), interface_hash(new), system is not None)


def _order(f: Finding) -> tuple:
    return (f.new.source.path, f.new.span.start, f.old.source.path, f.old.span.start, f.rule, f.subject)


def _verdict(findings: list[Finding], with_system: bool) -> Verdict:
    """The strictest verdict the findings allow."""
    if not findings:
        return "equivalent"
    errors = [f for f in findings if f.severity == Severity.ERROR]
    if not errors:
        return "replaceable"
    if not with_system:
        return "replaceable-if-unused" if all(f.usage_dependent for f in errors) else "incompatible"
    breaking = [f for f in errors if not f.usage_dependent or f.components or (f.requires and not f.satisfied_by)]
    return "incompatible" if breaking else "replaceable-if-unused"
