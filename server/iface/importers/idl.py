"""ROS 2 ``.idl`` files, as rosbags' IDL parser reads them, → parsed interface files.

rosbags gives each struct's fields and constants (not defaults or comments);
every struct becomes a message of the package being imported.
"""

from __future__ import annotations

from typing import Any

from .rosidl import PRIMITIVE_TYPES, ArrayKind, Element, Part, RosFile, RosType

#: rosbags' base type names → ROS .msg primitive names.
_BASE = {name: name for name in PRIMITIVE_TYPES} | {"octet": "byte"}


def _type(desc: Any, module: str) -> RosType:
    node, rest = desc
    kind = getattr(node, "name", str(node))
    if kind in ("ARRAY", "SEQUENCE"):
        inner, count = rest
        element = _type(inner, module)
        if kind == "ARRAY":
            return RosType(element.name, element.package, element.primitive, element.string_bound, "fixed", count)
        array: ArrayKind = "bounded" if count else "unbounded"
        return RosType(element.name, element.package, element.primitive, element.string_bound, array,
                       count or None)
    if kind == "NAME":
        package, _, name = str(rest).partition("/")
        name = name.rpartition("/")[2]
        return RosType(name, None if package == module else package, primitive=False)
    base, bound = rest
    if base not in _BASE:
        raise ValueError(f"the IDL type '{base}' has no iface equivalent")
    return RosType(_BASE[base], string_bound=bound or None)


def ros_files_from_idl(types: dict[str, Any], package: str) -> tuple[list[RosFile], list[str]]:
    """One message per struct; problems name the struct and the field."""
    files: list[RosFile] = []
    problems: list[str] = []
    for full, (consts, fields) in sorted(types.items()):
        module = full.partition("/")[0]
        name = full.rpartition("/")[2]
        part = Part(name, 0)
        ok = True
        for cname, ctype, value in consts:
            if ctype not in _BASE:
                problems.append(f"{name}.{cname}: the IDL type '{ctype}' has no iface equivalent")
                ok = False
                continue
            text = ("true" if value else "false") if isinstance(value, bool) else str(value)
            part.elements.append(Element("constant", RosType(_BASE[ctype]), cname, 0, value, [text]))
        for fname, desc in fields:
            try:
                part.elements.append(Element("field", _type(desc, module), fname, 0))
            except ValueError as e:
                problems.append(f"{name}.{fname}: {e}")
                ok = False
        if ok:
            rf = RosFile("msg", package, name)
            rf.parts.append(part)
            files.append(rf)
    return files, problems
