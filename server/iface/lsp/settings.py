"""The server's settings, from initializationOptions and workspace/didChangeConfiguration.

The shape is the one the VS Code extension sends: ``{output: {folder}, targets,
includePaths, compat: {baseline}}``, optionally wrapped in ``{"iface": …}``.
A value of the wrong type is ignored and the previous value kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

DEFAULT_OUTPUT = "generated"


@dataclass(frozen=True, slots=True)
class Settings:
    """What the user can configure."""

    output_folder: str = ""
    targets: tuple[str, ...] = ()
    include_paths: tuple[str, ...] = ()
    compat_baseline: str = ""
    #: Seconds to wait after an edit before compiling (edits in a burst are compiled once). 0 by default:
    #: an edit costs a few milliseconds to check, and edits that come while a check runs are checked together.
    diagnostics_delay: float = 0.0
    problems: list[str] = field(default_factory=list, compare=False)

    def updated(self, options: Any) -> Settings:
        """These settings with what ``options`` says; wrong types are reported in ``problems``."""
        if not isinstance(options, dict):
            return self
        if isinstance(options.get("iface"), dict):
            options = options["iface"]
        problems: list[str] = []
        new = replace(self, problems=problems)

        def text(value: Any, name: str, current: str) -> str:
            if isinstance(value, str):
                return value
            problems.append(f"{name} must be a string")
            return current

        def texts(value: Any, name: str, current: tuple[str, ...]) -> tuple[str, ...]:
            if isinstance(value, list) and all(isinstance(v, str) for v in value):
                return tuple(value)
            problems.append(f"{name} must be a list of strings")
            return current

        output = options.get("output")
        if isinstance(output, dict) and "folder" in output:
            new = replace(new, output_folder=text(output["folder"], "output.folder", self.output_folder))
        elif "outputFolder" in options:
            new = replace(new, output_folder=text(options["outputFolder"], "outputFolder", self.output_folder))
        if "targets" in options:
            new = replace(new, targets=texts(options["targets"], "targets", self.targets))
        if "includePaths" in options:
            new = replace(new, include_paths=texts(options["includePaths"], "includePaths", self.include_paths))
        compat = options.get("compat")
        if isinstance(compat, dict) and "baseline" in compat:
            new = replace(new, compat_baseline=text(compat["baseline"], "compat.baseline", self.compat_baseline))
        if "diagnosticsDelay" in options:
            delay = options["diagnosticsDelay"]
            if isinstance(delay, (int, float)) and not isinstance(delay, bool) and 0 <= delay <= 5000:
                new = replace(new, diagnostics_delay=delay / 1000)
            else:
                problems.append("diagnosticsDelay must be a number of milliseconds (0..5000)")
        return new
