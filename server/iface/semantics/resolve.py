"""Symbols and references: definitions by name, includes, externals, named types."""

from __future__ import annotations

from collections.abc import Iterator

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, make
from ..model.walk import named_types, type_roots
from .suggest import Suggester

BUILTIN_NAMES = tuple(sorted(m.BASE_ALIASES))


def build_symbols(iface: m.Interface) -> Iterator[Diagnostic]:
    """Fill ``iface.symbols``; a second definition of a name is an error."""
    symbols: dict[str, m.Definition] = {}
    src = iface.source
    for d in iface.definitions:
        first = symbols.get(d.name)
        if first is None:
            symbols[d.name] = d
            continue
        yield make("duplicate-definition", f"'{d.name}' is already defined", src, d.name_span,
                   related=[Related(src, first.name_span, f"first definition of '{d.name}'")])
    iface.symbols = symbols


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


def did_you_mean(iface: m.Interface, name: str) -> list[str]:
    """Close names for an unknown type name (one question; ``resolve_references`` shares one Suggester)."""
    return suggester(iface).suggest(name)


def resolve_references(iface: m.Interface) -> Iterator[Diagnostic]:
    """Resolve every named type of the file; report those that name nothing."""
    src = iface.source
    close_names: Suggester | None = None  # made at the first unknown name
    for item in iface.items:
        for root in type_roots(item):
            for t in named_types(root):
                if resolve_named(iface, t):
                    continue
                prefix = t.qualifier
                if prefix and prefix not in iface.included:
                    hint = (f"; '{prefix}' is neither an included file nor a declared package"
                            f" (add `include \"{prefix}.iface\"` or `external {prefix}`)")
                    yield make("unknown-type", f"unknown type '{t.name}'{hint}", src, t.span,
                               suggestions=[], name=t.name)
                    continue
                if close_names is None:
                    close_names = suggester(iface)
                close = close_names.suggest(t.name)
                hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
                yield make("unknown-type", f"unknown type '{t.name}'{hint}", src, t.span,
                           suggestions=close, name=t.name)


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
            for v in e.values:
                if v.name == value_name:
                    return v
    return None
