"""The ``idl`` target: OMG IDL 4 as rosidl writes it, one file per message, service and action.

Layout: ``<package>/msg/<Name>.idl``, ``srv/<Name>.idl``, ``action/<Name>.idl``, each
``module <package> { module <kind> { … } }`` with constants in ``<Struct>_Constants``
modules, ``sequence<T, N>``, ``string<N>``, typedefs for fixed arrays, ``@default`` and
``@verbatim`` comments. The model is lowered exactly as for the ``ros2`` target.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import jinja2

from ...compile import Compilation
from ..base import GeneratedFile, GenerationError, Result, Target, TemplateSet, header_lines, sorted_files
from ..ros2.lower import RosPackage, lower
from .render import FILTERS, ROS_TO_IDL, check_idl_values, includes, structs, typedefs

TEMPLATES = Path(__file__).parent / "templates"

__all__ = ["TARGET", "generate"]


def render_package(pkg: RosPackage, templates: TemplateSet) -> list[GeneratedFile]:
    """One .idl file per interface."""
    header = header_lines("//", pkg.source_name).rstrip("\n")
    files = []
    for kind in ("msg", "srv", "action"):
        for ri in pkg.of_kind(kind):
            text = templates.render("interface.idl.j2", interface=ri, package=pkg.name, header=header,
                                    structs=structs(ri), typedefs=typedefs(ri), includes=includes(ri))
            files.append(GeneratedFile(f"{pkg.name}/{kind}/{ri.name}.idl", text))
    return sorted_files(files)


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Lower the compilation as for ROS 2, refuse what IDL readers misread, render."""
    result = Result()
    pkg, diagnostics = lower(comp)
    result.diagnostics.extend(diagnostics)
    if pkg is not None:
        result.diagnostics.extend(check_idl_values(pkg))
    result.diagnostics.sort(key=lambda d: (d.path, d.span.start, d.span.end, d.code))
    if pkg is None or result.has_errors:
        return result
    templates = TemplateSet(TEMPLATES, "idl", filters={**FILTERS, "idl_primitive": ROS_TO_IDL.__getitem__},
                            override=options.get("templates"))
    try:
        result.files = render_package(pkg, templates)
    except jinja2.TemplateError as e:
        raise GenerationError(f"idl templates: {e}") from e
    return result


TARGET = Target(
    name="idl",
    description="OMG IDL 4 as rosidl writes it: one .idl file per message, service and action",
    generate=generate,
    templates=str(TEMPLATES),
)
