"""Targets found through the ``iface.targets`` entry point group, each behind a guard.

Every caller (the ``generate`` command, the editor's preview, ``roundtrip``) gets
its targets from here, so the guard holds everywhere: a target that raises
never shows a traceback. A template error becomes ``GenerationError`` (the
caller reports it as a usage error: the templates are the user's or broken);
any other exception becomes an ``internal-error`` diagnostic naming the target.
The guard also refuses output names no file system holds (``output-name-too-long``) and
paths that differ only in case (``output-name-case-conflict``: one file on macOS and Windows),
at the definition they come from, before anything is written.
"""

from __future__ import annotations

import dataclasses
import unicodedata
from typing import Any

import jinja2

from ..model.diagnostics import Diagnostic, Related, Severity
from ..model.source import Span
from ..semantics.compile import Compilation
from . import plugins
from .base import (
    NAME_MAX,
    CodeTable,
    GeneratedFile,
    GenerationError,
    Result,
    Target,
    long_names,
    sort_diagnostics,
)

GROUP = "iface.targets"

#: Codes every target may report through the guard.
CODES: dict[str, tuple[Severity, str]] = {
    "internal-error": (Severity.ERROR, "A target failed with an unexpected exception (a bug in the target); "
                       "nothing is generated."),
    "output-name-too-long": (Severity.ERROR, "A generated file or folder name longer than 255 bytes, which "
                             "file systems cannot hold; nothing is generated."),
    "output-name-case-conflict": (Severity.ERROR, "Two generated files whose paths differ only in case: one file "
                                  "on case-insensitive file systems (macOS, Windows); nothing is generated."),
}
_diag = CodeTable(CODES)


def guarded(target: Target) -> Target:
    """``target`` with a ``generate`` that reports exceptions instead of raising them."""
    inner = target.generate

    def generate(comp: Compilation, options: dict[str, Any]) -> Result:
        try:
            return check_names(inner(comp, options), comp)
        except GenerationError:
            raise
        except jinja2.TemplateError as e:
            raise GenerationError(f"{target.name} templates: {type(e).__name__}: {e}") from e
        except Exception as e:  # noqa: BLE001 - the point of the guard
            message = (f"the {target.name} target failed: {type(e).__name__}: {e} (a bug in the target: "
                       "please report it with the input file); nothing is generated")
            return Result(diagnostics=[_diag("internal-error", message, comp.interface.source, Span(0, 0))])

    return dataclasses.replace(target, generate=generate)


def _shortened(name: str) -> str:
    """A long name cut in the middle, for messages."""
    return name if len(name) <= 40 else f"{name[:24]}…{name[-12:]}"


def check_names(result: Result, comp: Compilation) -> Result:
    """``result``, with an error (and no files) for each file whose path has a name too long to write.

    The error stands at the definition the file comes from (else at the start of the file).
    """
    found = []
    for f in result.files:
        source, span = f.origin or (comp.interface.source, Span(0, 0))
        for part, size in long_names(f.path):
            found.append(_diag("output-name-too-long", f"the generated file or folder name '{_shortened(part)}' is "
                               f"{size} bytes long; file systems hold names of at most {NAME_MAX} bytes: shorten "
                               "the name it comes from", source, span))
    found.extend(_case_conflicts(result, comp))
    if found:
        result.diagnostics.extend(found)
        sort_diagnostics(result.diagnostics)
        result.files = []
    return result


def case_key(path: str) -> str:
    """What a case-insensitive file system (APFS, NTFS) sees of a path: composed and case-folded."""
    return unicodedata.normalize("NFC", path).casefold()


def _case_conflicts(result: Result, comp: Compilation) -> list[Diagnostic]:
    """An error for each file whose path equals an earlier one's but for case, at the definition it comes from."""
    first: dict[str, GeneratedFile] = {}
    found = []
    in_source_order = sorted(result.files, key=lambda f: (f.origin[1].start, f.path) if f.origin else (-1, f.path))
    for f in in_source_order:
        seen = first.setdefault(case_key(f.path), f)
        if seen is f or seen.path == f.path:
            continue
        source, span = f.origin or (comp.interface.source, Span(0, 0))
        related = [Related(*seen.origin, f"'{seen.path}' comes from here")] if seen.origin else []
        found.append(_diag("output-name-case-conflict", f"the generated file '{f.path}' differs from "
                           f"'{seen.path}' only in case: on case-insensitive file systems (macOS, Windows) they "
                           "are one file; rename one of the definitions they come from", source, span))
        found[-1].related.extend(related)
    return found


def targets() -> dict[str, Target]:
    """Every installed target by name (entry point value: a ``Target`` object), guarded."""
    return {name: guarded(target) for name, target in plugins.load(GROUP, Target).items()}


def get_target(name: str) -> Target | None:
    """The target called ``name``, if installed."""
    return targets().get(name)


def generate(comp: Compilation, target: str, **options: Any) -> Result:
    """Render ``comp`` for ``target``; an unknown target raises KeyError."""
    t = get_target(target)
    if t is None:
        raise KeyError(target)
    return t.generate(comp, options)
