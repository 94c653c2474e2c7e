"""What the workspace holds: every interface file under the workspace folders.

Files are compiled one by one on the model thread (a request waits behind at
most one of them) when the server starts, and again when they are saved or
change on disk. Open documents answer from their own compiled versions instead.
The facts kept (definitions, wirings) are immutable tuples, safe to read from
the event loop (completion reads topics from there).
"""

from __future__ import annotations

import asyncio
import logging
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .documents import path_to_uri

if TYPE_CHECKING:
    from ..model.nodes import Interface
    from ..semantics.compile import Compilation
    from .progress import Progress
    from .project import Project

log = logging.getLogger("iface.lsp")

MAX_FILES = 2000
SKIP_DIRS = frozenset({"node_modules", "__pycache__", "build", "install", "log", "dist", "venv"})


@dataclass(frozen=True, slots=True)
class WiringFact:
    """``direction type on topic`` in one file, with the definition the type resolves to."""

    path: str
    component: str
    direction: str
    type_name: str
    topic: str
    target: tuple[str, str] | None  # (defining file, definition name)


@dataclass(frozen=True, slots=True)
class FileFacts:
    """What one file defines and wires."""

    path: str
    definitions: tuple[tuple[str, str], ...]  # (name, kind)
    wirings: tuple[WiringFact, ...]


def facts_of(iface: Interface) -> FileFacts:
    """The facts of one compiled interface."""
    from ..semantics.query import defining_interface

    scopes = [iface, *iface.included.values()]
    wirings = []
    for w in iface.wirings:
        target = None
        if w.type.target is not None:
            home = defining_interface(scopes, w.type.target)
            if home is not None:
                target = (home.path, w.type.target.name)
        wirings.append(WiringFact(iface.path, iface.name, w.direction, w.type.name, w.topic, target))
    return FileFacts(iface.path, tuple((d.name, d.kind) for d in iface.definitions), tuple(wirings))


class WorkspaceIndex:
    """Facts and interfaces of the workspace's files, by path."""

    def __init__(self, project: Project, progress: Callable[[], Progress] | None = None) -> None:
        self.project = project
        self.facts: dict[str, FileFacts] = {}
        self.compilations: dict[str, Compilation] = {}
        self.ready = asyncio.Event()
        #: Seconds the last scan took (None while it runs).
        self.seconds: float | None = None
        self._progress = progress
        self._queue: list[str] = []
        self._task: asyncio.Task[None] | None = None

    def start(self) -> None:
        """Scan the workspace folders in the background (``$/progress`` tells the client how far it is)."""
        self._task = asyncio.get_running_loop().create_task(self._scan())

    def refresh(self, path: str) -> None:
        """Read one file again (saved, created, changed or deleted)."""
        if path.endswith((".iface", ".thrift")):
            self._queue.append(path)
            if self._task is None or self._task.done():
                self._task = asyncio.get_running_loop().create_task(self._drain())

    async def _scan(self) -> None:
        t0 = time.perf_counter()
        self.seconds = None
        progress = self._progress() if self._progress is not None else None
        try:
            paths = await self.project.run(self._list)
            keep = set(paths)
            for gone in [p for p in self.facts if p not in keep]:
                self.facts.pop(gone, None)
                self.compilations.pop(gone, None)
            if progress is not None:
                await progress.begin(len(paths))
            for done, path in enumerate(paths, 1):
                try:
                    await self.project.run(self._index_one, path)
                except Exception:
                    log.exception("indexing %s failed", path)
                if progress is not None:
                    progress.report(done, len(paths))
            await self._drain()
        finally:
            self.seconds = time.perf_counter() - t0
            if progress is not None:
                progress.end(f"{len(self.facts)} interface files indexed in {self.seconds:.1f} s")
            self.ready.set()

    def _list(self) -> list[str]:
        found: list[str] = []
        for root in self.project.roots:
            for folder, dirs, files in os.walk(root):
                dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d not in SKIP_DIRS)
                for f in sorted(files):
                    if f.endswith((".iface", ".thrift")):
                        found.append(os.path.join(folder, f))
                        if len(found) >= MAX_FILES:
                            log.warning("indexing the first %d interface files of the workspace only", MAX_FILES)
                            return found
        return found

    async def _drain(self) -> None:
        while self._queue:
            path = self._queue.pop(0)
            try:
                await self.project.run(self._index_one, path)
            except Exception:
                log.exception("indexing %s failed", path)

    def _index_one(self, path: str) -> None:
        if not os.path.isfile(path):
            self.facts.pop(path, None)
            self.compilations.pop(path, None)
            return
        comp = self.project.workspace().compile_path(path)
        self.compilations[path] = comp
        self.facts[path] = facts_of(comp.interface)

    # ---- questions (model thread, where interfaces are read) ---------------------------
    def all_facts(self) -> list[FileFacts]:
        """Facts of every file, open documents from their compiled versions."""
        out = dict(self.facts)
        for ver in list(self.project.compiled.values()):
            if ver.iface is not None:
                out[ver.path] = facts_of(ver.iface)
        return [out[k] for k in sorted(out)]

    def all_compilations(self) -> list[Compilation]:
        """Compilations of every file, open documents (and what they include) from their compiled versions."""
        out = dict(self.compilations)
        for ver in list(self.project.compiled.values()):
            if ver.comp is not None:
                for c in ver.comp.closure():
                    if c.path == ver.path or c.path not in out:
                        out[c.path] = c
        return [out[k] for k in sorted(out)]

    def referring(self, home: str, name: str) -> list[Interface]:
        """The interfaces that may use ``name`` defined in ``home``: ``home`` itself and the files that
        include it (at any depth) and whose text holds the name; the others cannot name it."""
        out: list[Interface] = []
        for comp in self.all_compilations():
            if comp.path == home or (name in comp.source.text and _includes(comp, home)):
                out.append(comp.interface)
        return out

    def all_interfaces(self) -> list[Interface]:
        """Interfaces of every file (see ``all_compilations``)."""
        return [c.interface for c in self.all_compilations()]

    def topics(self) -> list[tuple[str, str, str]]:
        """(topic, type, direction) of every wiring in the workspace."""
        seen: dict[tuple[str, str, str], None] = {}
        for facts in list(self.facts.values()):
            for w in facts.wirings:
                seen.setdefault((w.topic, w.type_name, w.direction))
        return list(seen)

    def uri(self, path: str) -> str:
        """The URI of an indexed path."""
        return path_to_uri(path)


def _includes(comp: Compilation, path: str) -> bool:
    """True when ``comp`` includes ``path``, directly or through other files."""
    return any(c.path == path for c in comp.closure()[1:])
