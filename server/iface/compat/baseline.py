"""The editor's view: a baseline (a file or a git revision) and findings as diagnostics in NEW."""

from __future__ import annotations

import os
import subprocess

from ..model.diagnostics import Diagnostic, Related, Severity
from ..semantics.compile import Compilation, Workspace, decode

#: how findings show in the editor: benign changes as hints
_EDITOR_SEVERITY = {Severity.ERROR: Severity.ERROR, Severity.WARNING: Severity.WARNING,
                    Severity.INFORMATION: Severity.HINT, Severity.HINT: Severity.HINT}


def load_baseline(path: str, spec: str, include_paths: list[str] | None = None) -> Compilation | None:
    """The baseline of ``path``: ``spec`` is a file path, or ``git:REV`` for the file at a git revision.

    A relative file path is read from the working directory, else beside ``path``.
    Returns None when the baseline cannot be read (no such file, revision or repository).
    """
    ws = Workspace(include_paths or [])
    if spec.startswith("git:"):
        text = _git_show(path, spec[4:])
        if text is None:
            return None
        return ws.compile_text(path, text)
    candidates = [spec] if os.path.isabs(spec) else [spec, os.path.join(os.path.dirname(os.path.abspath(path)), spec)]
    for candidate in candidates:
        if os.path.isfile(candidate):
            return ws.compile_path(candidate)
    return None


def _git_show(path: str, rev: str) -> str | None:
    """The text of ``path`` at revision ``rev`` of the repository it lies in."""
    if not rev or rev.startswith("-"):
        return None
    folder = os.path.dirname(os.path.abspath(path))
    try:
        top = subprocess.run(["git", "-C", folder, "rev-parse", "--show-toplevel"], capture_output=True,
                             text=True, timeout=10, check=False)
        if top.returncode != 0:
            return None
        rel = os.path.relpath(os.path.realpath(os.path.abspath(path)), os.path.realpath(top.stdout.strip()))
        shown = subprocess.run(["git", "-C", top.stdout.strip(), "show", f"{rev}:{rel.replace(os.sep, '/')}"],
                               capture_output=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    if shown.returncode != 0:
        return None
    text, problems = decode(shown.stdout, path)
    return None if problems and not text else text


def baseline_diagnostics(old: Compilation, new: Compilation) -> list[Diagnostic]:
    """Findings of ``compare(old, new)`` as diagnostics located in NEW's file, code ``compat-<rule>``.

    ``data`` holds the rule, the verdict-relevant severity and, where one exists,
    ``fix``: ``{"kind": "add-default" | "make-optional" | "restore", …, "edits":
    [{"start", "end", "text"}]}`` with character offsets into NEW's text.
    """
    from . import compare
    report = compare(old, new)
    out: list[Diagnostic] = []
    for f in report.findings:
        if os.path.abspath(f.new.source.path) != os.path.abspath(new.path):
            continue
        message = f.message + (f": {f.breaks}" if f.breaks else "")
        data: dict = {"rule": f.rule, "subject": f.subject}
        if f.fix is not None:
            data["fix"] = f.fix
        related = [Related(f.old.source, f.old.span, "in the baseline")]
        out.append(Diagnostic(f"compat-{f.rule}", message, new.source, f.new.span,
                              _EDITOR_SEVERITY[f.severity], related, data))
    return out
