"""One side of a comparison: a compilation with its definitions by qualified name,
canonical type keys, and which endpoints reach each definition in which direction."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from ..model import nodes as m
from ..model.source import Source, Span
from ..model.walk import named_types
from ..semantics.compile import Compilation
from .findings import Location

SEND, RECEIVE = "send", "receive"
BOTH = frozenset({SEND, RECEIVE})
#: the role of an endpoint -> (direction of its own data, direction of the answer)
_FLOW = {"publishes": SEND, "subscribes": RECEIVE, "provides": RECEIVE, "calls": SEND}


def channel(ep: m.Endpoint, kind: str) -> str:
    """The usage key of an endpoint: ``topic:/x``, ``service:/s`` or ``action:/a``."""
    return f"{kind}:{ep.name}"


def flip(d: str) -> str:
    """The other direction."""
    return RECEIVE if d == SEND else SEND


class Side:
    """A compilation seen by the comparison."""

    def __init__(self, comp: Compilation) -> None:
        self.comp = comp
        self.iface = comp.interface
        self.source = comp.source
        #: qualified name -> (definition, source it is written in)
        self.defs: dict[str, tuple[m.Definition, Source]] = {}
        self._qual: dict[int, str] = {}
        self._package: dict[int, str] = {}
        for c in comp.closure():
            prefix = "" if c is comp else Path(c.path).stem + "."
            package = package_of(c.interface, root=c is comp)
            for d in c.interface.definitions:
                q = prefix + d.name
                self._package.setdefault(id(d), package)
                if q not in self.defs:
                    self.defs[q] = (d, c.source)
                    self._qual[id(d)] = q
        #: id(definition) -> directions it flows in; keys of the endpoints that reach it
        self.dirs: dict[int, set[str]] = {}
        self.keys: dict[int, set[str]] = {}
        self._reach()

    # ---- names and types ----------------------------------------------------------------
    @property
    def name(self) -> str:
        """The component's name."""
        return self.iface.name

    def qualname(self, d: m.Definition) -> str:
        """The name of a definition, prefixed with its include's stem when included."""
        return self._qual.get(id(d), d.name)

    def identity(self, d: m.Definition) -> str:
        """How every component knows a definition: ``package/Name``, the package being the ``ros2``
        namespace of the file it is written in, as ROS 2 names it on the wire. A definition of a file
        without one is ``Name`` in the component's own file and ``stem/Name`` in an included file."""
        package = self._package.get(id(d), package_of(self.iface, root=True))
        return f"{package}/{d.name}" if package else d.name

    def type_key(self, t: m.TypeRef | None) -> str:
        """A canonical spelling of a type: aliases, ``list<T>``/``T[]`` and prefixes unified."""
        if t is None:
            return "void"
        if isinstance(t, m.BaseType):
            return f"{t.name}<={t.bound}" if t.bound is not None else t.name
        if isinstance(t, m.NamedType):
            return self._named_key(t)
        if isinstance(t, m.MapType):
            return f"map<{self.type_key(t.key)},{self.type_key(t.element)}>"
        if isinstance(t, m.SetType):
            return f"set<{self.type_key(t.element)}>"
        inner = self.type_key(t.element)
        if t.array == "fixed":
            return f"{inner}[{t.size}]"
        if t.array == "bounded":
            return f"{inner}[<={t.size}]"
        return f"{inner}[]"

    def _named_key(self, t: m.NamedType) -> str:
        return self.qualname(t.target) if t.target is not None else t.name

    def wire(self) -> Side:
        """This side with named types keyed by identity (``package/Name``), as other components see them."""
        return WireSide(self)

    def where(self, d: m.Definition) -> Source:
        """The source a definition is written in."""
        q = self.qualname(d)
        return self.defs[q][1] if q in self.defs else self.source

    def loc(self, span: Span | None, source: Source | None = None) -> Location:
        """A location in this side (the start of the file when ``span`` is None)."""
        return Location(source or self.source, span if span is not None else Span(0, 0))

    def anchor(self) -> Location:
        """Where whole-component findings point: the component header, else the file start."""
        comp = self.iface.component
        return self.loc(comp.name_span if comp is not None else None)

    def wiring_anchor(self) -> Location:
        """Where a removed wiring is reported in this side: its last wiring, else the anchor."""
        if self.iface.wirings:
            return self.loc(self.iface.wirings[-1].span)
        return self.anchor()

    # ---- reachability ----------------------------------------------------------------
    def _reach(self) -> None:
        for kind, eps in (("topic", self.iface.subscribed), ("topic", self.iface.published),
                          ("service", self.iface.services), ("action", self.iface.actions)):
            for ep in eps:
                key = channel(ep, kind)
                d = ep.definition
                if d is None:
                    continue
                flow = _FLOW[ep.role]
                dirs = {flow} if ep.wiring is not None else set(BOTH)
                self._visit(d, dirs, key)
        for ep in self.iface.diagnostics_endpoints:  # Δ: the component receives the requests
            if ep.definition is not None:
                self._visit(ep.definition, {RECEIVE}, f"service:{ep.name}")
        for d in self.iface.definitions:
            if isinstance(d, m.Struct) and d.kind == "configuration":
                for f in d.fields:
                    self._mark_type(f.type, {RECEIVE}, f"parameter:{f.name}")
            elif isinstance(d, m.Struct) and d.kind == "state":
                for f in d.fields:
                    self._mark_type(f.type, set(BOTH), f"state:{f.name}")

    def _visit(self, d: m.Definition, dirs: set[str], key: str) -> None:
        """Mark ``d`` as flowing in ``dirs`` (as seen from its top) and everything below it."""
        stack: list[tuple[m.Definition, frozenset[str]]] = [(d, frozenset(dirs))]
        while stack:
            x, ds = stack.pop()
            have = self.dirs.setdefault(id(x), set())
            keys = self.keys.setdefault(id(x), set())
            if ds <= have and key in keys:
                continue
            have |= ds
            keys.add(key)
            for child, cds in self._children(x, ds):
                stack.append((child, cds))

    def _mark_type(self, t: m.TypeRef, dirs: set[str], key: str) -> None:
        for d in _named_defs(t):
            self._visit(d, dirs, key)

    def _children(self, d: m.Definition, ds: frozenset[str]) -> Iterator[tuple[m.Definition, frozenset[str]]]:
        """Definitions used inside ``d`` with the direction they flow in."""
        flipped = frozenset(flip(x) for x in ds)
        if isinstance(d, m.Typedef):
            for t in _named_defs(d.type):
                yield t, ds
        elif isinstance(d, m.Struct):
            for f in d.fields:
                for t in _named_defs(f.type):
                    yield t, ds
        elif isinstance(d, m.Service):
            # ds is the direction of the request as seen by this side
            if d.extends is not None and d.extends.target is not None:
                yield d.extends.target, ds
            for fn in d.functions:
                for f in fn.params:
                    yield from ((t, ds) for t in _named_defs(f.type))
                for f in fn.throws:
                    yield from ((t, flipped) for t in _named_defs(f.type))
                if fn.returns is not None:
                    yield from ((t, flipped) for t in _named_defs(fn.returns))
            for sec, sds in ((d.request, ds), (d.response, flipped)):
                for f in sec.fields if sec else []:
                    yield from ((t, sds) for t in _named_defs(f.type))
        elif isinstance(d, m.Action):
            for sec, sds in ((d.goal, ds), (d.result, flipped), (d.feedback, flipped)):
                for f in sec.fields if sec else []:
                    yield from ((t, sds) for t in _named_defs(f.type))

    def directions(self, d: m.Definition | None) -> set[str]:
        """Directions ``d`` flows in (both when nothing reaches it)."""
        if d is None:
            return set(BOTH)
        found = self.dirs.get(id(d))
        return set(found) if found else set(BOTH)

    def usage(self, d: m.Definition | None) -> set[str]:
        """Usage keys of the endpoints that reach ``d`` (``type:Name`` when none do)."""
        if d is None:
            return set()
        found = self.keys.get(id(d))
        return set(found) if found else {f"type:{self.qualname(d)}"}


class WireSide(Side):
    """A side whose type keys name definitions by identity, to compare types across components."""

    def __init__(self, base: Side) -> None:  # shares the base side's state, computes nothing
        self.__dict__.update(base.__dict__)

    def _named_key(self, t: m.NamedType) -> str:
        return self.identity(t.target) if t.target is not None else external_identity(t)


def package_of(iface: m.Interface, root: bool) -> str:
    """The package a file's definitions belong to: its ``ros2`` namespace, else for an included
    file its stem (the prefix its types are written with), for the component's own file none."""
    return iface.namespace("ros2") or ("" if root else Path(iface.path).stem)


def external_identity(t: m.NamedType) -> str:
    """``pkg/Name`` of a type from an external package (``geometry_msgs.Pose``)."""
    pkg, _, local = t.name.rpartition(".")
    return f"{t.external or pkg}/{local}" if (t.external or pkg) else local


def _named_defs(t: m.TypeRef) -> Iterator[m.Definition]:
    for n in named_types(t):
        if n.target is not None:
            yield n.target

