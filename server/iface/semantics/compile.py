"""compile: text → Compilation (model, includes, diagnostics). What every consumer uses."""

from __future__ import annotations

import gc
import math
import os
import re
from bisect import bisect_left, bisect_right
from collections.abc import Callable, Generator, Iterable
from dataclasses import dataclass, field
from operator import attrgetter
from pathlib import Path
from typing import Literal

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, Severity, make
from ..model.normalize import normalize_action, normalize_service
from ..model.source import Source, Span
from ..syntax.edits import Change, EditCache, parse_edited
from ..syntax.parse import parse_text
from .analysis import Analysis, analyse

#: Files larger than this are refused with a message (interface files are small).
MAX_FILE_BYTES = 4 * 1024 * 1024
SUFFIXES = (".iface", ".thrift")
#: Include chains longer than this are refused (the message names the chain): no real interface nests so deep.
MAX_INCLUDE_DEPTH = 1000
_SURROGATE = re.compile("[\ud800-\udfff]")


@dataclass(eq=False)
class Compilation:
    """One compiled file: its model, the compilations of its includes, its diagnostics."""

    source: Source
    interface: m.Interface
    diagnostics: list[Diagnostic]
    includes: dict[str, Compilation] = field(default_factory=dict)

    @property
    def path(self) -> str:
        """The file's path."""
        return self.source.path

    @property
    def has_errors(self) -> bool:
        """True when the file itself has an error."""
        return any(d.severity == Severity.ERROR for d in self.diagnostics)

    def all_diagnostics(self) -> list[Diagnostic]:
        """Diagnostics of this file and of every file it includes, each file once."""
        return [d for c in self.closure() for d in c.diagnostics]

    def closure(self) -> list[Compilation]:
        """This compilation and those of all files it includes, each once, depth first."""
        out: list[Compilation] = []
        seen: set[str] = set()
        stack: list[Compilation] = [self]
        while stack:
            c = stack.pop()
            if c.path in seen:
                continue
            seen.add(c.path)
            out.append(c)
            stack.extend(reversed(list(c.includes.values())))
        return out


def too_large(text: str) -> bool:
    """True when ``text`` is more than ``MAX_FILE_BYTES`` as UTF-8 (an editor buffer: the limit files have)."""
    if len(text) > MAX_FILE_BYTES:
        return True
    return len(text) * 4 > MAX_FILE_BYTES and len(text.encode("utf-8", errors="surrogatepass")) > MAX_FILE_BYTES


def too_large_diagnostic(path: str, size: int) -> Diagnostic:
    """The one finding of a file over the limit: nothing of it is read."""
    return make("file-too-large", f"the file is {size / (1024 * 1024):.1f} MB; iface reads interface files up to "
                f"{MAX_FILE_BYTES // (1024 * 1024)} MB", Source(path, ""), Span(0, 0))


def decode(data: bytes, path: str) -> tuple[str, list[Diagnostic]]:
    """Bytes → text; bad input gets a diagnostic instead of an exception."""
    problems: list[Diagnostic] = []
    if len(data) > MAX_FILE_BYTES:
        return "", [too_large_diagnostic(path, len(data))]
    nul = data.find(b"\0")
    if nul >= 0:
        text = data[:nul].decode("utf-8", errors="replace")
        src = Source(path, text)
        return "", [make("binary-file", "the file holds NUL bytes: it is binary, not an interface file",
                         src, Span(len(text), len(text)))]
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        good = data[:e.start].decode("utf-8")
        text = data.decode("utf-8", errors="replace")
        src = Source(path, text)
        problems.append(make("invalid-encoding", f"byte 0x{data[e.start]:02x} is not valid UTF-8 "
                             "(iface files are UTF-8); undecodable bytes are read as U+FFFD",
                             src, Span(len(good), len(good) + 1)))
    return text, problems


class Workspace:
    """Reads and compiles files, caching them; open editor buffers override the disk."""

    def __init__(self, include_paths: Iterable[str] = ()) -> None:
        self.include_paths = [str(p) for p in include_paths]
        self.overlays: dict[str, str] = {}
        self._cache: dict[str, tuple[object, Compilation]] = {}
        self._chunks: dict[str, EditCache] = {}
        self._memos: dict[str, Analysis] = {}

    # ---- reading ---------------------------------------------------------------
    @staticmethod
    def normpath(path: str) -> str:
        """The absolute, normalised form of a path used as a key."""
        return os.path.abspath(path)

    def set_overlay(self, path: str, text: str | None) -> None:
        """Use ``text`` for ``path`` instead of the disk (None: back to the disk)."""
        key = self.normpath(path)
        if text is None:
            self.overlays.pop(key, None)
            self._chunks.pop(key, None)
            self._memos.pop(key, None)
        else:
            self.overlays[key] = text

    def retain(self, keep: set[str]) -> None:
        """Forget every cached file outside ``keep`` (normalised paths): its compilation, overlay, chunks."""
        for store in (self._cache, self.overlays, self._chunks, self._memos):
            for key in [k for k in store if k not in keep]:
                del store[key]

    def cached_paths(self) -> set[str]:
        """The files something is cached for."""
        return {*self._cache, *self.overlays, *self._chunks, *self._memos}

    def _stamp(self, key: str) -> object:
        if key in self.overlays:
            return ("overlay", self.overlays[key])
        try:
            st = os.stat(key)
        except OSError:
            return None
        return (st.st_mtime_ns, st.st_size)

    def read(self, path: str) -> tuple[str | None, list[Diagnostic]]:
        """The text of a file (None if it cannot be read) and any decoding problems."""
        key = self.normpath(path)
        if key in self.overlays:
            return self.overlays[key], []
        try:
            data = Path(key).read_bytes()
        except OSError:
            return None, []
        return decode(data, path)

    def find_include(self, including: str, name: str) -> str | None:
        """The file an include names: beside the including file, then on the include paths."""
        if os.path.isabs(name):
            return name if self._exists(name) else None
        for base in [os.path.dirname(self.normpath(including)), *self.include_paths]:
            candidate = self.normpath(os.path.join(base, name))
            if self._exists(candidate):
                return candidate
        return None

    def _exists(self, path: str) -> bool:
        return self.normpath(path) in self.overlays or os.path.isfile(path)

    # ---- compiling -------------------------------------------------------------------
    def compile_path(self, path: str) -> Compilation:
        """Compile a file from the overlay or the disk (a missing file gets a diagnostic)."""
        return self._compile(self.normpath(path), None)

    def compile_text(self, path: str, text: str, edited: tuple[str, int, int] | None = None) -> Compilation:
        """Compile ``text`` as the content of ``path`` (an editor buffer).

        ``edited`` is (last text, head, tail) when ``text`` is the last text compiled for ``path`` with only
        what lies between its first ``head`` and last ``tail`` characters edited: the texts are then not
        compared to find where they differ (a comparison that takes time with the length of the file).
        """
        key = self.normpath(path)
        if (cache := self._chunks.get(key)) is not None:
            cache.known = edited  # None too: what an earlier call said is not about this text
        self.overlays[key] = text
        return self._compile(key, text)

    def _deps_fresh(self, comp: Compilation, fresh: set[str]) -> bool:
        """True when every file ``comp`` includes, at any depth, is cached as it is now.

        ``fresh`` holds the files found fresh already during this compile: each is looked at once.
        """
        stack = [comp]
        while stack:
            c = stack.pop()
            for path, inc in c.includes.items():
                if path in fresh:
                    continue
                cached = self._cache.get(path)
                if cached is None or cached[1] is not inc or cached[0] != self._stamp(path):
                    return False
                fresh.add(path)
                stack.append(inc)
        return True

    def _cached(self, key: str, fresh: set[str]) -> Compilation | None:
        """The cached compilation of ``key`` if neither it nor what it includes changed since."""
        cached = self._cache.get(key)
        if cached is None:
            return None
        if key not in fresh:
            stamp = self._stamp(key)
            if stamp is None or cached[0] != stamp or not self._deps_fresh(cached[1], fresh):
                return None
            fresh.add(key)
        return cached[1]

    def _compile(self, key: str, text: str | None) -> Compilation:
        """Compile ``key`` and what it includes, depth first, without recursion.

        Each file's compilation is a generator that asks for the files it
        includes; this loop keeps the chain of files being compiled as an
        explicit stack, so an include chain of any length needs no Python stack
        (and a file's parse never runs deep in one). A file that includes one
        already on the chain closes a cycle; past ``MAX_INCLUDE_DEPTH`` files
        an include is refused with the chain named.
        """
        fresh: set[str] = set()
        cached = self._cached(key, fresh)  # an editor buffer's text is its overlay: its stamp
        if cached is not None:
            return cached
        with collector_paused():
            return self._compile_chain(key, text, fresh)

    def _compile_chain(self, key: str, text: str | None, fresh: set[str]) -> Compilation:
        """``_compile``'s loop over the chain of files being compiled."""
        frames: list[tuple[str, object, CompileSteps]] = [(key, self._stamp(key), self._steps(key, text))]
        on_chain = {key}
        answer: Compilation | Refused | None = None
        while True:
            path, stamp, steps = frames[-1]
            try:
                wanted = steps.send(answer)
            except StopIteration as done:
                comp: Compilation = done.value
                self._cache[path] = (stamp, comp)
                fresh.add(path)
                frames.pop()
                on_chain.discard(path)
                if not frames:
                    return comp
                answer = comp
                continue
            if wanted in on_chain:
                answer = Refused("cycle", [f[0] for f in frames])
                continue
            cached = self._cached(wanted, fresh)
            if cached is not None:
                answer = cached
            elif len(frames) >= MAX_INCLUDE_DEPTH:
                answer = Refused("depth", [*(f[0] for f in frames), wanted])
            else:
                frames.append((wanted, self._stamp(wanted), self._steps(wanted, None)))
                on_chain.add(wanted)
                answer = None

    def _steps(self, key: str, text: str | None) -> CompileSteps:
        """The compilation of one file, asking for its includes as it goes."""
        problems: list[Diagnostic] = []
        if text is None:
            text, problems = self.read(key)
            if text is None:
                src = Source(key, "")
                return Compilation(src, m.Interface(src, Path(key).stem),
                                   [make("include-not-found", f"cannot read '{key}'", src, Span(0, 0))])
        elif too_large(text):
            src = Source(key, "")
            size = len(text.encode("utf-8", errors="surrogatepass"))
            return Compilation(src, m.Interface(src, Path(key).stem), [too_large_diagnostic(key, size)])
        editing = key in self.overlays
        cache = self._chunks.setdefault(key, EditCache()) if editing else None
        memo = self._memos.setdefault(key, Analysis()) if editing else None
        return (yield from compile_steps(Source(key, text), problems, cache=cache, memo=memo,
                                         find=self.find_include))


@dataclass(frozen=True, slots=True)
class Refused:
    """An include that is not compiled: it closes a ``cycle`` or goes past the ``depth`` limit; ``chain``
    is the files that lead to it."""

    reason: Literal["cycle", "depth"]
    chain: list[str]


#: A file's compilation: yields the paths of the files it includes, is sent their compilations (or why
#: not), returns its own.
CompileSteps = Generator[str, "Compilation | Refused | None", Compilation]


def compile_source(source: Source, problems: list[Diagnostic] | None = None, *,
                   cache: EditCache | None = None,
                   memo: Analysis | None = None,
                   includes: Workspace | None = None) -> Compilation:
    """Parse, model, resolve and check one source; ``includes`` finds and compiles the files it includes."""
    steps = compile_steps(source, problems, cache=cache, memo=memo,
                          find=includes.find_include if includes is not None else None)
    answer: Compilation | Refused | None = None
    with collector_paused():
        while True:
            try:
                wanted = steps.send(answer)
            except StopIteration as done:
                return done.value
            assert includes is not None  # nothing is asked for without a way to find it
            answer = includes.compile_path(wanted)


class collector_paused:  # named as a function: `with collector_paused():`
    """The cyclic garbage collector paused while a compile works (parsing, modelling and checking make many
    objects and free none of them to it), then as it was. Its first young collection afterwards traverses what
    the compile made, for the caller (a one-shot ``iface-lsp check`` has none: ``cli.ONE_SHOT``).

    A class, not a generator: leaving it allocates nothing the collector tracks (a generator's end raises a
    StopIteration, which would start that collection inside the compile)."""

    __slots__ = ("enabled",)

    def __enter__(self) -> None:
        self.enabled = gc.isenabled()
        gc.disable()

    def __exit__(self, *exc: object) -> None:
        if self.enabled:
            gc.enable()


def compile_steps(source: Source, problems: list[Diagnostic] | None = None, *,
                  cache: EditCache | None = None,
                  memo: Analysis | None = None,
                  find: Callable[[str, str], str | None] | None = None) -> CompileSteps:
    """``compile_source`` as steps: yields each included file's path and is sent its compilation."""
    # (its drivers, compile_source and Workspace, pause the cyclic collector over the whole chain: collector_paused)
    diagnostics: list[Diagnostic] = list(problems or [])
    diagnostics.extend(_surrogates(source))
    parsed = parse_text(source.text) if cache is None else parse_edited(source.text, cache)
    change = cache.change if cache is not None and memo is not None else None
    before = memo.iface if memo is not None else None
    if change is None or before is None or before.items is not change[3]:
        before = change = None
    iface = build_interface(source, parsed.items, before, change)
    for p in parsed.problems:
        diagnostics.append(make(p.code, p.message, source, p.span, **p.data))
    included = yield from _include(iface, diagnostics, find)
    diagnostics.extend(analyse(iface, memo, change))
    broken = parsed.broken_ranges() if any(p.code == "syntax-error" for p in parsed.problems) else None
    if broken:
        diagnostics = [d for d in diagnostics if d.code == "syntax-error" or d.source is not source
                       or not _inside(broken, d.span.start)]
    if not iface.items and not diagnostics:
        diagnostics.append(make("empty-file", "the file is empty: it defines no interface", source, Span(0, 0)))
    diagnostics.sort(key=lambda d: (d.span.start, d.span.end))
    return Compilation(source, iface, diagnostics, included)


def _inside(ranges: list[tuple[int, int]], offset: int) -> bool:
    """True when ``offset`` lies in one of ``ranges`` (sorted, not overlapping): a binary search."""
    i = bisect_right(ranges, (offset, math.inf)) - 1
    return i >= 0 and offset < ranges[i][1]


def _surrogates(source: Source) -> list[Diagnostic]:
    """A lone UTF-16 surrogate in the text (an editor can send one; a file read as UTF-8 never holds one)."""
    found = None if source.text.isascii() else _SURROGATE.search(source.text)
    if found is None:
        return []
    return [make("invalid-encoding", f"U+{ord(found.group()):04X} is a lone UTF-16 surrogate: it is no character "
                 "and cannot be written as UTF-8", source, Span(found.start(), found.end()))]


#: The lists of an Interface that sort its items, and the kinds of item each holds (the rest: definitions).
_LISTS: tuple[tuple[str, type], ...] = (("wirings", m.Wiring), ("includes", m.Include), ("namespaces", m.Namespace),
                                       ("externals", m.External), ("component_decls", m.ComponentDecl),
                                       ("system_decls", m.SystemDecl), ("instances", m.Instance))
_START = attrgetter("span.start")


def _list_of(item: m.Item) -> str:
    for name, kind in _LISTS:
        if isinstance(item, kind):
            return name
    return "definitions"


def build_interface(source: Source, items: list[m.Item], before: m.Interface | None = None,
                    change: Change | None = None) -> m.Interface:
    """Sort parsed items into an Interface (before resolution).

    With the interface of the version ``before`` and what the edit ``change``d, its lists are the lists
    before with the items gone replaced by the new ones, in time that follows the edit.
    """
    iface = m.Interface(source, Path(source.path).stem)
    iface.items = items
    if before is not None and change is not None and items and _splice(iface, before, change):
        return iface
    iface.wirings, iface.includes, iface.namespaces, iface.externals = [], [], [], []
    iface.component_decls, iface.definitions, iface.component = [], [], None
    iface.system_decls, iface.instances = [], []
    for item in items:
        if isinstance(item, m.Wiring):
            iface.wirings.append(item)
        elif isinstance(item, m.Include):
            iface.includes.append(item)
        elif isinstance(item, m.Namespace):
            iface.namespaces.append(item)
        elif isinstance(item, m.External):
            iface.externals.append(item)
        elif isinstance(item, m.ComponentDecl):
            iface.component_decls.append(item)
            if iface.component is None:
                iface.component = item
        elif isinstance(item, m.SystemDecl):
            iface.system_decls.append(item)
        elif isinstance(item, m.Instance):
            iface.instances.append(item)
        else:
            if isinstance(item, m.Service):
                normalize_service(item)
            elif isinstance(item, m.Action):
                normalize_action(item)
            iface.definitions.append(item)
    _name(iface)
    return iface


def _name(iface: m.Interface) -> None:
    """The file's name and version: its component's, or its system's, else the file stem."""
    iface.component = iface.component_decls[0] if iface.component_decls else None
    iface.system = iface.system_decls[0] if iface.system_decls else None
    decl = iface.component or iface.system
    if decl is not None:
        iface.name = decl.name
        iface.version = decl.version


def _splice(iface: m.Interface, before: m.Interface, change: Change) -> bool:
    """Fill the lists of ``iface`` from those ``before`` and the ``change``; False if they do not fit."""
    cut, gone, new, _ = change
    where: dict[str, tuple[int, int, int]] = {}
    for name in (*(n for n, _ in _LISTS), "definitions"):
        old: list[m.Item] = getattr(before, name)
        out = [x for x in gone if _list_of(x) == name]
        come = [x for x in new if _list_of(x) == name]
        if not out and not come:
            setattr(iface, name, old)  # shared: an interface's lists are made, never changed
            continue
        at = bisect_left(old, cut, key=_START)
        if any(a is not b for a, b in zip(old[at:at + len(out)], out)) or len(old) < at + len(out):
            return False
        # one copy, the changed part replaced in place (a list of many items is copied once, not three times)
        spliced = old.copy()
        spliced[at:at + len(out)] = come
        setattr(iface, name, spliced)
        where[name] = (at, len(out), len(come))
    iface.spliced = (id(before), where)
    for item in new:
        if isinstance(item, m.Service):
            normalize_service(item)
        elif isinstance(item, m.Action):
            normalize_action(item)
    _name(iface)
    return True


def _include(iface: m.Interface, diagnostics: list[Diagnostic],
             find: Callable[[str, str], str | None] | None) -> Generator[str, Compilation | Refused | None,
                                                                          dict[str, Compilation]]:
    """Ask for the included files' compilations and register them under their prefixes."""
    src = iface.source
    out: dict[str, Compilation] = {}
    for inc in iface.includes:
        if inc.cpp:
            continue
        if not inc.path.endswith(SUFFIXES):
            diagnostics.append(make("include-not-interface", f"cannot include '{inc.path}': only .iface and "
                                    ".thrift files hold interfaces", src, inc.path_span))
            continue
        found = find(src.path, inc.path) if find is not None else None
        if found is None:
            diagnostics.append(make("include-not-found", f"cannot find included file '{inc.path}'",
                                    src, inc.path_span))
            continue
        inc.resolved = found
        comp = yield found
        if isinstance(comp, Refused) and comp.reason == "depth":
            diagnostics.append(make("include-too-deep", f"includes nest more than {MAX_INCLUDE_DEPTH} files deep: "
                                    f"{_chain(comp.chain)}; iface stops reading there", src, inc.path_span,
                                    chain=comp.chain))
            continue
        if not isinstance(comp, Compilation):
            diagnostics.append(make("include-cycle", f"'{inc.path}' includes this file back: "
                                    "includes must not form a cycle", src, inc.path_span))
            continue
        out[found] = comp
        chain = _path_back(comp, src.path)
        if chain:
            names = " → ".join(Path(p).name for p in [src.path, *chain])
            diagnostics.append(make("include-cycle", f"includes form a cycle: {names}", src, inc.path_span))
        prefixes = {Path(found).stem}
        ros = comp.interface.namespace("ros2")
        if ros:
            prefixes.add(ros)
        for p in prefixes:
            iface.included.setdefault(p, comp.interface)
        errors = [d for d in comp.all_diagnostics() if d.severity == Severity.ERROR]
        if errors and not chain:
            first = errors[0]
            line, col, _, _ = first.location()
            diagnostics.append(make(
                "include-error", f"'{inc.path}' has {len(errors)} error{'s' if len(errors) > 1 else ''}; "
                f"first: {first.message}", src, inc.path_span,
                related=[Related(first.source, first.span, first.message)]))
    return out


def _path_back(comp: Compilation, target: str) -> list[str]:
    """The include chain from ``comp`` back to ``target`` ([] when there is none)."""
    parent: dict[str, str | None] = {comp.path: None}
    stack = [comp]
    while stack:
        c = stack.pop()
        for inc in c.interface.includes:
            if inc.resolved == target:
                chain = [c.path]
                while (up := parent[chain[-1]]) is not None:
                    chain.append(up)
                return [*reversed(chain), target]
        for key, sub in c.includes.items():
            if key not in parent:
                parent[key] = c.path
                stack.append(sub)
    return []


def _chain(paths: list[str], keep: int = 3) -> str:
    """Files as ``a.iface → b.iface → …``, the middle of a long chain left out."""
    names = [Path(p).name for p in paths]
    if len(names) > 2 * keep + 1:
        names = [*names[:keep], f"… ({len(names) - 2 * keep} more)", *names[-keep:]]
    return " → ".join(names)
