"""The state document: its types, the widening rule, values to and from JSON, save and restore.

The same for every component iface generates (docs/runtime.md); nothing here imports ROS, so the
rules can be read and tested on their own. The node (``iface_runtime_py.runtime``) applies them.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from .protocol import PROTOCOL_VERSION, STATE_FORMAT

_FORMAT = re.compile(r"^iface-state/([0-9]+)$")

_BITS = {"byte": 8, "char": 8, "uint8": 8, "int8": 8, "uint16": 16, "int16": 16, "uint32": 32, "int32": 32,
         "uint64": 64, "int64": 64}
_SIGNED = frozenset({"int8", "int16", "int32", "int64"})
_FLOAT_EXACT = {"float32": 24, "float64": 53}
_FLOAT32_MAX = 3.4028234663852886e38
_STRINGS = frozenset({"string", "wstring"})
_TYPE = re.compile(r"^(?P<base>[A-Za-z][A-Za-z0-9_]*(?:/[A-Za-z][A-Za-z0-9_]*)?)(?:<=(?P<bound>[0-9]+))?"
                   r"(?:\[(?P<bounded><=)?(?P<size>[0-9]*)\])?$")


class StateError(ValueError):
    """A state document this component cannot take; the message says why."""


# ---- types ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Type:
    """A type of the state document: ``.msg`` spelling, message types as ``package/Name``."""

    base: str
    bound: int | None = None
    array: str | None = None
    size: int | None = None

    @classmethod
    def parse(cls, text: str) -> Type:
        found = _TYPE.match(text.strip())
        if found is None:
            raise StateError(f"'{text}' is not a type")
        size = found.group("size")
        array = None
        if found.group(0).endswith("]"):
            array = "bounded" if found.group("bounded") else ("fixed" if size else "unbounded")
        return cls(found.group("base"), int(found.group("bound")) if found.group("bound") else None, array,
                   int(size) if size else None)

    @property
    def element(self) -> Type:
        return Type(self.base, self.bound)

    @property
    def is_message(self) -> bool:
        return "/" in self.base

    def __str__(self) -> str:
        core = self.base + (f"<={self.bound}" if self.bound is not None else "")
        if self.array == "fixed":
            return f"{core}[{self.size}]"
        if self.array == "bounded":
            return f"{core}[<={self.size}]"
        if self.array == "unbounded":
            return f"{core}[]"
        return core


def _int_range(base: str) -> tuple[int, int]:
    bits = _BITS[base]
    if base in _SIGNED:
        return -(2 ** (bits - 1)), 2 ** (bits - 1) - 1
    return 0, 2 ** bits - 1


def widens(old: str, new: str) -> bool:
    """True when every value of primitive ``old`` is a value of primitive ``new``."""
    if old == new:
        return True
    if old in _BITS and new in _BITS:
        old_bits, new_bits = _BITS[old], _BITS[new]
        if (old in _SIGNED) == (new in _SIGNED):
            return new_bits >= old_bits
        return new in _SIGNED and new_bits > old_bits
    if old in _BITS and new in _FLOAT_EXACT:
        return _BITS[old] - (1 if old in _SIGNED else 0) <= _FLOAT_EXACT[new]
    return old == "float32" and new == "float64"


def assignable(old: Type, new: Type) -> bool:
    """True when a value saved as ``old`` can be held by ``new`` (the same type, or a wider primitive)."""
    if old == new:
        return True
    if old.array is not None or new.array is not None or old.is_message or new.is_message:
        return False
    if old.base in _STRINGS and new.base == old.base:
        return new.bound is None or (old.bound is not None and new.bound >= old.bound)
    if old.bound is not None or new.bound is not None:
        return False
    return widens(old.base, new.base)


# ---- values -----------------------------------------------------------------------------------------

#: ``describe(package/Name)`` → {field: type text}; ``make(package/Name)`` → a new message.
Describe = Callable[[str], dict[str, str]]
Make = Callable[[str], Any]


def _plain(value: Any) -> Any:
    """Sequences as the message classes hold them (numpy arrays, array.array, bytes) as a list."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, (list, tuple)):
        return list(value)
    try:
        return list(value)
    except TypeError:
        return value


def encode(value: Any, t: Type, describe: Describe) -> Any:
    """A value of type ``t`` as JSON data."""
    if t.array is not None:
        return [encode(v, t.element, describe) for v in _plain(value)]
    if t.is_message:
        return {name: encode(getattr(value, name), Type.parse(ft), describe) for name, ft in describe(t.base).items()}
    if t.base == "bool":
        return bool(value)
    if t.base in _BITS:
        if isinstance(value, (bytes, bytearray)):
            return value[0] if value else 0
        if isinstance(value, str):
            return ord(value) if value else 0
        return int(value)
    if t.base in _FLOAT_EXACT:
        number = float(value)
        if math.isnan(number):
            return "nan"
        if math.isinf(number):
            return "inf" if number > 0 else "-inf"
        return number
    return str(value)


def decode(data: Any, t: Type, describe: Describe, make: Make, where: str) -> Any:
    """JSON data as a value of type ``t``; StateError naming ``where`` when it does not fit."""
    if t.array is not None:
        if not isinstance(data, list):
            raise StateError(f"{where}: expected a list for {t}")
        if t.array == "fixed" and len(data) != t.size:
            raise StateError(f"{where}: {t} holds exactly {t.size} elements, not {len(data)}")
        if t.array == "bounded" and t.size is not None and len(data) > t.size:
            raise StateError(f"{where}: {t} holds at most {t.size} elements, not {len(data)}")
        items = [decode(v, t.element, describe, make, f"{where}[{i}]") for i, v in enumerate(data)]
        if t.base == "byte":
            return b"".join(items)
        return items
    if t.is_message:
        if not isinstance(data, dict):
            raise StateError(f"{where}: expected an object for {t.base}")
        fields = describe(t.base)
        unknown = sorted(set(data) - set(fields))
        if unknown:
            raise StateError(f"{where}: {t.base} has no field {unknown[0]}")
        msg = make(t.base)
        for name, ft in fields.items():
            if name in data:
                setattr(msg, name, decode(data[name], Type.parse(ft), describe, make, f"{where}.{name}"))
        return msg
    if t.base == "bool":
        if not isinstance(data, bool):
            raise StateError(f"{where}: expected true or false, not {data!r}")
        return data
    if t.base in _BITS:
        if not isinstance(data, int) or isinstance(data, bool):
            raise StateError(f"{where}: expected an integer for {t}, not {data!r}")
        low, high = _int_range(t.base)
        if not low <= data <= high:
            raise StateError(f"{where}: {data} does not fit {t} ({low}..{high})")
        if t.base == "byte":
            return bytes([data])
        return chr(data) if t.base == "char" else data
    if t.base in _FLOAT_EXACT:
        if isinstance(data, str) and data in ("nan", "inf", "-inf"):
            return float(data)
        if not isinstance(data, (int, float)) or isinstance(data, bool):
            raise StateError(f"{where}: expected a number for {t}, not {data!r}")
        number = float(data)
        if t.base == "float32" and abs(number) > _FLOAT32_MAX:
            raise StateError(f"{where}: {data} does not fit float32")
        return number
    if not isinstance(data, str):
        raise StateError(f"{where}: expected a string for {t}, not {data!r}")
    if t.bound is not None and len(data) > t.bound:
        raise StateError(f"{where}: {len(data)} characters do not fit {t}")
    return data


def _message_types(schema: dict[str, str], describe: Describe) -> dict[str, dict[str, str]]:
    """The fields of every message type the schema uses, nested ones included."""
    out: dict[str, dict[str, str]] = {}
    todo = [Type.parse(t).base for t in schema.values()]
    while todo:
        base = todo.pop()
        if "/" not in base or base in out:
            continue
        out[base] = dict(describe(base))
        todo.extend(Type.parse(t).base for t in out[base].values())
    return out


# ---- the state document ---------------------------------------------------------------------------


@dataclass
class Restored:
    """What a restore did: variables set from the document, variables that kept their value."""

    restored: list[str]
    kept: list[str]
    same_interface: bool
    message: str
    #: When each work timer of the saving node last ran (ns since the epoch), by timer name.
    schedule: dict[str, int] = field(default_factory=dict)


class StateCodec:
    """Saves a state object as a state document and restores one into it, refusing what does not fit."""

    def __init__(self, component: str, version: str, interface_hash: str, schema: dict[str, str],
                 describe: Describe, make: Make) -> None:
        self.component = component
        self.version = version
        self.interface_hash = interface_hash
        self.schema = dict(schema)
        self.describe = describe
        self.make = make

    def save(self, state: Any, schedule: dict[str, int] | None = None) -> str:
        """The state document of ``state`` (compact JSON, keys sorted); ``schedule``: when each work timer last ran."""
        values = {name: encode(getattr(state, name), Type.parse(t), self.describe) for name, t in self.schema.items()}
        doc = {"format": STATE_FORMAT, "protocol_version": PROTOCOL_VERSION, "component": self.component,
               "version": self.version, "interface_hash": self.interface_hash, "schema": self.schema,
               "types": _message_types(self.schema, self.describe), "values": values,
               "schedule": dict(schedule or {})}
        return json.dumps(doc, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)

    def save_value(self, state: Any, name: str) -> Any:
        """One variable of ``state`` as JSON data."""
        return encode(getattr(state, name), Type.parse(self.schema[name]), self.describe)

    def read(self, text: str) -> tuple[dict[str, Any], Restored]:
        """The decoded values of a document and what restoring it does; StateError when it is refused."""
        try:
            doc = json.loads(text)
        except ValueError as e:
            raise StateError(f"the state is not JSON: {e}") from None
        if not isinstance(doc, dict) or doc.get("format") != STATE_FORMAT:
            found = doc.get("format") if isinstance(doc, dict) else None
            newer = _FORMAT.match(found) if isinstance(found, str) else None
            if newer and int(newer.group(1)) > int(_FORMAT.match(STATE_FORMAT).group(1)):  # type: ignore[union-attr]
                raise StateError(f"the state document's format {found!r} (protocol "
                                 f"{doc.get('protocol_version', '?')}) is newer than this runtime's {STATE_FORMAT!r} "
                                 f"(protocol {PROTOCOL_VERSION}): update iface_runtime_py to restore it")
            raise StateError(f"the state document's format is {found!r}, not {STATE_FORMAT!r}")
        schema, values, types = doc.get("schema"), doc.get("values"), doc.get("types", {})
        if not isinstance(schema, dict) or not isinstance(values, dict) or not isinstance(types, dict):
            raise StateError("the state document has no schema, types or values object")
        origin = f"{doc.get('component', '?')} {doc.get('version', '')}".strip()
        problems = []
        for name in sorted(schema):
            theirs = Type.parse(str(schema[name]))
            if name not in self.schema:
                problems.append(f"state '{name}' of {origin} has no place in {self.component}: its value would "
                                "be lost")
                continue
            mine = Type.parse(self.schema[name])
            if not assignable(theirs, mine):
                problems.append(f"state '{name}' is {theirs} in {origin} but {mine} in {self.component}")
        mine_types = _message_types(self.schema, self.describe)
        for base, fields in sorted(types.items()):
            if base in mine_types and dict(fields) != mine_types[base]:
                problems.append(f"message {base} has other fields in {origin} than in {self.component}")
        if problems:
            raise StateError("; ".join(problems))
        decoded = {}
        for name in sorted(schema):
            if name not in values:
                raise StateError(f"the state document has no value for '{name}'")
            decoded[name] = decode(values[name], Type.parse(self.schema[name]), self.describe, self.make, name)
        same = doc.get("interface_hash") == self.interface_hash
        kept = sorted(set(self.schema) - set(schema))
        how = "the same interface" if same else f"interface {doc.get('interface_hash', '?')}"
        message = f"restored {len(decoded)} variable(s) saved by {origin} ({how})"
        if kept:
            message += f"; kept {', '.join(kept)}"
        schedule = doc.get("schedule") or {}
        if not isinstance(schedule, dict):
            schedule = {}
        timers = {str(k): int(v) for k, v in schedule.items() if isinstance(v, int) and not isinstance(v, bool)}
        return decoded, Restored(sorted(decoded), kept, same, message, timers)

    def restore(self, state: Any, text: str) -> Restored:
        """Put a document into ``state``: all of it, or nothing and StateError."""
        decoded, report = self.read(text)
        for name, value in decoded.items():
            setattr(state, name, value)
        return report
