"""Writing generated files: atomic, inside the output folder, never over hand edits."""

from __future__ import annotations

import os
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

from .base import GENERATED_MARK, GeneratedFile, content_hash

_STAMP = re.compile(r" \(iface-hash: ([0-9a-f]{16})\)")


@dataclass(slots=True)
class WriteReport:
    """What happened to each file: written, unchanged, refused (hand-edited), or differing (check)."""

    written: list[str] = field(default_factory=list)
    unchanged: list[str] = field(default_factory=list)
    refused: list[str] = field(default_factory=list)
    differing: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)


class UnsafePath(ValueError):
    """A generated path that would leave the output folder."""


def safe_join(out_dir: Path, rel: str) -> Path:
    """``out_dir / rel``, refusing absolute paths, ``..`` and anything resolving outside."""
    p = PurePosixPath(rel)
    if p.is_absolute() or any(part in ("..", "") for part in p.parts) or "\\" in rel or "\0" in rel:
        raise UnsafePath(rel)
    full = (out_dir / Path(*p.parts)).resolve()
    root = out_dir.resolve()
    if root != full and root not in full.parents:
        raise UnsafePath(rel)
    return full


def stamp(text: str) -> str:
    """Put the content hash right after the generated mark of the header.

    The hash covers the text without the stamp, so an edit anywhere is detected.
    """
    if GENERATED_MARK not in text:
        return text
    return text.replace(GENERATED_MARK, f"{GENERATED_MARK} (iface-hash: {content_hash(text)})", 1)


def unstamp(text: str) -> tuple[str, str | None]:
    """The text without its stamp, and the stamped hash (None if there is none)."""
    m = _STAMP.search(text)
    if m is None:
        return text, None
    return text[:m.start()] + text[m.end():], m.group(1)


def hand_edited(existing: str) -> bool:
    """True when a file on disk was not written by iface as it is now."""
    body, digest = unstamp(existing)
    return digest is None or content_hash(body) != digest


def atomic_write(path: Path, text: str) -> None:
    """Write via a temporary file in the same folder and rename it into place."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_files(files: list[GeneratedFile], out_dir: str | Path, *, force: bool = False,
                dry_run: bool = False, check: bool = False) -> WriteReport:
    """Write (or, with ``check``, compare) files under ``out_dir``.

    Every path is checked before anything is written, so a bad path writes nothing.
    """
    out = Path(out_dir)
    report = WriteReport()
    planned: list[tuple[GeneratedFile, Path, str]] = []
    for f in files:
        try:
            full = safe_join(out, f.path)
        except UnsafePath:
            report.errors.append(f"{f.path}: refused: the path leaves the output folder")
            continue
        planned.append((f, full, stamp(f.text)))
    if report.errors:
        return report
    for f, full, text in planned:
        existing = None
        if full.is_file():
            try:
                existing = full.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                existing = ""
        if existing == text:
            report.unchanged.append(f.path)
            continue
        if check:
            report.differing.append(f.path)
            continue
        if existing is not None and not force and hand_edited(existing):
            report.refused.append(f.path)
            continue
        if not dry_run:
            atomic_write(full, text)
        report.written.append(f.path)
    return report
