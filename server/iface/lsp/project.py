"""The project: open documents, the model thread, the compile scheduler and diagnostics publishing.

Threads: the asyncio loop owns the documents (text, version, edit log); the
model thread (a one-worker executor) owns the core ``Workspace`` and every
``CompiledVersion``. A compilation shares model nodes with the next one of its
document (unchanged chunks are reused and shifted in place), so a compiled version is
read only on the model thread, and only until the next compile replaces it.
Requests that arrive before the newest version is compiled use the latest
compiled version and map offsets through the edits made since (``EditLog``).
"""

from __future__ import annotations

import asyncio
import logging
import os
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import TYPE_CHECKING, Any, TypeVar

from .convert import UTF16, LineIndex, LineIndexes
from .documents import DocState, Document, path_to_uri, uri_to_path
from .findings import Findings, capped
from .settings import Settings
from .versions import DocumentView, CompiledVersion, names_of

if TYPE_CHECKING:
    from ..model.nodes import Interface
    from ..model.source import Source, Span
    from ..semantics.compile import Workspace

log = logging.getLogger("iface.lsp")
T = TypeVar("T")


def _log_failure(done: Future[object]) -> None:
    if not done.cancelled() and (error := done.exception()) is not None:
        log.error("work on the model thread failed", exc_info=error)


class Project:
    """Documents, settings, the model thread and the compile scheduler."""

    def __init__(self, publish: Callable[[str, int | None, list[Any]], None]) -> None:
        self.publish = publish
        self.docs: dict[str, Document] = {}
        self.compiled: dict[str, CompiledVersion] = {}
        self.settings = Settings()
        self.encoding = UTF16
        self.roots: list[str] = []
        self.model = ThreadPoolExecutor(max_workers=1, thread_name_prefix="iface-model")
        self._ws: Workspace | None = None
        self._dirty: set[str] = set()
        self._compiling: str | None = None
        self._edited: set[str] = set()  # the dirty documents that are not only dependents of another
        self._task: asyncio.Task[None] | None = None
        self._kick: asyncio.Event | None = None
        self._waiters: dict[str, list[tuple[int, asyncio.Future[CompiledVersion | None]]]] = {}
        self._external: dict[str, set[str]] = {}
        self.line_indexes = LineIndexes()
        self.findings = Findings()
        self.workspace_index: Any = None
        #: uri -> diagnostics of the last "Verify against the running system", published beside each file's own
        self.live: dict[str, list[Any]] = {}

    # ---- the model thread ------------------------------------------------------
    async def run(self, fn: Callable[..., T], *args: Any) -> T:
        """Run ``fn(*args)`` on the model thread."""
        return await asyncio.get_running_loop().run_in_executor(self.model, fn, *args)

    def submit(self, fn: Callable[..., object], *args: Any) -> None:
        """Run ``fn(*args)`` on the model thread without waiting for it; a failure is logged, not lost."""
        self.model.submit(fn, *args).add_done_callback(_log_failure)

    def workspace(self) -> Workspace:
        """The core workspace (model thread only), created with the configured include paths."""
        if self._ws is None:
            from ..semantics.compile import Workspace
            self._ws = Workspace(self._include_paths())
        return self._ws

    def _include_paths(self) -> list[str]:
        base = self.roots[0] if self.roots else os.getcwd()
        return [p if os.path.isabs(p) else os.path.join(base, p) for p in self.settings.include_paths]

    def reset_workspace(self) -> None:
        """Start a new core workspace (after include paths change); model thread only."""
        self._ws = None
        ws = self.workspace()
        for doc in list(self.docs.values()):
            ws.set_overlay(doc.path, doc.state.text)

    def index_of(self, source: Source) -> LineIndex:
        """A line index for another file's text (model thread)."""
        return self.line_indexes.get(source, self.encoding)

    def location(self, source: Source, span: Span) -> Any:
        """An LSP location of a span in any file (model thread)."""
        from . import convert
        return convert.location(path_to_uri(source.path), self.index_of(source), span)

    def compile(self, doc: Document) -> tuple[CompiledVersion, list[tuple[str, int | None, list[Any]]]]:
        """Compile the newest version of an open document (model thread).

        Returns the compiled version (installed only while the document is still open)
        and the diagnostics to publish.
        """
        from . import convert
        uri, path, state = doc.uri, doc.path, doc.state
        ws = self.workspace()
        index = state.index
        last = self.compiled.get(uri)
        kept = doc.log.kept(last.seq, state.seq, len(last.text)) if last is not None else None
        try:
            comp = ws.compile_text(path, state.text, (last.text, *kept) if last is not None and kept else None)
        except Exception as e:  # the model must never take the server down
            log.exception("compiling %s failed", uri)
            ver = CompiledVersion(uri, path, state.version, state.seq, state.text, index, None)
            self._install(doc, ver)
            return ver, [(uri, state.version, [convert.internal_error(f"iface failed on this file: {e!r}")])]
        names, topics = names_of(comp, self.compiled.get(uri))
        deps = frozenset(c.path for c in comp.closure()[1:])
        ver = CompiledVersion(uri, path, state.version, state.seq, state.text, index, comp, names, topics, deps)
        self._install(doc, ver)
        uri_of = path_to_uri
        found = self.findings.of(path, comp, self.settings, self._include_paths())
        pubs: list[tuple[str, int | None, list[Any]]] = [
            (uri, state.version, [*(convert.diagnostic(d, index, uri_of, self.index_of) for d in found),
                                  *self.live.get(uri, ())])]
        for inc in comp.closure()[1:]:
            inc_uri = path_to_uri(inc.path)
            if inc_uri in self.docs:
                continue
            inc_index = self.index_of(inc.source)
            pubs.append((inc_uri, None, [convert.diagnostic(d, inc_index, uri_of, self.index_of)
                                         for d in capped(inc.diagnostics)]))
        return ver, pubs

    def _install(self, doc: Document, ver: CompiledVersion) -> None:
        if self.docs.get(doc.uri) is doc:
            self.compiled[doc.uri] = ver

    def compile_disk(self, uri: str) -> CompiledVersion | None:
        """A compiled version of a file that is not open, read from the disk (model thread)."""
        path = uri_to_path(uri)
        if not os.path.isfile(path):
            return None
        comp = self.workspace().compile_path(path)
        text = comp.source.text
        return CompiledVersion(uri, path, -1, 0, text, LineIndex(text, self.encoding), comp, *names_of(comp))

    # ---- documents (event loop) ----------------------------------------------------
    def open(self, uri: str, text: str, version: int) -> None:
        """A document was opened."""
        self.docs[uri] = Document(uri, text, version, self.encoding)
        self.compiled.pop(uri, None)  # a compiled version of an earlier opening counts edits of another log
        self.changed(uri)

    def change(self, uri: str, changes: list[Any], version: int) -> None:
        """A document changed."""
        doc = self.docs.get(uri)
        if doc is None:
            return
        doc.apply(changes, version)
        self.changed(uri)

    def close(self, uri: str) -> None:
        """A document was closed: back to the disk for anything that includes it."""
        doc = self.docs.pop(uri, None)
        if doc is None:
            return
        self.compiled.pop(uri, None)
        for _, fut in self._waiters.pop(uri, []):
            if not fut.done():
                fut.set_result(None)
        keep = {d.path for d in self.docs.values()}
        for ver in self.compiled.values():
            keep |= ver.deps
        self.submit(self._release, doc.path, keep)
        self.publish(uri, None, [])
        for other, ver in list(self.compiled.items()):
            if doc.path in ver.deps:
                self.changed(other)

    def _release(self, path: str, keep: set[str]) -> None:
        """Forget what was cached for a closed document, unless an open document (``keep``) still uses it.

        Files of the workspace index stay cached: the index holds their compilations anyway.
        """
        if self._ws is not None:
            self._ws.set_overlay(path, None)
            indexed = set(getattr(self.workspace_index, "compilations", {}) or {})
            self._ws.retain({self._ws.normpath(p) for p in keep | indexed})
        self.line_indexes.retain(keep)
        self.findings.retain(keep)

    def file_changed_on_disk(self, path: str) -> None:
        """A file that is not open changed: recheck the open documents that include it."""
        for uri, ver in list(self.compiled.items()):
            if path in ver.deps:
                self.changed(uri)

    def set_live(self, found: dict[str, list[Any]]) -> None:
        """Put the findings of a verify run on their files (open ones with their own diagnostics), clear the last."""
        before, self.live = set(self.live), {u: d for u, d in found.items() if d}
        for uri in sorted(before | set(self.live)):
            if uri in self.docs:
                self.changed(uri)
            else:
                self.publish(uri, None, list(self.live.get(uri, ())))

    def recheck_all(self) -> None:
        """Compile every open document again (settings changed)."""
        for uri in self.docs:
            self.changed(uri)

    # ---- scheduling (event loop) ---------------------------------------------------
    def changed(self, uri: str) -> None:
        """Schedule a compile of ``uri`` (edited, opened, or asked for): before any re-check of dependents."""
        self._edited.add(uri)
        self._schedule(uri)

    def _schedule(self, uri: str) -> None:
        self._dirty.add(uri)
        if self._task is None or self._task.done():
            self._kick = asyncio.Event()
            self._task = asyncio.get_running_loop().create_task(self._drain())

    def _flush(self) -> None:
        if self._kick is not None:
            self._kick.set()

    def _changed_deps(self, uri: str) -> list[str]:
        """The open documents that ``uri``'s last check included and that changed since (their check pending)."""
        ver = self.compiled.get(uri)
        if ver is None or not ver.deps:
            return []
        pending = self._dirty | ({self._compiling} if self._compiling else set())
        return sorted(u for u in pending if u != uri and u in self.docs and self.docs[u].path in ver.deps)

    def _behind(self, uri: str) -> bool:
        """Whether ``uri``'s last check read a file that changed since: its re-check is due, or the changed
        file's own check is still to come."""
        return (uri in self._dirty and uri not in self._edited) or bool(self._changed_deps(uri))

    def _next(self) -> str:
        """The document to compile next: one a request waits for (after the changed files it includes), then
        an edited one, then a dependent."""
        for group in (self._dirty & self._waiters.keys(), self._dirty & self._edited, self._dirty):
            if group:
                first = min(group)
                deps = self._changed_deps(first) if first in self._waiters else []
                return deps[0] if deps else first
        raise LookupError("nothing to compile")

    async def _drain(self) -> None:
        """Compile dirty documents one at a time.

        An edit waits ``diagnostics_delay`` for the rest of its burst; dependents
        of an edited file are re-checked after it, one by one, and a new edit
        goes before those still waiting (they are then checked against it).
        """
        assert self._kick is not None
        while self._dirty:
            delay = self.settings.diagnostics_delay
            if delay > 0 and self._dirty & self._edited and not self._kick.is_set():
                try:
                    await asyncio.wait_for(self._kick.wait(), delay)
                except asyncio.TimeoutError:
                    pass
            self._kick.clear()
            while self._dirty:
                uri = self._next()
                self._dirty.discard(uri)
                self._edited.discard(uri)
                self._compiling = uri
                try:
                    await self._check(uri)
                except Exception:  # keep checking the other documents, and the next edits
                    log.exception("checking %s failed", uri)
                finally:
                    self._compiling = None
                if self._dirty & self._edited and not self._kick.is_set() and delay > 0:
                    break  # an edit came meanwhile: let its burst end first

    async def _check(self, uri: str) -> None:
        doc = self.docs.get(uri)
        if doc is None:
            return
        ver, pubs = await self.run(self.compile, doc)
        if self.docs.get(uri) is not doc:
            return  # closed or opened again meanwhile
        self._publish_all(uri, pubs)
        doc.log.forget_before(ver.seq)
        self._wake_waiters(uri, ver)
        for other, over in list(self.compiled.items()):
            if other != uri and doc.path in over.deps and other in self.docs:
                self._schedule(other)

    def _publish_all(self, owner: str, pubs: list[tuple[str, int | None, list[Any]]]) -> None:
        now = {u for u, _, _ in pubs[1:]}
        for uri, version, diags in pubs:
            if uri != owner:
                self._external.setdefault(uri, set()).add(owner)
            self.publish(uri, version, diags)
        for uri, owners in list(self._external.items()):
            if owner in owners and uri not in now:
                owners.discard(owner)
                if not owners:
                    del self._external[uri]
                    if uri not in self.docs:
                        self.publish(uri, None, [])

    def _wake_waiters(self, uri: str, ver: CompiledVersion) -> None:
        waiters = self._waiters.get(uri)
        if not waiters:
            return
        keep = []
        for version, fut in waiters:
            if fut.done():
                continue
            if ver.version >= version or uri not in self.docs:
                fut.set_result(ver)
            else:
                keep.append((version, fut))
        if keep:
            self._waiters[uri] = keep
            self.changed(uri)
            self._flush()
        else:
            self._waiters.pop(uri, None)

    async def latest(self, uri: str, fresh: bool = False) -> CompiledVersion | None:
        """The latest compiled version of ``uri``; with ``fresh``, one of its current version.

        Without ``fresh`` a document that has never been compiled is compiled now.
        """
        doc = self.docs.get(uri)
        if doc is None:
            ver = self.compiled.get(uri)
            return ver if ver is not None else await self.run(self.compile_disk, uri)
        ver = self.compiled.get(uri)
        if ver is not None and (not fresh or ver.version == doc.state.version) and not self._behind(uri):
            return ver
        fut: asyncio.Future[CompiledVersion | None] = asyncio.get_running_loop().create_future()
        self._waiters.setdefault(uri, []).append((doc.state.version, fut))
        self.changed(uri)
        self._flush()
        return await fut

    async def view(self, uri: str, fn: Callable[[DocumentView], T], fresh: bool = False) -> T | None:
        """Run ``fn`` on the model thread over the latest compiled version of ``uri`` seen from its current text."""
        ver = await self.latest(uri, fresh)
        if ver is None:
            return None
        return await self.run(self._in_view, uri, fn)

    def _in_view(self, uri: str, fn: Callable[[DocumentView], T]) -> T | None:
        doc = self.docs.get(uri)
        ver = self.compiled.get(uri)
        if doc is None:
            ver = ver or self.compile_disk(uri)
            if ver is None:
                return None
            state = DocState(ver.text, ver.version, ver.seq, self.encoding)
            return fn(DocumentView(self, ver, state, []))
        if ver is None:
            return None
        state = doc.state
        edits = doc.log.between(ver.seq, state.seq) if state.seq > ver.seq else []
        return fn(DocumentView(self, ver, state, edits))

    def open_interfaces(self) -> list[Interface]:
        """Interfaces of every open document and everything they include (model thread)."""
        out: dict[str, Interface] = {}
        for ver in list(self.compiled.values()):
            if ver.comp is None:
                continue
            for c in ver.comp.closure():
                out.setdefault(c.path, c.interface)
        return list(out.values())
