"""Type names too long for the files rosidl generates from them.

A .msg file name that fits is not enough: ``colcon build`` runs rosidl's
generators, which name their files after the type in snake_case plus a suffix,
the longest being ``<type>__rosidl_typesupport_introspection_cpp.hpp``. A name
whose longest file would not fit in one file system name makes the build fail,
so it is refused here, at the definition.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from ...model.diagnostics import Diagnostic
from ..base import NAME_MAX
from .codes import diag
from .package import RosPackage

#: The longest file name suffix rosidl's default generators append to a type's snake_case name.
LONGEST_SUFFIX = "__rosidl_typesupport_introspection_cpp.hpp"


def rosidl_snake(name: str) -> str:
    """A type name as rosidl writes it in file names (``convert_camel_case_to_lower_case_underscore``)."""
    value = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", name)
    value = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", value)
    return value.lower()


def check_rosidl_names(pkg: RosPackage) -> Iterator[Diagnostic]:
    """An error for each interface whose rosidl-generated file names would be too long."""
    for ri in pkg.interfaces:
        longest = rosidl_snake(ri.name) + LONGEST_SUFFIX
        size = len(longest.encode("utf-8"))
        if size > NAME_MAX:
            yield diag("ros2-name-too-long", f"{ri.kind}/{ri.name[:24]}…: rosidl names its generated files after "
                       f"the type, the longest '{rosidl_snake(ri.name)[:16]}…{LONGEST_SUFFIX}' with {size} bytes; "
                       f"file systems hold {NAME_MAX}, so the package would not build: shorten the name (its "
                       f"snake_case form may have {NAME_MAX - len(LONGEST_SUFFIX)} characters)", ri.source, ri.span)
