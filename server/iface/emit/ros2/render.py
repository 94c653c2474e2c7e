"""Writing lowered values as ROS 2 .msg text and YAML, and refusing what cannot be written."""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterator
from typing import Any
from xml.sax.saxutils import escape as xml_escape

from ...model.diagnostics import Diagnostic
from ..text import line_comment, yaml_string
from .codes import diag
from .package import PyValue, RosPackage, RosType, Scalar

_YAML_SPECIAL_KEY = re.compile(r"^(y|yes|n|no|true|false|on|off|null|~|\.inf|\.nan|[-+]?[0-9].*)$", re.IGNORECASE)


def msg_scalar(value: Scalar) -> str:
    """A single value in .msg syntax (strings double-quoted, inner quotes escaped as rosidl reads them)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    return '"' + value.replace('"', '\\"') + '"'


def msg_value(value: PyValue) -> str:
    """A default in .msg syntax: a scalar or ``[a, b]``."""
    if isinstance(value, list):
        return "[" + ", ".join(msg_scalar(v) for v in value) + "]"
    return msg_scalar(value)


def msg_type(rt: RosType, package: str) -> str:
    """A field type in .msg syntax, seen from ``package``."""
    return rt.msg(package)


def _unprintable(text: str) -> str | None:
    for c in text:
        if c != " " and not c.isprintable():
            return f"U+{ord(c):04X}"
    return None


def msg_string_problem(text: str, *, field_default: bool, in_array: bool) -> tuple[str, str] | None:
    """(code, reason) when a string cannot be written on a .msg line, else None."""
    if "#" in text:
        return ("ros2-hash-in-string", "it contains '#', which ROS 2 parsers read as the start of a comment")
    bad = _unprintable(text)
    if bad is not None:
        return ("ros2-unwritable-string", f"it contains {bad} (a line break or control character); "
                ".msg values are one line")
    if field_default and "=" in text:
        return ("ros2-unwritable-string", "it contains '=', which makes rosidl read the line as a constant")
    if text.endswith("\\") or '\\"' in text:
        return ("ros2-unwritable-string", "a backslash before a quote or at the end is read differently "
                "by ROS 2 parsers")
    # elements are written quoted, so commas are safe; quotes and outer spaces are not
    if in_array and (any(q in text for q in "\"'\\") or text != text.strip()):
        return ("ros2-unwritable-string", "array elements cannot hold quotes, backslashes or "
                "leading/trailing spaces in .msg syntax")
    return None


def check_msg_values(pkg: RosPackage) -> Iterator[Diagnostic]:
    """Errors for string defaults and constants that .msg syntax cannot hold."""
    for ri in pkg.interfaces:
        for sec in ri.sections:
            for c in sec.consts:
                if isinstance(c.value, str):
                    problem = msg_string_problem(c.value, field_default=False, in_array=False)
                    if problem:
                        yield diag(problem[0], f"constant '{c.name}' of {ri.kind}/{ri.name} cannot be written: "
                                   f"{problem[1]}", c.source, c.span)
            for f in sec.fields:
                values = f.default if isinstance(f.default, list) else [f.default]
                for v in values:
                    if isinstance(v, str):
                        problem = msg_string_problem(v, field_default=True, in_array=isinstance(f.default, list))
                        if problem:
                            yield diag(problem[0], f"the default of '{f.name}' in {ri.kind}/{ri.name} cannot "
                                       f"be written: {problem[1]}", f.source, f.span)
                            break


# ---- YAML -------------------------------------------------------------------------


def yaml_key(key: str) -> str:
    """A mapping key, quoted when YAML would read it as something other than a string."""
    return f'"{key}"' if _YAML_SPECIAL_KEY.match(key) else key


def yaml_float(value: float) -> str:
    """A float that both YAML 1.1 (PyYAML) and 1.2 (yaml-cpp) read as a float."""
    if math.isnan(value):
        return ".nan"
    if math.isinf(value):
        return ".inf" if value > 0 else "-.inf"
    text = repr(value)
    if "e" in text and "." not in text:
        mantissa, _, exponent = text.partition("e")
        text = f"{mantissa}.0e{exponent}"
    if "e" in text and text.partition("e")[2][0] not in "+-":
        mantissa, _, exponent = text.partition("e")
        text = f"{mantissa}e+{exponent}"
    return text


def yaml_scalar(value: Scalar) -> str:
    """One YAML scalar."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return yaml_float(value)
    return yaml_string(value)


def yaml_value(value: PyValue) -> str:
    """A YAML scalar or flow sequence."""
    if isinstance(value, list):
        return "[" + ", ".join(yaml_scalar(v) for v in value) + "]"
    return yaml_scalar(value)


def xml(text: str) -> str:
    """Text for an XML element or attribute."""
    return xml_escape(text, {'"': "&quot;"})


FILTERS: dict[str, Callable[..., Any]] = {
    "comment": line_comment,
    "msg_value": msg_value,
    "msg_scalar": msg_scalar,
    "msg_type": msg_type,
    "yaml_key": yaml_key,
    "yaml_value": yaml_value,
    "xml": xml,
}
