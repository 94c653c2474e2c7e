"""Writing imported ``.iface`` files: atomic, inside the output folder, never over a different file unforced.

Imported files are the user's to edit, so they carry no "generated" stamp; an
existing file with other content is therefore refused unless ``force``.
"""

from __future__ import annotations

from pathlib import Path

from ..emit.base import GeneratedFile
from ..emit.write import UnsafePath, WriteReport, atomic_write, safe_join


def write_imported(files: list[GeneratedFile], out_dir: str | Path, *, force: bool = False) -> WriteReport:
    """Write ``files`` under ``out_dir``; every path is checked before anything is written."""
    out = Path(out_dir)
    report = WriteReport()
    planned: list[tuple[GeneratedFile, Path]] = []
    for f in files:
        try:
            planned.append((f, safe_join(out, f.path)))
        except UnsafePath:
            report.errors.append(f"{f.path}: refused: the path leaves the output folder")
    if report.errors:
        return report
    for f, full in planned:
        existing = None
        if full.exists():
            try:
                existing = full.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                existing = ""
        if existing == f.text:
            report.unchanged.append(f.path)
            continue
        if existing is not None and not force:
            report.refused.append(f.path)
            continue
        try:
            atomic_write(full, f.text)
        except OSError as e:
            report.errors.append(f"{f.path}: {e.strerror}")
            continue
        report.written.append(f.path)
    return report
