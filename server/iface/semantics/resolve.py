"""Symbols and references: definitions by name, includes, externals, named types."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, make
from ..model.walk import named_types, type_roots
from .suggest import Suggester

BUILTIN_NAMES = tuple(sorted(m.BASE_ALIASES))


def _candidates(iface: m.Interface) -> list[str]:
    names = [n for n, d in iface.symbols.items() if not isinstance(d, m.Const)]
    for prefix, inc in iface.included.items():
        names.extend(f"{prefix}.{n}" for n, d in inc.symbols.items() if not isinstance(d, m.Const))
    return names


def resolve_named(iface: m.Interface, t: m.NamedType) -> bool:
    """Point ``t`` at its definition or external package; False when nothing fits."""
    t.target = None
    t.external = None
    name = t.name
    found = iface.symbols.get(name)
    if found is not None:
        t.target = found
        return True
    prefix, _, local = name.rpartition(".")
    if prefix:
        inc = iface.included.get(prefix)
        if inc is not None:
            t.target = inc.symbols.get(local)
            return t.target is not None
        for ext in iface.externals:
            if ext.name == prefix or ext.name == name:
                t.external = prefix
                return True
    return False


def suggester(iface: m.Interface) -> Suggester:
    """Did-you-mean over the type names in reach of ``iface`` and the builtin types."""
    return Suggester([*_candidates(iface), *BUILTIN_NAMES])


def resolve_references(iface: m.Interface) -> Iterator[Diagnostic]:
    """Resolve every named type of the file; report those that name nothing."""
    unknown: list[m.NamedType] = []
    for item in iface.items:
        unknown.extend(resolve_item(iface, item))
    yield from unknown_types(iface, unknown, [])


def resolve_item(iface: m.Interface, item: m.Item, uses: set[str] | None = None) -> list[m.NamedType]:
    """Resolve the named types of one item; returns those that name nothing. ``uses`` gets the names looked up."""
    unknown: list[m.NamedType] = []
    for root in type_roots(item):
        for t in named_types(root):
            if uses is not None:
                uses.add(t.name)
            if not resolve_named(iface, t):
                unknown.append(t)
    return unknown


def unknown_types(iface: m.Interface, unknown: Sequence[m.NamedType], close_names: list[Suggester]) -> Iterator[Diagnostic]:
    """The findings of named types that name nothing, in order; ``close_names`` holds the one Suggester of a
    compile once it is made (at the first name that needs it: made at most once, used in the file's order)."""
    src = iface.source
    for t in unknown:
        prefix = t.qualifier
        if prefix and prefix not in iface.included:
            hint = (f"; '{prefix}' is neither an included file nor a declared package"
                    f" (add `include \"{prefix}.iface\"` or `external {prefix}`)")
            yield make("unknown-type", f"unknown type '{t.name}'{hint}", src, t.span,
                       suggestions=[], name=t.name)
            continue
        if not close_names:
            close_names.append(suggester(iface))
        close = close_names[0].suggest(t.name)
        hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
        yield make("unknown-type", f"unknown type '{t.name}'{hint}", src, t.span,
                   suggestions=close, name=t.name)


def break_cycles(iface: m.Interface, members_out: set[int] | None = None) -> Iterator[Diagnostic]:
    """Typedefs that stand for themselves (``typedef B A``, ``typedef A B``; ``typedef list<A> A``) and services
    that extend themselves: each definition of a cycle gets an error naming it, and its references to the
    cycle are left unresolved, so that no walk of the model follows the cycle round."""
    src = iface.source
    local = {id(d) for d in iface.definitions}

    def aliased(d: m.Definition) -> Iterator[m.Definition]:
        for t in _cycle_refs(d):
            assert t.target is not None
            yield t.target

    cycles = find_cycles([d for d in iface.definitions if isinstance(d, (m.Typedef, m.Service))], aliased)
    for cycle in cycles:
        kind = "typedef" if isinstance(cycle[0], m.Typedef) else "extends"
        for i, d in enumerate(cycle):
            if id(d) not in local:
                continue
            names = " → ".join(x.name for x in [*cycle[i:], *cycle[:i], d])
            if kind == "typedef":
                message = (f"typedef '{d.name}' stands for itself: {names}; a typedef must end in a type "
                           "(wrap the recursion in a struct or message)")
            else:
                message = f"service '{d.name}' extends itself: {names}; the chain of extends must end"
            yield make(f"{kind}-cycle", message, src, d.name_span, cycle=[x.name for x in cycle])
    members = {id(d) for cycle in cycles for d in cycle}
    if members_out is not None:
        members_out.update(members)
    for cycle in cycles:
        for d in cycle:
            if id(d) in local:
                for t in _cycle_refs(d):
                    if id(t.target) in members:
                        t.target = None


def _cycle_refs(d: m.Definition) -> Iterator[m.NamedType]:
    """The references a typedef (through containers, not through structs) or an ``extends`` follows."""
    if isinstance(d, m.Typedef):
        for t in named_types(d.type):
            if isinstance(t.target, m.Typedef):
                yield t
    elif isinstance(d, m.Service) and d.extends is not None and isinstance(d.extends.target, m.Service):
        yield d.extends


def settle_typedefs(iface: m.Interface) -> None:
    """Set every typedef's ``final`` (what it stands for through other typedefs), each chain walked once."""
    local = [d for d in iface.definitions if isinstance(d, m.Typedef)]
    for d in local:
        d.final = None
    for d in local:
        chain: list[m.Typedef] = []
        t: m.TypeRef = d.type
        seen: set[int] = set()
        while (isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef) and t.target.final is None
               and id(t.target) not in seen and t.target is not d):
            seen.add(id(t.target))
            chain.append(t.target)
            t = t.target.type
        if isinstance(t, m.NamedType) and isinstance(t.target, m.Typedef) and t.target.final is not None:
            t = t.target.final
        for x in (d, *chain):
            x.final = t


def find_cycles(roots: list[m.Definition],
                edges: Callable[[m.Definition], Iterator[m.Definition]]) -> list[list[m.Definition]]:
    """The cycles of the graph ``edges`` spans from ``roots``, each once, in the order first met (iterative)."""
    state: dict[int, int] = {}  # id -> 1 on the path, 2 done
    cycles: list[list[m.Definition]] = []
    for root in roots:
        if id(root) in state:
            continue
        path: list[m.Definition] = [root]
        stack = [edges(root)]
        state[id(root)] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[id(path.pop())] = 2
                stack.pop()
                continue
            mark = state.get(id(nxt))
            if mark == 1:
                cycles.append(path[next(i for i, x in enumerate(path) if x is nxt):])
            elif mark is None:
                state[id(nxt)] = 1
                path.append(nxt)
                stack.append(edges(nxt))
    return cycles


def constant_value(iface: m.Interface, name: str) -> m.Const | m.EnumValue | None:
    """The constant or enum value a name in a value position refers to."""
    prefix, _, local = name.rpartition(".")
    scopes = [iface] if not prefix or prefix not in iface.included else [iface.included[prefix]]
    for scope in scopes:
        d = scope.symbols.get(name) or scope.symbols.get(local)
        if isinstance(d, m.Const):
            return d
    owner_name, _, value_name = name.rpartition(".")
    if owner_name:
        enum_prefix, _, enum_local = owner_name.rpartition(".")
        scope = iface.included.get(enum_prefix, iface) if enum_prefix else iface
        e = scope.symbols.get(enum_local or owner_name)
        if isinstance(e, m.Enum):
            return e.named(value_name)
    return None
