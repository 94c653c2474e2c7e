"""Importers: existing interface files (ROS 2, PX4, the JSON form) → ``.iface`` files.

An importer is a small descriptor (``Importer``) found through the
``iface.importers`` entry point group, like the targets of ``iface.emit``. Its
``run(inputs, options)`` reads files and returns an ``ImportResult``: the
``.iface`` texts to write, the problems found (``file:line: message``), and
where each imported definition came from (what ``roundtrip`` compares).
Importers never write: ``iface.importers.output.write_imported`` does, and
never over a different existing file unless forced.

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit`` (the shared writer).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

from ..emit import plugins
from ..emit.base import GeneratedFile

GROUP = "iface.importers"

Severity = Literal["error", "warning", "note"]


@dataclass(frozen=True, slots=True)
class Problem:
    """Something found in an input file; ``line`` is 1-based, 0 for the file as a whole."""

    path: str
    line: int
    message: str
    severity: Severity = "error"

    def format(self, path: str | None = None) -> str:
        """``file:line: message`` (warnings and notes say so after the location)."""
        where = path or self.path
        if self.line > 0:
            where = f"{where}:{self.line}"
        label = "" if self.severity == "error" else f"{self.severity}: "
        return f"{where}: {label}{self.message}"


@dataclass(frozen=True, slots=True)
class Origin:
    """One imported definition: its source file, the ``.iface`` file it went to, and its name there."""

    source: str
    iface: str
    definition: str
    kind: str


@dataclass(slots=True)
class ImportResult:
    """What an importer produced: ``.iface`` files (relative paths), problems, origins, inputs read."""

    files: list[GeneratedFile] = field(default_factory=list)
    problems: list[Problem] = field(default_factory=list)
    origins: list[Origin] = field(default_factory=list)
    #: Every interface file read (imported or not), for counting what a round trip compares.
    sources: list[str] = field(default_factory=list)
    #: Packages whose types are used but that were not imported (kept as ``external``).
    missing: list[str] = field(default_factory=list)

    @property
    def has_errors(self) -> bool:
        """True when some input could not be imported."""
        return any(p.severity == "error" for p in self.problems)


class InputError(Exception):
    """The inputs cannot be read at all (a usage or I/O problem: exit code 2)."""


@dataclass(frozen=True)
class Importer:
    """An importer: name (the ``--from`` value), one-line description, and its run function."""

    name: str
    description: str
    run: Callable[[list[str], dict[str, Any]], ImportResult]


def importers() -> dict[str, Importer]:
    """Every installed importer by name (entry point value: an ``Importer`` object)."""
    return plugins.load(GROUP, Importer)


def get_importer(name: str) -> Importer | None:
    """The importer called ``name``, if installed."""
    return importers().get(name)


__all__ = ["GROUP", "InputError", "ImportResult", "Importer", "Origin", "Problem", "get_importer", "importers"]
