"""The px4 target: uORB messages, a module class header and module.yaml parameters.

PX4 speaks uORB: fixed-size messages with ``uint64 timestamp`` first, published
and subscribed on snake_case topics. Anything uORB cannot hold (strings,
variable-length arrays, defaults, services, actions) is reported, never dropped
in silence; see docs/targets-px4-ardupilot.md.

May import: what ``emit`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``) and the shared
modules of ``emit``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...semantics.compile import Compilation
from ..base import (
    GeneratedFile,
    Result,
    Target,
    TemplateSet,
    sort_diagnostics,
    sorted_files,
)
from ..support import Owners, component_span
from ..text import cpp_string, header_name, line_comment, yaml_string
from .codes import CODES, diag
from .messages import MessageBuilder
from .module import ModuleBuilder
from .upstream import collisions

TEMPLATES = Path(__file__).parent / "templates"
FILTERS: dict[str, Callable[..., Any]] = {"cpp_string": cpp_string, "yaml_str": yaml_string, "comment": line_comment}


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """uORB messages, the module header and module.yaml; errors mean no files."""
    owners = Owners(comp)
    messages = MessageBuilder(comp, owners)
    msgs = messages.build()
    modules = ModuleBuilder(comp, owners, messages.messages, messages.names, messages.wired)
    module = modules.build()
    diagnostics = [*messages.diagnostics, *modules.diagnostics, *_not_generated(comp.interface),
                   *collisions(comp.interface, messages)]
    result = Result(diagnostics=sort_diagnostics(diagnostics))
    if result.has_errors:
        return result
    ts = TemplateSet(TEMPLATES, "px4", filters=FILTERS, override=options.get("templates"))
    common = {"source_name": header_name(comp.path), "close": ""}
    files = [GeneratedFile(f"msg/{msg.name}.msg", ts.render("msg.j2", msg=msg, open="#", **common),
                           (owners.source(msg.struct), msg.struct.name_span))
             for msg in msgs]
    if module is not None:
        folder = f"src/modules/{module.module_name}"
        named = (comp.interface.source, component_span(comp.interface))
        files.append(GeneratedFile(f"{folder}/{module.class_name}.hpp",
                                   ts.render("module.hpp.j2", module=module, open="//", **common), named))
        files.append(GeneratedFile(f"{folder}/module.yaml", ts.render("module.yaml.j2", module=module, open="#",
                                                                       **common), named))
        files.append(GeneratedFile(f"{folder}/{module.class_name}.cpp",
                                   ts.render("module.cpp.j2", module=module, open="//", **common), named))
        files.append(GeneratedFile(f"{folder}/{module.class_name}_user.cpp",
                                   ts.render("module_user.cpp.j2", module=module, **common), named, once=True))
        files.append(GeneratedFile(f"{folder}/CMakeLists.txt",
                                   ts.render("CMakeLists.txt.j2", module=module, open="#", **common), named))
        files.append(GeneratedFile(f"{folder}/Kconfig", ts.render("Kconfig.j2", module=module, open="#", **common),
                                   named))
    result.files = sorted_files(files)
    return result


def _not_generated(iface: m.Interface) -> Iterator[Diagnostic]:
    """PX4 has no services, actions or state: say so for each one."""
    src = iface.source
    seen: set[int] = set()
    for ep in [*iface.services, *iface.actions]:
        defn = ep.definition
        if defn is None or id(defn) in seen:
            continue
        seen.add(id(defn))
        kind = "action" if isinstance(defn, m.Action) else "service"
        span = ep.wiring.span if ep.wiring is not None else defn.name_span
        verb = "provided" if ep.role == "provides" else "called"
        yield diag("px4-no-services", f"PX4 has no {kind}s: {kind} '{defn.name}' ({verb} as '{ep.name}') is not "
                   "generated for px4; uORB only publishes and subscribes topics", src, span)
    for svc in iface.diagnostics:
        if id(svc) not in seen:
            seen.add(id(svc))
            yield diag("px4-no-services", f"PX4 has no services: the diagnostics service '{svc.name}' is not "
                       "generated for px4", src, svc.name_span)
    for d in iface.definitions:
        if isinstance(d, m.Struct) and d.kind == "state":
            yield diag("px4-no-state", f"PX4 has no state set: state '{d.name}' is not generated for px4",
                       src, d.name_span)


TARGET = Target("px4", "PX4: uORB .msg files and a module that builds in PX4's tree (ModuleBase, ModuleParams, "
                "ScheduledWorkItem; CMakeLists.txt, Kconfig, module.yaml; the user's file written once)",
                generate, str(TEMPLATES))

__all__ = ["CODES", "TARGET", "generate"]
