"""Compiled versions of a document and how a request sees them from the current text.

A ``CompiledVersion`` is one compiled version (read on the model thread only, but for
``names``); a ``DocumentView`` is a compiled version seen from its document's current text,
mapping positions through the edits made since.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..semantics.systems import containers
from .convert import LineIndex
from .documents import DocState, Edit, map_back, map_forward

if TYPE_CHECKING:
    from collections.abc import Iterator

    from ..model.nodes import Definition, Interface, Wiring
    from ..model.source import Source, Span
    from ..semantics.compile import Compilation
    from .project import Project

@dataclass(frozen=True, slots=True)
class Name:
    """A definition as completion sees it (immutable, safe to read from any thread); its kind is its detail."""

    name: str
    kind: str
    doc: str
    members: tuple[str, ...] = ()


@dataclass(eq=False)
class CompiledVersion:
    """One compiled version of a document (read on the model thread only, except ``names``)."""

    uri: str
    path: str
    version: int
    seq: int
    text: str
    index: LineIndex
    comp: Compilation | None
    names: tuple[Name, ...] = ()
    #: The topic and the type name of each wiring: ((topic, type name), ...).
    topics: tuple[tuple[str, str], ...] = ()
    deps: frozenset[str] = frozenset()
    #: The type names of ``names`` sorted by name, local ones then included ones (completion builds it once).
    sorted_types: tuple[tuple[Name, ...], tuple[Name, ...]] | None = None

    @property
    def system_names(self) -> tuple[Name, ...]:
        """For a system file: the components its includes declare (kind ``component``), its instances
        (kind ``instance``) and the containers they name (kind ``container``, its instances as members);
        empty for any other file."""
        iface = self.iface
        if iface is None or (iface.system is None and not iface.instances):
            return ()
        out = [Name(inc.name, "component", inc.component.doc or "" if inc.component is not None else "")
               for inc in {i.name: i for i in iface.included.values()}.values()]
        out += [Name(i.name, "instance", i.doc or "", (i.component,)) for i in iface.instances]
        for box in containers(iface.instances):
            out.append(Name(box, "container", "", tuple(i.name for i in iface.instances if i.value("container") == box)))
        return tuple(out)

    @property
    def iface(self) -> Interface | None:
        """The compiled interface."""
        return self.comp.interface if self.comp is not None else None


@dataclass(eq=False)
class DocumentView:
    """A compiled version seen from the current text of its document."""

    project: Project
    ver: CompiledVersion
    state: DocState
    edits: list[Edit]

    @property
    def uri(self) -> str:
        return self.ver.uri

    @property
    def comp(self) -> Compilation | None:
        return self.ver.comp

    @property
    def iface(self) -> Interface | None:
        return self.ver.iface

    @property
    def text(self) -> str:
        """The current text."""
        return self.state.text

    @property
    def index(self) -> LineIndex:
        """The line index of the current text."""
        return self.state.index

    @property
    def current(self) -> bool:
        """True when the compiled version is of the current text."""
        return not self.edits

    def offset(self, line: int, character: int) -> int | None:
        """A current LSP position → an offset in the compiled version (None inside newly typed text)."""
        off = self.state.index.offset(line, character)
        return map_back(self.edits, off) if self.edits else off

    def place(self, start: int, end: int) -> tuple[int, int] | None:
        """A compiled version range → the current offsets (None if that text was replaced)."""
        if not self.edits:
            return start, end
        a = map_forward(self.edits, start)
        b = map_forward(self.edits, end)
        if a is None or b is None or b < a:
            return None
        return a, b

    def range(self, span: Span) -> Any:
        """The current LSP range of a compiled version span, or None."""
        from . import convert
        placed = self.place(span.start, span.end)
        return convert.range_(self.index, *placed) if placed is not None else None

    def location(self, source: Source, span: Span) -> Any:
        """An LSP location of a span in this document or in another file."""
        from . import convert
        if source.path == self.ver.path:
            rng = self.range(span)
            return convert.lsp.Location(uri=self.uri, range=rng) if rng is not None else None
        return self.project.location(source, span)


def names_of(comp: Compilation, last: CompiledVersion | None = None
             ) -> tuple[tuple[Name, ...], tuple[tuple[str, str], ...]]:
    """Names of a compilation for completion (local definitions, then included ones with their prefix)
    and its topics (``CompiledVersion.topics``).

    Chunks that did not change keep their definition objects, so the names of the ``last`` compiled version's
    definitions are kept and an edit rebuilds only its own. When the compilation's lists were spliced
    from those of the ``last`` compiled version's, so are its names and topics, in time that follows the edit
    (a list the edit did not change is the last one).
    """
    from ..model import nodes as m
    from ..model.walk import all_fields

    def make(prefix: str, d: m.Definition) -> Name:
        if isinstance(d, m.Enum):
            members = tuple(v.name for v in d.values)
        elif isinstance(d, m.Const):
            members = ()
        else:
            members = tuple(f.name for f in all_fields(d)) + tuple(c.name for c in getattr(d, "consts", ()))
        return Name(prefix + d.name, d.kind, d.doc or "", members)

    # the definitions of ``last``'s names (its interface's lists are its own: a compile makes new ones)
    # and the place of each by id, made when first needed
    old: list[m.Definition] | None = None
    known: dict[int, int] = {}

    def entry(prefix: str, d: m.Definition) -> Name:
        nonlocal old
        if old is None:
            old = [d for _, d in _named(last.iface)] if last is not None and last.iface is not None else []
            if len(old) == len(last.names if last is not None else ()):
                known.update((id(x), i) for i, x in enumerate(old))
        i = known.get(id(d))
        if i is not None and old[i] is d and last is not None and last.names[i].name == prefix + d.name:
            return last.names[i]
        return make(prefix, d)

    iface = comp.interface
    spliced = iface.spliced
    before = last.iface if last is not None else None
    if spliced is not None and before is not None and spliced[0] == id(before) and \
            [(p, id(i)) for p, i in before.included.items()] == [(p, id(i)) for p, i in iface.included.items()]:
        n = len(before.definitions)
        assert last is not None
        spliced_names = last.names
        if "definitions" in spliced[1]:
            at, out, come = spliced[1]["definitions"]
            spliced_names = (*last.names[:at], *(make("", d) for d in iface.definitions[at:at + come]),
                             *last.names[at + out:])
        topics = last.topics
        if "wirings" in spliced[1]:
            at, out, come = spliced[1]["wirings"]
            topics = (*last.topics[:at], *_topics(iface.wirings[at:at + come]), *last.topics[at + out:])
        if len(spliced_names) - len(last.names) == len(iface.definitions) - n:
            return spliced_names, topics
    return tuple(entry(prefix, d) for prefix, d in _named(iface)), tuple(_topics(iface.wirings))


def _named(iface: Interface) -> Iterator[tuple[str, Definition]]:
    """The definitions ``names_of`` names, in its order, with their prefix: local ones (''), then those of
    each include (``prefix.``)."""
    for d in iface.definitions:
        yield "", d
    for prefix, inc in sorted(iface.included.items()):
        for d in inc.definitions:
            yield prefix + ".", d


def _topics(wirings: list[Wiring]) -> Iterator[tuple[str, str]]:
    """The topic and the type name of each wiring."""
    for w in wirings:
        yield w.topic, w.type.name
