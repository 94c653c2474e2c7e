"""Findings beyond the core compile: the compatibility baseline, the configured targets, the cap per file."""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..model.diagnostics import Diagnostic
    from ..semantics.compile import Compilation
    from .settings import Settings

log = logging.getLogger("iface.lsp")
#: Findings published per file; past it one ``too-many-findings`` says how many more there are.
MAX_DIAGNOSTICS = 500


def capped(found: list[Diagnostic]) -> list[Diagnostic]:
    """The first ``MAX_DIAGNOSTICS`` findings (in order), then one saying how many were left out."""
    if len(found) <= MAX_DIAGNOSTICS:
        return found
    from ..model.diagnostics import make

    rest = found[MAX_DIAGNOSTICS:]
    first = rest[0]
    more = make("too-many-findings", f"and {len(rest)} more finding(s) in this file: the editor shows the "
                f"first {MAX_DIAGNOSTICS}; `iface-lsp check` lists them all", first.source, first.span)
    return [*found[:MAX_DIAGNOSTICS], more]


class Findings:
    """What the editor shows for a compiled file, with the baselines read once per file (model thread)."""

    def __init__(self) -> None:
        self._baselines: dict[tuple[str, str], Compilation | None] = {}

    def of(self, path: str, comp: Compilation, settings: Settings, include_paths: list[str]) -> list[Diagnostic]:
        """The core findings of ``path``, then the baseline's and the targets' ones, capped."""
        return capped([*comp.diagnostics, *system_findings(comp),
                       *self._compat(path, comp, settings.compat_baseline, include_paths),
                       *target_findings(comp, settings.targets)])

    def forget(self) -> None:
        """Read baselines again (the setting changed)."""
        self._baselines.clear()

    def retain(self, keep: set[str]) -> None:
        """Keep only the baselines of the files in ``keep``."""
        self._baselines = {k: v for k, v in self._baselines.items() if k[0] in keep}

    def _compat(self, path: str, comp: Compilation, spec: str, include_paths: list[str]) -> list[Any]:
        """Findings against the configured compatibility baseline, if any."""
        if not spec or comp.has_errors:
            return []
        try:
            from ..compat import baseline_diagnostics, load_baseline
        except ImportError:
            return []
        key = (path, spec)
        if key not in self._baselines:
            self._baselines[key] = load_baseline(path, spec, include_paths)
        old = self._baselines[key]
        if old is None:
            return []
        try:
            return baseline_diagnostics(old, comp)
        except Exception:
            log.exception("comparing %s with its baseline failed", path)
            return []


def system_findings(comp: Compilation) -> list[Any]:
    """A system file's graph conflicts (types, QoS, topics nobody publishes), on its instances."""
    if comp.interface.system is None:
        return []
    from ..compat.systemfile import system_findings as found

    try:
        return sorted(found(comp), key=lambda d: (d.span.start, d.span.end))
    except Exception:
        log.exception("the system graph of %s failed", comp.path)
        return []


def target_findings(comp: Compilation, names: Sequence[str]) -> list[Any]:
    """What generating for the targets ``names`` (setting ``targets``) reports in this file beyond the
    core checks: warnings such as package metadata show while editing."""
    if not names or comp.has_errors:
        return []
    try:
        from ..emit.base import GenerationError
        from ..emit.registry import targets
    except ImportError:
        return []
    installed = targets()
    seen = {(d.code, d.span.start, d.span.end) for d in comp.diagnostics}
    out = []
    for name in names:
        target = installed.get(name)
        if target is None:
            continue
        try:
            result = target.generate(comp, {})
        except GenerationError:
            continue
        for d in result.diagnostics:
            key = (d.code, d.span.start, d.span.end)
            if d.path == comp.path and key not in seen:
                seen.add(key)
                out.append(d)
    return out
