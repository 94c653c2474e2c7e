"""Saved states of the instances of a system, kept on disk (docs/system.md).

Each instance has a folder ``<state dir>/snapshots/<instance>/`` of state documents, one file per
snapshot, named ``<sequence>.json`` with a zero-padded sequence number so that names sort by age.
A write is atomic: the document goes to a temporary file in the same folder, is flushed and
fsynced, then renamed over its final name, and the folder is fsynced. A writer killed at any point
leaves at most a stray temporary file (removed by the next writer), never a half-written snapshot
under a final name; the previous snapshot stays readable. The last ``keep`` snapshots are kept.
"""

from __future__ import annotations

import json
import os
import re
import time
from dataclasses import dataclass
from pathlib import Path

#: Snapshots kept per instance when the manager is not told otherwise.
DEFAULT_KEEP = 5
_FINAL = re.compile(r"^(\d{10})\.json$")
_TEMP_PREFIX = ".tmp-"


@dataclass(frozen=True, slots=True)
class Snapshot:
    """One saved state: its file, sequence number, time written (seconds since the epoch) and document."""

    path: Path
    sequence: int
    written: float
    document: str


class SnapshotStore:
    """The snapshots of one instance."""

    def __init__(self, folder: Path, keep: int = DEFAULT_KEEP) -> None:
        if keep < 1:
            raise ValueError("keep must be at least 1")
        self.folder = folder
        self.keep = keep

    def _sequences(self) -> list[tuple[int, Path]]:
        """Final snapshot files, oldest first."""
        if not self.folder.is_dir():
            return []
        found = []
        for entry in self.folder.iterdir():
            match = _FINAL.match(entry.name)
            if match:
                found.append((int(match.group(1)), entry))
        return sorted(found)

    def write(self, document: str) -> Snapshot:
        """Save ``document`` atomically as the newest snapshot; drop those beyond ``keep``."""
        self.folder.mkdir(parents=True, exist_ok=True)
        self._remove_temporaries()
        existing = self._sequences()
        sequence = existing[-1][0] + 1 if existing else 1
        final = self.folder / f"{sequence:010d}.json"
        temp = self.folder / f"{_TEMP_PREFIX}{sequence:010d}-{os.getpid()}"
        data = document.encode("utf-8")
        fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            view = memoryview(data)
            while view:
                written = os.write(fd, view)
                view = view[written:]
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(temp, final)
        self._sync_folder()
        for _, old in existing[: max(0, len(existing) + 1 - self.keep)]:
            old.unlink(missing_ok=True)
        return Snapshot(final, sequence, final.stat().st_mtime, document)

    def all(self) -> list[Snapshot]:
        """Every readable snapshot, oldest first (a file that is not a JSON document is skipped)."""
        out = []
        for sequence, path in self._sequences():
            snap = _read(path, sequence)
            if snap is not None:
                out.append(snap)
        return out

    def latest(self) -> Snapshot | None:
        """The newest readable snapshot, or None."""
        for sequence, path in reversed(self._sequences()):
            snap = _read(path, sequence)
            if snap is not None:
                return snap
        return None

    def _remove_temporaries(self) -> None:
        for entry in self.folder.iterdir():
            if entry.name.startswith(_TEMP_PREFIX):
                entry.unlink(missing_ok=True)

    def _sync_folder(self) -> None:
        fd = os.open(self.folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _read(path: Path, sequence: int) -> Snapshot | None:
    try:
        text = path.read_text(encoding="utf-8")
        json.loads(text)
        written = path.stat().st_mtime
    except (OSError, ValueError):
        return None
    return Snapshot(path, sequence, written, text)


def iso_time(seconds: float) -> str:
    """A time as ISO 8601 UTC with milliseconds (``2026-11-28T06:01:02.345Z``)."""
    whole = int(seconds)
    return time.strftime("%Y-%m-%dT%H:%M:%S", time.gmtime(whole)) + f".{int((seconds - whole) * 1000):03d}Z"
