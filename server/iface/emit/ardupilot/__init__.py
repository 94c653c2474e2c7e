"""The ardupilot target: OMG IDL and table entries for AP_DDS, and an AP_Param table.

ArduPilot talks to ROS 2 through AP_DDS, which reads ROS 2 types as OMG IDL in
the rosidl shape (``libraries/AP_DDS/Idl/<pkg>/msg|srv/<Name>.idl``). The IDL is
the ``idl`` target's, lowered exactly as for ``ros2`` so both sides agree on the
wire; AP_DDS has no actions, so those are left out with a warning. Its typedefs
and files carry ArduPilot's ``#ifndef …_defined`` guards; names colliding with IDL keywords are
escaped as there (``_struct``). The wiring statements
become AP_DDS topic and service table entries and XRCE-DDS profiles (``dds``);
the configuration set P becomes an ``AP_Param`` group class whose indices are kept
stable from field ids (``params``, documentation fields from ``metadata``); see
docs/targets-px4-ardupilot.md.

May import: what ``emit`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``), the shared
modules of ``emit`` and the ``idl`` target it reuses.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape

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
from ..idl import render_package
from ..idl import templates as idl_templates
from ..idl.render import check_idl_values
from ..idl.reserved import check_ap_idl_names
from ..keywords import c_family_keyword
from ..ros2.lower import lower_checked
from ..ros2.package import RosPackage
from ..support import component_span
from ..text import cpp_string, header_name, one_line
from .codes import CODES, diag
from .dds import DdsBuilder
from .params import ParamBuilder

TEMPLATES = Path(__file__).parent / "templates"
IDL_ROOT = "libraries/AP_DDS/Idl"
IGNORED = frozenset({"ros2-package-metadata"})


FILTERS: dict[str, Callable[..., Any]] = {"cpp_string": cpp_string, "one_line": one_line,
                                          "xml": lambda text: escape(str(text), {'"': "&quot;"})}


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """IDL for messages and services, AP_DDS tables and profiles, the AP_Param class; errors mean no files."""
    pkg, lowered = lower_checked(comp, check_idl_values, check_ap_idl_names, _no_keywords, _no_actions)
    # package.xml is the ros2 target's business, not ArduPilot's
    diagnostics = [d for d in lowered if d.code not in IGNORED]
    params = ParamBuilder(comp)
    table = params.build()
    diagnostics.extend(params.diagnostics)
    dds = DdsBuilder(comp)
    tables = dds.build()
    diagnostics.extend(dds.diagnostics)
    result = Result(diagnostics=sort_diagnostics(diagnostics))
    if result.has_errors or table is None or pkg is None:
        return result
    ts = TemplateSet(TEMPLATES, "ardupilot", filters=FILTERS, override=options.get("templates"))
    common = {"source_name": header_name(comp.path), "open": "//", "close": ""}
    files = [GeneratedFile(f"{IDL_ROOT}/{f.path}", f.text, f.origin)
             for f in render_package(pkg, idl_templates(), guards=True) if "/action/" not in f.path]
    folder = f"libraries/{table.library}"
    named = (comp.interface.source, component_span(comp.interface))
    if table.params:
        files.append(GeneratedFile(f"{folder}/{table.class_name}.h", ts.render("params.h.j2", table=table, **common),
                                   named))
        files.append(GeneratedFile(f"{folder}/{table.class_name}.cpp",
                                   ts.render("params.cpp.j2", table=table, **common), named))
    dds_files = [("AP_DDS_Topic_Table.h", tables.topics, common),
                 ("AP_DDS_Service_Table.h", tables.services, common),
                 ("dds_xrce_profile.xml", tables.topics or tables.services,
                  {**common, "source_name": common["source_name"].replace("--", "- -"), "open": "<!--",
                   "close": " -->"})]
    for name, entries, context in dds_files:
        if entries:
            text = ts.render(f"{name}.j2", tables=tables, component=comp.interface.name, **context)
            files.append(GeneratedFile(f"{folder}/{name}", text, named))
    result.files = sorted_files(files)
    return result


def _no_keywords(pkg: RosPackage) -> Iterator[Diagnostic]:
    """An error for each name that is a C or C++ keyword: the code built from the IDL would not compile."""
    seen: set[tuple[str, int, int]] = set()
    for what, name, source, span in pkg.identifiers():
        key = (source.path, span.start, span.end)
        if c_family_keyword(name) and key not in seen:
            seen.add(key)
            yield diag("ap-reserved-name", f"{what} is a C/C++ keyword: the code ArduPilot's build generates from "
                       "the IDL declares it as an identifier, which does not compile; rename it", source, span)


def _no_actions(pkg: RosPackage) -> Iterator[Diagnostic]:
    """AP_DDS has no actions: a warning for each one."""
    for action in pkg.of_kind("action"):
        yield diag("ap-no-actions", f"AP_DDS has no actions: action '{action.name}' is not generated for "
                   "ardupilot", action.source, action.span)


TARGET = Target("ardupilot", "ArduPilot: OMG IDL for AP_DDS (rosidl shape, ArduPilot's guards), AP_DDS topic and "
                "service table entries with XRCE-DDS profiles, and an AP_Param table with stable indices", generate,
                str(TEMPLATES))

__all__ = ["CODES", "TARGET", "generate"]
