"""Lowering, part 1: one run's state and diagnostics, and the ROS names of packages, types, fields and nodes.

A converted name is a warning (``ros-naming``), an unconvertible one an error (``ros-name-invalid``).
"""

from __future__ import annotations

import re

from ...model import nodes as m
from ...model.diagnostics import Diagnostic, make
from ...model.naming import (
    is_ros_constant,
    is_ros_field,
    ros_constant_name,
    ros_field_name,
    ros_type_name,
)
from ...model.source import Source, Span
from ...semantics.compile import Compilation
from ..support import Owners, component_span
from .codes import diag

_PACKAGE_CHARS = re.compile(r"^[A-Za-z0-9_.\-]+$")
_NODE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def _namespace_name_span(source: Source, ns: m.Namespace) -> Span:
    """Where the name of ``namespace ros2 NAME`` stands (the whole statement if it cannot be found)."""
    text = source.text
    after_scope = text.find(ns.scope, ns.span.start, ns.span.end)
    start = text.find(ns.name, after_scope + len(ns.scope), ns.span.end) if after_scope >= 0 else -1
    return Span(start, start + len(ns.name)) if start >= 0 else ns.span


class Namer:
    """One lowering run: collects diagnostics and names things the ROS 2 way."""

    def __init__(self, comp: Compilation) -> None:
        self.comp = comp
        self.iface = comp.interface
        self.diags: list[Diagnostic] = []
        self.owners = Owners(comp)
        self.interfaces: list[m.Interface] = [c.interface for c in comp.closure()]
        self._packages: dict[int, str | None] = {}
        self._package_spans: dict[int, Span] = {}
        self._type_names: dict[int, str | None] = {}
        self.depends: set[str] = set()

    # ---- diagnostics -----------------------------------------------------------
    def error(self, code: str, message: str, source: Source, span: Span) -> None:
        self.diags.append(diag(code, message, source, span))

    def renamed(self, what: str, name: str, new: str | None, source: Source, span: Span) -> str | None:
        """Report a converted (warning) or unconvertible (error) name; return the ROS name."""
        if new is None:
            self.diags.append(make("ros-name-invalid", f"{what} name '{name}' cannot be made a valid "
                                   f"ROS 2 {what} name", source, span, name=name))
        elif new != name:
            self.diags.append(make("ros-naming", f"{what} name '{name}' is not a ROS 2 {what} name; "
                                   f"it becomes '{new}' in ROS 2", source, span, name=name, replacement=new))
        return new

    # ---- names -------------------------------------------------------------------
    def package_of(self, iface: m.Interface) -> str | None:
        """The ROS package of a file: its ``ros2`` namespace, else its file stem."""
        key = id(iface)
        if key in self._packages:
            return self._packages[key]
        ns = next((n for n in iface.namespaces if n.scope == "ros2"), None)
        raw = ns.name if ns is not None else iface.source.path.replace("\\", "/").rpartition("/")[2].rsplit(".", 1)[0]
        span = _namespace_name_span(iface.source, ns) if ns is not None else Span(0, 0)
        self._package_spans[key] = span
        new = ros_field_name(raw) if _PACKAGE_CHARS.match(raw) else None
        if new is None:
            self.error("ros-name-invalid", f"package name '{raw}' cannot be made a valid ROS 2 package name "
                       "(lower-case letters, digits and single underscores)", iface.source, span)
        elif new != raw:
            self.diags.append(make("ros-naming", f"package name '{raw}' is not a ROS 2 package name; it becomes "
                                   f"'{new}' in ROS 2", iface.source, span, name=raw, replacement=new))
        self._packages[key] = new
        return new

    def type_name(self, d: m.Definition, *, suffix: str = "") -> str | None:
        """The ROS name of a definition, reported once when it changes.

        The diagnostics service Δ is named by the language (``service diagnostics``),
        so its conversion (``Diagnostics``) is silent, as in the core checks.
        """
        key = id(d)
        if key not in self._type_names:
            owner = self.owners.of(d)
            new = ros_type_name(d.name)
            if isinstance(d, m.Service) and d.is_diagnostics and new is not None:
                self._type_names[key] = new
            else:
                self._type_names[key] = self.renamed("type", d.name, new, owner.source, d.name_span)
        base = self._type_names[key]
        return None if base is None else base + suffix

    def field_name(self, name: str, source: Source, span: Span) -> str | None:
        return self.renamed("field", name, name if is_ros_field(name) else ros_field_name(name), source, span)

    def const_name(self, name: str, source: Source, span: Span) -> str | None:
        return self.renamed("constant", name, name if is_ros_constant(name) else ros_constant_name(name),
                            source, span)

    def node_name(self, component: str) -> str | None:
        """The node the parameters belong to: the component name, converted if ROS 2 refuses it."""
        if _NODE.match(component):
            return component
        return self.renamed("node", component, ros_field_name(component), self.iface.source,
                            component_span(self.iface))

    def _clashes(self, names: list[tuple[str, Source, Span]], what: str) -> None:
        seen: dict[str, str] = {}
        for name, src, span in names:
            written = src.text[span.start:span.end]
            if name in seen:
                self.error("ros2-name-clash", f"{what} '{written}' becomes '{name}' in ROS 2, like "
                           f"'{seen[name]}' before it", src, span)
            else:
                seen[name] = written
