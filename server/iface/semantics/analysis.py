"""Resolution and checks of one file, kept per item so that an edit redoes only what it changed.

Every definition and wiring statement is a ``Unit``: the names it looks up,
what resolving them found, and its findings (those of the item alone, and
those that read what its names resolve to). An ``Analysis`` keeps the units of
one document between its versions; an unchanged chunk keeps its model objects,
so a unit whose item is the same object, and none of whose names now resolve
to another definition, is kept as it is. The file-wide results are made from
small summaries kept in dicts (definitions by name, the struct graph's edges),
so an edit updates them in time that follows the edit.

A compile without an ``Analysis`` (``check``) runs the same steps with nothing
to keep. Where an edit could change what the summaries cannot see (a typedef,
an ``extends``, a cycle, the includes) every unit is made again: the same steps
as a first compile.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass
from operator import attrgetter

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, make
from ..model.source import Source
from ..model.walk import all_consts, bodies
from ..syntax.edits import Change
from .resolve import break_cycles, resolve_item, settle_typedefs, unknown_types
from .sets import SetFindings, derive
from . import systems  # noqa: F401  (registers the system file's checks)
from .suggest import Suggester
from .validate import (
    RULES,
    definition_findings,
    is_robot,
    local_findings,
    recursion,
    recursive_types,
    rehome,
    struct_members,
    wiring_findings,
)


#: What a unit is made for: a definition or a wiring statement (model nodes hash by identity: the keys of
#: ``Analysis.units``).
Part = m.Definition | m.Wiring
#: The names a unit uses, as kept (see ``_pack``).
Uses = str | tuple[str, ...]


def _pack(uses: set[str]) -> Uses:
    """The names an item uses, as kept: one name itself, else a tuple (empty: the one empty tuple)."""
    return next(iter(uses)) if len(uses) == 1 else tuple(uses)


def _names(uses: Uses) -> tuple[str, ...]:
    """The names of ``Unit.uses``."""
    return (uses,) if isinstance(uses, str) else uses


@dataclass(slots=True, eq=False)
class Unit:
    """One definition or wiring statement and what it found."""

    item: Part
    #: Every name the item looks up (types and named values, with their parts): one name itself (most items
    #: look up one), else a tuple (see ``_names``).
    uses: Uses
    #: Its named types that name nothing, in order.
    unknown: Sequence[m.NamedType]
    #: ``unknown-type`` findings of ``unknown``.
    unresolved: Sequence[Diagnostic]
    #: Findings of the item alone (local rules; wiring rules).
    local: Sequence[Diagnostic]
    #: Findings that read what its names resolve to.
    checked: Sequence[Diagnostic]
    #: For a struct: the structs its fields hold (a local one by name), the edges of the recursion check.
    edges: tuple[object, ...] = ()


@dataclass(slots=True, eq=False)
class Quiet:
    """What is kept of a quiet struct with edges: the names it uses, its edges."""

    uses: Uses
    edges: tuple[object, ...]


#: What ``Analysis.units`` keeps of an item: its ``Unit``, or when the unit is quiet (no finding, nothing
#: unknown: most are) only the names it uses (with a struct's edges, a ``Quiet``), made into a unit again when
#: read (``_unit``).
Kept = Unit | Quiet | Uses


def _unit(x: Part, kept: Kept) -> Unit:
    """The unit of ``x`` from what is kept of it."""
    if isinstance(kept, Unit):
        return kept
    if isinstance(kept, Quiet):
        return Unit(x, kept.uses, (), (), (), (), kept.edges)
    return Unit(x, kept, (), (), (), (), ())


class Analysis:
    """What one document's last compile found, per item (the memo of ``analyse``)."""

    def __init__(self) -> None:
        self.context: object = None
        self.units: dict[Part, Kept] = {}
        #: The items that use a name (see ``_use``).
        self.users: Users = {}
        #: The names defined more than once: their definitions, in the order of the text (a name defined once
        #: is found in ``symbols``: see ``_defined``).
        self.twice: dict[str, tuple[m.Definition, ...]] = {}
        self.duplicates: dict[str, list[Diagnostic]] = {}
        #: The symbol table of the last interface (its ``symbols``, the same dict).
        self.symbols: dict[str, m.Definition] = {}
        #: Units with a finding, by their item.
        self.noisy: dict[Part, Unit] = {}
        #: Units with a named type that names nothing, by their item.
        self.unknown: dict[Part, Unit] = {}
        #: The source the kept findings are attached to.
        self.source: Source | None = None
        self.cycles: list[Diagnostic] = []
        self.cycle_members: set[int] = set()
        self.recursion: list[Diagnostic] = []
        self.involved: set[int] = set()
        self.sets = SetFindings()
        #: The interface of the last compile (its lists are spliced for the next version).
        self.iface: m.Interface | None = None

    def reset(self) -> None:
        """Forget everything (the next compile is a first one); the last interface stays."""
        last = self.iface
        self.__init__()  # type: ignore[misc]
        self.iface = last


#: The items that use a name: the item itself, a tuple of a few, or a set of more (most names have one or two
#: users, and a set is some 200 bytes).
Users = dict[str, Part | tuple[Part, ...] | set[Part]]
_FEW = 8


def _use(users: Users, name: str, x: Part) -> None:
    """Record that the item ``x`` uses ``name``."""
    had = users.get(name)
    if had is None:
        users[name] = x
    elif isinstance(had, tuple):
        if x not in had:
            users[name] = (*had, x) if len(had) < _FEW else {*had, x}
    elif isinstance(had, set):
        had.add(x)
    elif had is not x:
        users[name] = (had, x)


def _unuse(users: Users, name: str, x: Part) -> None:
    """Forget that the item ``x`` uses ``name``."""
    had = users.get(name)
    if had is x:
        del users[name]
    elif isinstance(had, tuple):
        if x in had:
            rest = tuple(y for y in had if y is not x)
            users[name] = rest[0] if len(rest) == 1 else rest
    elif isinstance(had, set):
        had.discard(x)


def _users(users: Users, name: str) -> Collection[Part]:
    """The items that use ``name``."""
    had = users.get(name)
    if had is None:
        return ()
    return had if isinstance(had, (tuple, set)) else (had,)


def _defined(an: Analysis, name: str) -> tuple[m.Definition, ...]:
    """The definitions of ``name`` the last compile found, in the order of the text."""
    same = an.twice.get(name)
    if same is not None:
        return same
    d = an.symbols.get(name)
    return () if d is None else (d,)


def _value_names(v: m.Value | None, out: set[str]) -> None:
    """The names a value refers to, with the parts ``constant_value`` looks up."""
    stack = [v] if v is not None else []
    while stack:
        x = stack.pop()
        if x.kind == "name":
            name = str(x.value)
            owner, _, local = name.rpartition(".")
            out.update((name, local, owner, owner.rpartition(".")[2]))
        elif x.kind == "list":
            stack.extend(x.value)
        elif x.kind == "map":
            for key, val in x.value:
                stack.append(key)
                stack.append(val)


def _named_values(d: m.Definition, out: set[str]) -> None:
    for c in all_consts(d):
        _value_names(c.value, out)
    for _, fields, _ in bodies(d):
        for f in fields:
            if f.default is not None:
                _value_names(f.default, out)


def _edges(iface: m.Interface, s: m.Struct) -> tuple[object, ...]:
    """The structs the fields of ``s`` hold: a local one by its name, an included one by identity."""
    symbols = iface.symbols
    return tuple(c.name if symbols.get(c.name) is c else id(c) for _, c in struct_members(s))


_START = attrgetter("span.start")
_UNITS = (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const, m.Wiring)


def analyse(iface: m.Interface, an: Analysis | None = None, change: Change | None = None) -> list[Diagnostic]:
    """Resolve ``iface`` and check it; ``an`` keeps what an unchanged item found for the next version.

    The findings come in the order of a whole-file pass (duplicates, unknown types, cycles, sets, local
    checks, checks of resolved definitions, file rules, recursion): sorting by place keeps that order
    between findings at one place.
    """
    src = iface.source
    robot = is_robot(iface)
    context = (robot, src.path, tuple((p, id(i)) for p, i in iface.included.items()),
               tuple(e.name for e in iface.externals))
    keep = an is not None
    if an is None:
        an = Analysis()
    elif an.context != context:
        an.reset()
    an.context = context
    last, an.iface = an.iface, iface
    defs = iface.definitions
    units = an.units
    items: list[Part]
    told = change is not None and bool(units)
    if not units:  # a first compile
        removed = []
        added = [*defs, *iface.wirings]
    elif told:  # the edit says what it changed
        assert change is not None
        removed = [_unit(x, units.pop(x)) for x in change[1] if isinstance(x, _UNITS) and x in units]
        added = [x for x in change[2] if isinstance(x, _UNITS)]
    else:
        items = [*defs, *iface.wirings]
        present = dict.fromkeys(items)
        removed = [_unit(x, units.pop(x)) for x in units.keys() - present.keys()]
        added = list(present.keys() - units.keys())
        if last is not None and _reordered(last, iface, units):
            removed, added = [], [*defs, *iface.wirings]
            an.reset()  # an item moved past another (a chunk found by its text): every unit again
            an.context = context
            an.iface = iface
            units = an.units
    if (_structural(an, removed, added)):
        an.reset()
        an.context = context
        units = an.units
        removed = []
        added = [*defs, *iface.wirings]
    first = not units
    added.sort(key=_START)
    if an.source is not None and an.source is not src:
        _rehome_all(an, src)
    an.source = src
    # ---- definitions by name: duplicates and the symbol table -------------------------------------
    #: The names whose definitions the edit changed: their definitions now.
    changed: dict[str, tuple[m.Definition, ...]] = {}
    for u in removed:
        for n in _names(u.uses):
            _unuse(an.users, n, u.item)
        an.noisy.pop(u.item, None)
        an.unknown.pop(u.item, None)
        if not isinstance(u.item, m.Wiring):
            n = u.item.name
            changed[n] = tuple(d for d in (changed[n] if n in changed else _defined(an, n)) if d is not u.item)
    for x in added:
        if not isinstance(x, m.Wiring):
            n = x.name
            changed[n] = (*(changed[n] if n in changed else _defined(an, n)), x)
    for n, same in an.twice.items():  # two chunks of one text may swap their model objects between versions
        if n not in changed and same != tuple(sorted(same, key=_START)):
            changed[n] = same
    for n, same in changed.items():
        if len(same) < 2:
            an.twice.pop(n, None)
            an.duplicates.pop(n, None)
            continue
        same = changed[n] = an.twice[n] = tuple(sorted(same, key=_START))
        head = same[0]
        an.duplicates[n] = [make("duplicate-definition", f"'{d.name}' is already defined", src, d.name_span,
                                 related=[Related(src, head.name_span, f"first definition of '{d.name}'")])
                            for d in same[1:]]
    was = {n: an.symbols.get(n) for n in changed}
    if first or (changed and not (told and _in_place(removed, added, changed))):
        symbols: dict[str, m.Definition] = {}
        for d in defs:
            if d.name not in symbols:
                symbols[d.name] = d
        an.symbols = symbols
    elif changed:  # definitions replaced by ones of the same names, in the same order: the table keeps its order
        an.symbols = dict(an.symbols)  # a copy: the last interface keeps its own table
        for n in changed:
            an.symbols[n] = changed[n][0]
    iface.symbols = an.symbols  # shared until the table changes (it is never changed in place)
    rebound = [n for n in changed if an.symbols.get(n) is not was[n]]
    names_changed = any(isinstance(an.symbols.get(n), m.Const) != isinstance(was[n], m.Const)
                        or (n in an.symbols) != (was[n] is not None) for n in rebound)
    # ---- resolve what is new, and what uses a name that now means another definition ----------------
    redo = dict.fromkeys(added)
    for n in rebound:
        for x in _users(an.users, n):
            redo.setdefault(x)
    todo = added if first else sorted(redo, key=_START)
    fresh: list[Unit] = []
    for x in todo:
        uses: set[str] = set()
        unknown = resolve_item(iface, x, uses if keep else None)
        old = None if (kept := units.get(x)) is None else _unit(x, kept)
        if isinstance(x, m.Wiring):
            local = old.local if old is not None else (wiring_findings(src, x) if robot else [])
        else:
            if keep:
                _named_values(x, uses)
            local = old.local if old is not None else local_findings(src, x, robot)
        unit = Unit(x, _pack(uses), unknown or (), (), local or (), (), old.edges if old is not None else ())
        if keep:
            if old is not None:
                for n in _names(old.uses):
                    if n not in uses:
                        _unuse(an.users, n, x)
            for n in uses:
                _use(an.users, n, x)
        units[x] = unit
        if unknown:
            an.unknown[x] = unit
        else:
            an.unknown.pop(x, None)
        fresh.append(unit)
    if first:
        an.cycle_members = set()
        an.cycles = list(break_cycles(iface, an.cycle_members))
        settle_typedefs(iface)
    # ---- unknown names: all of them again, in order, when the names in reach changed ------------------
    if names_changed or any(u.unknown for u in fresh):
        pending = sorted(an.unknown.values(), key=lambda u: u.item.span.start)
        close: list[Suggester] = []
        for u in pending:
            u.unresolved = list(unknown_types(iface, u.unknown, close)) or ()
    # ---- the seven sets: findings now, the sets themselves when first read ---------------------------
    if first and not removed:
        an.sets.update(iface, [], added, [])
    else:
        new = set(added)
        an.sets.update(iface, [u.item for u in removed], [u.item for u in fresh if u.item in new],
                       [u.item for u in fresh if u.item not in new and isinstance(u.item, m.Wiring)])
    iface.defer_sets(_fill_sets)
    # ---- checks of resolved definitions -----------------------------------------------------------
    for u in fresh:
        if not isinstance(u.item, m.Wiring):
            u.checked = definition_findings(iface, u.item) or ()
    # ---- recursion over the struct graph ----------------------------------------------------------
    if robot:
        _recursion(iface, an, removed, fresh, first, keep)
    else:
        an.recursion = []
    for u in fresh:
        if u.unresolved or u.local or u.checked:
            an.noisy[u.item] = u
        else:
            an.noisy.pop(u.item, None)
            if keep and not u.unknown:  # quiet: only the names it uses (and its edges) are kept
                units[u.item] = Quiet(u.uses, u.edges) if u.edges else u.uses
    # ---- the findings, in the order of a whole-file pass --------------------------------------------
    noisy = list(an.noisy.values())
    out: list[Diagnostic] = []
    for found in an.duplicates.values():
        out.extend(found)
    for u in noisy:
        out.extend(u.unresolved)
    out.extend(an.cycles)
    out.extend(an.sets.findings())
    for u in noisy:
        out.extend(u.local)
    for u in noisy:
        out.extend(u.checked)
    for fn, robot_only in RULES:
        if fn is not recursion and (robot or not robot_only):
            out.extend(fn(iface))
    out.extend(an.recursion)
    return out


def _rehome_all(an: Analysis, src: Source) -> None:
    """Attach every kept finding to the newest version of the file."""
    an.duplicates = {n: [rehome(d, src) for d in found] for n, found in an.duplicates.items()}
    an.cycles = [rehome(d, src) for d in an.cycles]
    an.recursion = [rehome(d, src) for d in an.recursion]
    an.sets.rehome(lambda d: rehome(d, src))
    for u in an.noisy.values():
        u.unresolved = [rehome(d, src) for d in u.unresolved]
        u.local = [rehome(d, src) for d in u.local]
        u.checked = [rehome(d, src) for d in u.checked]


def _reordered(last: m.Interface, iface: m.Interface, kept: dict[Part, Kept]) -> bool:
    """True when the items kept from the ``last`` version are not in the order they had there."""
    for before, now in ((last.definitions, iface.definitions), (last.wirings, iface.wirings)):
        old = [x for x in before if x in kept]
        new = [x for x in now if x in kept]
        if len(old) != len(new) or any(a is not b for a, b in zip(old, new)):
            return True
    return False


def _in_place(removed: list[Unit], added: list[Part], changed: dict[str, tuple[m.Definition, ...]]) -> bool:
    """True when the edit replaced definitions by as many of the same names in the same order, none of them
    defined twice: the symbol table then has its keys in the same order."""
    gone = [u.item.name for u in removed if not isinstance(u.item, m.Wiring)]
    come = [x.name for x in added if not isinstance(x, m.Wiring)]
    return gone == come and all(len(same) == 1 for same in changed.values())


def _fill_sets(iface: m.Interface) -> None:
    """Make the seven sets of ``iface`` (their findings were made with the rest)."""
    for _ in derive(iface):
        pass


def _structural(an: Analysis, removed: list[Unit], added: list[Part]) -> bool:
    """True when an edit touches what the per-item summaries do not follow: typedefs (their chains),
    ``extends`` (its cycles), a definition on a cycle. Then every unit is made again."""
    if not an.units and not removed:
        return False
    for x in [*(u.item for u in removed), *added]:
        if isinstance(x, m.Typedef) or (isinstance(x, m.Service) and x.extends is not None):
            return True
        if id(x) in an.cycle_members:
            return True
    names = {x.name for x in [*(u.item for u in removed), *added] if not isinstance(x, m.Wiring)}
    for n in names:
        for x in _users(an.users, n):
            if x in an.units and (isinstance(x, m.Typedef) or (isinstance(x, m.Service) and x.extends is not None)
                                  or id(x) in an.cycle_members):
                return True
    return False


def _recursion(iface: m.Interface, an: Analysis, removed: list[Unit], fresh: list[Unit], first: bool,
               keep: bool) -> None:
    """The recursion check again, unless the edit left the struct graph as it was and it has no cycle."""
    same = not first and not an.involved
    if not keep:  # nothing to compare with later
        an.recursion = list(recursive_types(iface, [d for d in iface.definitions if isinstance(d, m.Struct)],
                                            an.involved))
        return
    gone: dict[str, tuple[object, ...]] = {}
    for u in removed:
        if isinstance(u.item, m.Struct) and u.edges:
            gone[u.item.name] = u.edges
    for u in fresh:
        if not isinstance(u.item, m.Struct):
            continue
        before = u.edges
        u.edges = _edges(iface, u.item)
        if not same:
            continue
        if before:  # the same struct, resolved again
            same = before == u.edges
        elif u.edges:  # a new struct: it must stand for one gone with the same edges
            same = gone.pop(u.item.name, None) == u.edges
    if same and not gone:
        return
    an.involved = set()
    structs = [d for d in iface.definitions if isinstance(d, m.Struct)]
    an.recursion = list(recursive_types(iface, structs, an.involved))
