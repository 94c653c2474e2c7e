"""Lower a compiled interface to a ROS 2 interface package (shared by the ``ros2``, ``idl`` and ``ardupilot`` targets).

What becomes what (see docs/targets.md):
- ``message``, ``struct`` and ``exception`` → a message; ``union`` and ``senum`` → an error;
- a flat or sectioned ``service`` → one service; a Thrift function ``f`` of service ``S`` →
  the service ``SF`` (request: the arguments; response: ``result`` unless void; ``throws`` → error);
- ``action`` → an action; the state Σ → ``<Component>State``; top-level constants →
  ``<Component>Constants`` (constants only); configuration P → parameters;
- a field of an enum type → ``int32`` plus the enum's values as ``<ENUM>_<VALUE>`` constants in
  the same message; typedefs are followed; ``binary`` → ``uint8[]``; ``uuid`` → ``uint8[16]``.
Values are decoded to Python values here; each target checks and writes them its own way.

This module assembles the package (its files, parameters and metadata); the parts it is built from are
``names`` → ``fields`` → ``definitions``, each a layer of the one lowering run.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...model.naming import ros_type_name
from ...model.walk import resolve_typedefs, type_text
from ...semantics.compile import Compilation
from ..base import sort_diagnostics
from ..support import component_span
from ..text import doc_lines, header_name
from .definitions import DefinitionLowering
from .fields import field_comments
from .package import PyValue, RosInterface, RosPackage, RosParam, RosSection

_EMAIL = re.compile(r"^[-a-zA-Z0-9_%+]+(\.[-a-zA-Z0-9_%+]+)*@[-a-zA-Z0-9%]+(\.[-a-zA-Z0-9%]+)*\.[a-zA-Z]{2,}$")
_VERSION = re.compile(r"^[0-9]+(\.[0-9]+){0,2}$")


class _Lowering(DefinitionLowering):
    """The whole package: interface files, the component's constants and state, parameters, metadata."""

    def package(self) -> RosPackage | None:
        iface = self.iface
        src = iface.source
        name = self.package_of(iface)
        component = iface.name
        comp_type = ros_type_name(component)
        if comp_type is None:
            self.error("ros-name-invalid", f"component name '{component}' cannot be made a ROS 2 type name",
                       src, component_span(iface))
        node = self.node_name(component)
        if name is None or node is None:
            return None
        pkg = RosPackage(name=name, component=component, node=node, version=self.version(),
                         description=self.annotation("description") or (
                             (doc_lines(iface.component.doc) if iface.component else []) or
                             [f"ROS 2 interfaces of the {component} component."])[0],
                         maintainer=self.annotation("maintainer") or "unknown",
                         maintainer_email=self.email(),
                         license=self.annotation("license") or "TODO",
                         source_name=header_name(src.path), name_source=src,
                         name_span=self._package_spans[id(iface)], node_span=component_span(iface))
        for other in self.interfaces:
            if other is not iface and self.package_of(other) != name:
                continue
            for d in other.definitions:
                if isinstance(d, m.Struct) and d.kind in ("configuration", "state") and other is not iface:
                    continue
                pkg.interfaces.extend(self.interfaces_of(d, other))
        consts = [(d, other) for other in self.interfaces if other is iface or self.package_of(other) == name
                  for d in other.definitions if isinstance(d, m.Const)]
        if consts and comp_type is not None:
            sec = RosSection("message", [], [c for c in (self.const(c, o) for c, o in consts) if c])
            self._clashes([(c.name, c.source, c.span) for c in sec.consts], "constant")
            pkg.interfaces.append(RosInterface("msg", comp_type + "Constants", [sec],
                                               [f"Constants of {component}."], consts[0][1].source,
                                               consts[0][0].name_span))
        if iface.state and comp_type is not None:
            states = [d for d in iface.definitions if isinstance(d, m.Struct) and d.kind == "state"]
            sec = self.section("message", iface.state, [c for s in states for c in s.consts], iface)
            doc = next((doc_lines(s.doc) for s in states if s.doc), [f"The state of {component}."])
            pkg.interfaces.append(RosInterface("msg", comp_type + "State", [sec], doc, src, states[0].name_span))
        pkg.params = self.params()
        seen: dict[tuple[str, str], RosInterface] = {}
        for ri in pkg.interfaces:
            key = (ri.kind, ri.name)
            if key in seen:
                self.error("ros2-name-clash", f"two definitions become {ri.kind}/{ri.name} in ROS 2",
                           ri.source, ri.span)
            seen[key] = ri
        if pkg.of_kind("action"):
            self.depends.add("action_msgs")
        self.depends.discard(name)
        pkg.depends = sorted(self.depends)
        return pkg

    def params(self) -> list[RosParam]:
        """The parameters P with their decoded defaults, refusing what a ROS 2 parameter cannot hold.

        ROS 2 parameters are bool, int64, double, string, byte[] and arrays of bool,
        int64, double or string; a YAML file cannot state an empty array (its type
        is unknown), nor an integer outside int64.
        """
        out = []
        src = self.iface.source
        for f in self.iface.parameters:
            problem = _param_type_problem(f.type)
            if problem is not None:
                self.error("ros2-param-type", f"parameter '{f.name}' is {type_text(f.type)}: {problem}; a ROS 2 "
                           "parameter is a bool, integer (int64), double, string, or an array of one of those",
                           src, f.type.span)
                continue
            enums: list[m.Enum] = []
            rt = self.ros_type(f.type, self.iface, enums)
            if rt is None:
                continue
            if rt.primitive == "uint64":
                self.error("ros2-param-uint64", f"parameter '{f.name}' is {type_text(f.type)}: ROS 2 integer "
                           "parameters are int64, so values above 9223372036854775807 cannot be set",
                           src, f.type.span)
            param = RosParam(f.name, rt, None, field_comments(f))
            if f.default is not None:
                value = self.value(f.default, rt, enums[0] if enums else None, self.iface)
                param.value = self._param_value(f, value)
                if value == []:
                    param.note = ("not set here: ROS 2 cannot load an empty list from YAML (its type is "
                                  "unknown), so the node's own default, [], applies")
            out.append(param)
        return out

    def _param_value(self, f: m.Field, value: PyValue | None) -> PyValue | None:
        """``value`` when a ROS 2 parameter file can state it; None (reported) when not."""
        assert f.default is not None
        src = self.iface.source
        if value == []:
            self.error("ros2-param-empty-list", f"parameter '{f.name}': ROS 2 cannot load an empty list from a "
                       "parameter file (it cannot tell its type); the default is written as a comment instead",
                       src, f.default.span)
            return None
        items = value if isinstance(value, list) else [value]
        lo, hi = _INT64
        if any(isinstance(x, int) and not isinstance(x, bool) and not lo <= x <= hi for x in items):
            self.error("ros2-param-value", f"parameter '{f.name}': the default {f.default.text or value} does not fit "
                       f"int64 ({lo}..{hi}), the type of every ROS 2 integer parameter", src, f.default.span)
            return None
        return value

    def annotation(self, key: str) -> str | None:
        comp = self.iface.component
        if comp is None:
            return None
        a = m.annotation(comp.annotations, key)
        return a.text if a is not None and a.text else None

    def email(self) -> str:
        email = self.annotation("maintainer_email")
        if email is None:
            return "unknown@example.com"
        if not _EMAIL.match(email):
            comp = self.iface.component
            assert comp is not None
            self.error("ros2-package-metadata", f"'{email}' is not an e-mail address package.xml accepts: "
                       "unknown@example.com is written instead", self.iface.source, comp.span)
            return "unknown@example.com"
        return email

    def version(self) -> str:
        comp = self.iface.component
        if comp is None or comp.version is None:
            return "0.0.0"
        if not _VERSION.match(comp.version):
            self.error("ros2-package-metadata", f"version '{comp.version}' is not MAJOR[.MINOR[.PATCH]]: package.xml "
                       "gets 0.0.0", self.iface.source, comp.span)
            return "0.0.0"
        parts = comp.version.split(".")
        return ".".join(str(int(p)) for p in parts + ["0"] * (3 - len(parts)))


_INT64 = m.INT_RANGES["i64"]


def _param_type_problem(t: m.TypeRef) -> str | None:
    """Why a ROS 2 parameter cannot have type ``t`` (typedefs followed), None when it can."""
    r = resolve_typedefs(t)
    if isinstance(r, m.MapType):
        return "ROS 2 parameters have no maps (use one parameter per key, or two arrays)"
    if isinstance(r, m.SetType):
        return "ROS 2 parameters have no sets (use an array)"
    element: m.TypeRef = r
    if isinstance(r, m.ArrayType):
        element = resolve_typedefs(r.element)
        nested = isinstance(element, (m.ArrayType, m.SetType, m.MapType)) or (
            isinstance(element, m.BaseType) and element.name in ("binary", "uuid"))
        if nested:
            return "ROS 2 parameters have no arrays of arrays"
    if isinstance(element, m.NamedType) and not isinstance(element.target, m.Enum):
        what = "arrays of messages" if element is not r else "message types"
        return f"ROS 2 parameters have no {what}"
    return None


def lower(comp: Compilation) -> tuple[RosPackage | None, list[Diagnostic]]:
    """The ROS 2 package of a compilation and the diagnostics found on the way."""
    run = _Lowering(comp)
    pkg = run.package()
    return pkg, run.diags


#: A check of a lowered package: what a target's output syntax cannot hold.
PackageCheck = Callable[[RosPackage], Iterable[Diagnostic]]


def lower_checked(comp: Compilation, *checks: PackageCheck) -> tuple[RosPackage | None, list[Diagnostic]]:
    """``lower``, then every check over the package; the diagnostics sorted."""
    pkg, diagnostics, _ = lower_run(comp, *checks)
    return pkg, diagnostics


def lower_run(comp: Compilation, *checks: PackageCheck) -> tuple[RosPackage | None, list[Diagnostic],
                                                                   DefinitionLowering]:
    """``lower_checked``, and the run itself: node generators ask it the ROS names of wired definitions.

    Its ``package_of``, ``type_name`` and ``ros_type`` give the names the package was written with.
    """
    run = _Lowering(comp)
    pkg = run.package()
    diagnostics = run.diags
    if pkg is not None:
        for check in checks:
            diagnostics.extend(check(pkg))
    return pkg, sort_diagnostics(diagnostics), run
