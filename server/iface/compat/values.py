"""Canonical values and the widening relation between types."""

from __future__ import annotations

from typing import Any

from ..model import nodes as m

_SIGNED = ("i8", "i16", "i32", "i64")
_UNSIGNED = ("u8", "u16", "u32", "u64")
#: exactly representable integer widths in float64 / float32 mantissas
_FLOAT_EXACT = {"float32": 24, "float64": 53}
_BITS = {"i8": 8, "i16": 16, "i32": 32, "i64": 64, "u8": 8, "u16": 16, "u32": 32, "u64": 64,
         "char": 8, "wchar": 16, "octet": 8}


def value_key(v: m.Value | None) -> Any:
    """A comparable, JSON-able form of a constant value (spelling ignored: ``0x10`` == ``16``)."""
    if v is None:
        return None
    if v.kind == "list":
        return ["list", [value_key(x) for x in v.value]]
    if v.kind == "map":
        return ["map", [[value_key(k), value_key(x)] for k, x in v.value]]
    if v.kind == "double":
        return ["double", repr(float(v.value))]
    return [v.kind, v.value]


def value_text(v: m.Value | None) -> str:
    """A value as written."""
    if v is None:
        return "none"
    return v.text or str(v.value)


def widens(old: str, new: str) -> bool:
    """True when every value of base type ``old`` is a value of base type ``new`` (both canonical)."""
    if old == new:
        return True
    if old in _BITS and new in _BITS:
        ob, nb = _BITS[old], _BITS[new]
        old_signed, new_signed = old in _SIGNED, new in _SIGNED
        if old_signed == new_signed:
            return nb >= ob
        return new_signed and not old_signed and nb > ob
    if old in _BITS and new in _FLOAT_EXACT:
        return _BITS[old] - (1 if old in _SIGNED else 0) <= _FLOAT_EXACT[new]
    return old == "float32" and new == "float64"


def widens_type(old: m.TypeRef, new: m.TypeRef) -> bool:
    """Widening of base types and string bounds (used where NEW receives: parameters, state)."""
    if not (isinstance(old, m.BaseType) and isinstance(new, m.BaseType)):
        return False
    if old.name in m.STRING_TYPES and new.name == old.name:
        return new.bound is None or (old.bound is not None and new.bound >= old.bound)
    if old.bound is not None or new.bound is not None:
        return False
    return widens(old.name, new.name)
