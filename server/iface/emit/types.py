"""The one table of how each language type is written by each target.

Every emitter (ROS 2, PX4, IDL, JSON Schema) and the editor's hover read this
module, so a type means the same thing everywhere. ``None`` in a column means
"this target has no such type": emitters report an error naming the construct
instead of dropping it.

Base types are keyed by their canonical model name (``BaseType.name``);
containers by a kind: ``fixed``, ``bounded``, ``unbounded`` (arrays),
``bounded_string``, ``set``, ``map``. Container cells are format strings over
``{T}`` (the element written for that target), ``{K}`` (a map key), ``{N}``
(the size or bound) and, for IDL fixed arrays, ``{name}`` (the typedef name).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..model.nodes import INT_RANGES


@dataclass(frozen=True, slots=True)
class TypeRow:
    """How one language type is written by each target, with a note for the docs."""

    language: str
    ros2: str | None
    px4: str | None
    idl: str | None
    json_schema: dict[str, Any] | None
    note: str = ""


def _int_schema(name: str) -> dict[str, Any]:
    lo, hi = INT_RANGES[name]
    return {"type": "integer", "minimum": lo, "maximum": hi}


#: Base types by canonical name, in the order of the docs.
BASE_TYPES: dict[str, TypeRow] = {row.language: row for row in (
    TypeRow("bool", "bool", "bool", "boolean", {"type": "boolean"}),
    TypeRow("i8", "int8", "int8", "int8", _int_schema("i8"), "Thrift `byte` is `i8`."),
    TypeRow("i16", "int16", "int16", "int16", _int_schema("i16")),
    TypeRow("i32", "int32", "int32", "int32", _int_schema("i32")),
    TypeRow("i64", "int64", "int64", "int64", _int_schema("i64")),
    TypeRow("u8", "uint8", "uint8", "uint8", _int_schema("u8")),
    TypeRow("u16", "uint16", "uint16", "uint16", _int_schema("u16")),
    TypeRow("u32", "uint32", "uint32", "uint32", _int_schema("u32")),
    TypeRow("u64", "uint64", "uint64", "uint64", _int_schema("u64")),
    TypeRow("float32", "float32", "float32", "float", {"type": "number"}, "Thrift/C `float`."),
    TypeRow("float64", "float64", "float64", "double", {"type": "number"}, "Thrift `double`."),
    TypeRow("char", "char", "char", "uint8", _int_schema("char"),
            "8-bit unsigned; rosidl writes ROS `char` as IDL `uint8`."),
    TypeRow("wchar", "wchar", None, "wchar", _int_schema("wchar"),
            "16-bit character (a UTF-16 code unit); ROS 2 has it in .idl only: the ros2 target writes such an "
            "interface as an .idl file."),
    TypeRow("octet", "byte", "uint8", "octet", _int_schema("octet"), "ROS `byte`, an opaque 8-bit value."),
    TypeRow("string", "string", None, "string", {"type": "string"},
            "PX4 uORB has no unbounded strings: write `string<=N` (`char[N]`)."),
    TypeRow("wstring", "wstring", None, "wstring", {"type": "string"}, "UTF-16 in ROS 2 and IDL; uORB text is 8-bit."),
    TypeRow("binary", "uint8[]", None, "sequence<uint8>", {"type": "string", "contentEncoding": "base64"},
            "Thrift `binary`: an unbounded byte array."),
    TypeRow("uuid", "uint8[16]", "uint8[16]", "uint8[16]", {"type": "string", "format": "uuid"},
            "Thrift `uuid`: 16 bytes (IDL through a typedef, as for any fixed array)."),
)}

#: Containers and bounded strings, by kind.
CONTAINERS: dict[str, TypeRow] = {row.language: row for row in (
    TypeRow("fixed", "{T}[{N}]", "{T}[{N}]", "typedef {T} {name}[{N}];",
            {"type": "array", "items": "{T}", "minItems": "{N}", "maxItems": "{N}"},
            "`T[N]`: exactly N elements."),
    TypeRow("bounded", "{T}[<={N}]", None, "sequence<{T}, {N}>",
            {"type": "array", "items": "{T}", "maxItems": "{N}"},
            "`T[<=N]`: at most N elements; PX4 has fixed arrays only."),
    TypeRow("unbounded", "{T}[]", None, "sequence<{T}>", {"type": "array", "items": "{T}"},
            "`T[]` and Thrift `list<T>`."),
    TypeRow("bounded_string", "{T}<={N}", "char[{N}]", "{T}<{N}>", {"type": "string", "maxLength": "{N}"},
            "`string<=N` and `wstring<=N`; PX4 writes text as a char array (`string<=N` only), as its "
            "`log_message` does."),
    TypeRow("set", None, None, None, {"type": "array", "items": "{T}", "uniqueItems": True},
            "Thrift `set<T>`: no ROS 2/PX4/IDL equivalent (write `T[]` to accept duplicates)."),
    TypeRow("map", None, None, None, {"type": "object", "additionalProperties": "{T}"},
            "Thrift `map<K,V>`: no ROS 2/PX4/IDL equivalent; JSON only with string keys."),
)}

#: Column titles of the table, by TypeRow attribute.
COLUMNS: dict[str, str] = {"language": "iface", "ros2": "ROS 2 (.msg, .idl)", "px4": "PX4 (uORB)",
                           "idl": "OMG IDL", "json_schema": "JSON Schema"}

#: How the language spells each canonical base type (the aliases shown in the docs).
SPELLINGS: dict[str, str] = {
    "bool": "bool", "i8": "i8, int8, byte", "i16": "i16, int16", "i32": "i32, int32", "i64": "i64, int64",
    "u8": "u8, uint8", "u16": "u16, uint16", "u32": "u32, uint32", "u64": "u64, uint64",
    "float32": "float, float32", "float64": "double, float64", "char": "char", "wchar": "wchar",
    "octet": "octet", "string": "string", "wstring": "wstring", "binary": "binary", "uuid": "uuid",
}

_CONTAINER_SPELLING: dict[str, str] = {
    "fixed": "T[N]", "bounded": "T[<=N]", "unbounded": "T[], list<T>", "bounded_string": "string<=N",
    "set": "set<T>", "map": "map<K,V>",
}


def base(name: str) -> TypeRow:
    """The row of a canonical base type name (KeyError for anything else)."""
    return BASE_TYPES[name]


def ros2_base(name: str) -> str | None:
    """The ROS 2 spelling of a base type, None if ROS 2 has none."""
    return BASE_TYPES[name].ros2


def px4_base(name: str) -> str | None:
    """The PX4 uORB spelling of a base type, None if uORB has none."""
    return BASE_TYPES[name].px4


#: Targets whose bounded strings are 8-bit text only (``wstring<=N`` has no equivalent).
_NARROW_TEXT = frozenset({"px4"})


def container(kind: str, target: str, element: str, size: int | None = None, *, key: str = "",
              name: str = "") -> str | None:
    """A container type written for ``target`` (``ros2``, ``px4``, ``idl``), None if unsupported.

    For ``bounded_string`` the element is the string kind, ``string`` or ``wstring``.
    """
    pattern = getattr(CONTAINERS[kind], target)
    if pattern is None or (kind == "bounded_string" and element == "wstring" and target in _NARROW_TEXT):
        return None
    return pattern.format(T=element, N="" if size is None else size, K=key, name=name)


def _schema_cell(schema: dict[str, Any] | None) -> str:
    if schema is None:
        return "—"
    parts = []
    for k, v in schema.items():
        parts.append(f'"{k}": {v}' if not isinstance(v, str) or v.startswith("{")
                     else f'"{k}": "{v}"')
    return "`{" + ", ".join(parts).replace("True", "true") + "}`"


def _cell(text: str | None) -> str:
    return "—" if text is None else f"`{text}`"


def markdown_table() -> str:
    """The whole table in Markdown (docs and hover read it)."""
    lines = ["| " + " | ".join(COLUMNS.values()) + " | Notes |",
             "|" + "---|" * (len(COLUMNS) + 1)]
    for key, row in BASE_TYPES.items():
        lines.append(f"| `{SPELLINGS[key]}` | {_cell(row.ros2)} | {_cell(row.px4)} | {_cell(row.idl)} | "
                     f"{_schema_cell(row.json_schema)} | {row.note} |")
    for key, row in CONTAINERS.items():
        lines.append(f"| `{_CONTAINER_SPELLING[key]}` | {_cell(row.ros2)} | {_cell(row.px4)} | "
                     f"{_cell(row.idl)} | {_schema_cell(row.json_schema)} | {row.note} |")
    return "\n".join(lines) + "\n"


def hover_markdown(name: str) -> str | None:
    """A short Markdown block for the editor's hover over a base type name or alias."""
    from ..model.nodes import BASE_ALIASES

    canonical = BASE_ALIASES.get(name)
    if canonical is None:
        return None
    row = BASE_TYPES[canonical]
    cells = [f"{COLUMNS[c]}: {_cell(getattr(row, c))}" for c in ("ros2", "px4", "idl")]
    cells.append(f"JSON Schema: {_schema_cell(row.json_schema)}")
    text = f"**{name}** (`{canonical}`)\n\n" + "  \n".join(cells)
    return text + (f"\n\n{row.note}" if row.note else "")
