"""Interfaces ``.msg``/``.srv``/``.action`` syntax cannot express, written as ``.idl`` files as ROS 2 packages do.

rosidl reads ``wchar`` only from ``.idl`` (``.msg`` has no such type), so an interface with a
``wchar`` field or constant goes to ``<kind>/<Name>.idl``, written as the ``idl`` target writes
it, and ``rosidl_generate_interfaces`` lists that file instead.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

from ...model.diagnostics import Diagnostic
from ..base import header_lines
from .package import RosInterface, RosPackage

#: ROS 2 primitives rosidl accepts in .idl files only.
IDL_ONLY = frozenset({"wchar"})


def needs_idl(ri: RosInterface) -> bool:
    """True when a field or constant of ``ri`` has a type only an .idl file can state."""
    return any(f.type.primitive in IDL_ONLY for sec in ri.sections for f in sec.fields) or \
        any(c.primitive in IDL_ONLY for sec in ri.sections for c in sec.consts)


def check_idl_interfaces(pkg: RosPackage) -> Iterator[Diagnostic]:
    """The idl target's value checks, for the interfaces written as .idl."""
    from ..idl.render import check_idl_values  # the idl target lowers through ros2: imported when used

    yield from check_idl_values(replace(pkg, interfaces=[ri for ri in pkg.interfaces if needs_idl(ri)]))


def render_idl(ri: RosInterface, pkg: RosPackage) -> str:
    """The .idl text of one interface, as the idl target writes it."""
    from ..idl import templates
    from ..idl.render import includes, structs, typedefs

    return templates().render(
        "interface.idl.j2", interface=ri, package=pkg.name, header=header_lines("//", pkg.source_name).rstrip("\n"),
        structs=structs(ri), typedefs=typedefs(ri), includes=includes(ri), guards=False)


__all__ = ["IDL_ONLY", "check_idl_interfaces", "needs_idl", "render_idl"]
