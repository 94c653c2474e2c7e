"""The ``idl`` target: OMG IDL 4 as rosidl writes it, one file per message, service and action.

Layout: ``<package>/msg/<Name>.idl``, ``srv/<Name>.idl``, ``action/<Name>.idl``, each
``module <package> { module <kind> { … } }`` with constants in ``<Struct>_Constants``
modules, ``sequence<T, N>``, ``string<N>``, typedefs for fixed arrays, ``@default`` and
``@verbatim`` comments. The model is lowered exactly as for the ``ros2`` target. A name that
collides with an IDL keyword (case-insensitively) is written with IDL's escape, a leading
underscore (``_struct``), which IDL compilers strip.

May import: what ``emit`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``) and the shared
modules of ``emit``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...semantics.compile import Compilation
from ..base import (
    GeneratedFile,
    Result,
    Target,
    TemplateSet,
    header_lines,
    sorted_files,
)
from ..ros2.filenames import check_rosidl_names
from ..ros2.keywords import check_keywords
from ..ros2.lower import lower_checked
from ..ros2.package import RosPackage
from .render import FILTERS, check_idl_values, includes, structs, typedefs
from .reserved import check_idl_names

TEMPLATES = Path(__file__).parent / "templates"

__all__ = ["TARGET", "generate"]


def render_package(pkg: RosPackage, templates: TemplateSet, *, guards: bool = False) -> list[GeneratedFile]:
    """One .idl file per interface.

    ``guards`` (the ardupilot flavour): each fixed-array typedef inside
    ``#ifndef <package>_<kind>_<typedef>_defined`` as ArduPilot's AP_DDS IDL writes it, and the
    file's modules inside ``#ifndef <package>_<kind>_<Name>_defined``, so a file included twice
    (two components using one dependency) declares its structs once and leaves no empty module.
    Names colliding with IDL keywords are escaped (``_struct``); the ros2 target, whose reader
    rosidl_parser takes no escape, renders the same template unescaped.
    """
    header = header_lines("//", pkg.source_name).rstrip("\n")
    files = []
    for kind in ("msg", "srv", "action"):
        for ri in pkg.of_kind(kind):
            text = templates.render("interface.idl.j2", interface=ri, package=pkg.name, header=header,
                                    structs=structs(ri), typedefs=typedefs(ri, escape=True),
                                    includes=includes(ri), guards=guards, escape=True)
            files.append(GeneratedFile(f"{pkg.name}/{kind}/{ri.name}.idl", text, (ri.source, ri.span)))
    return sorted_files(files)


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Lower the compilation as for ROS 2, refuse what IDL readers misread or refuse, render."""
    pkg, diagnostics = lower_checked(comp, check_idl_values, check_idl_names, check_keywords, check_rosidl_names)
    result = Result(diagnostics=diagnostics)
    if pkg is None or result.has_errors:
        return result
    result.files = render_package(pkg, templates(options.get("templates")))
    return result


def templates(override: str | None = None) -> TemplateSet:
    """The idl target's templates (``override``: a folder of templates that wins)."""
    return TemplateSet(TEMPLATES, "idl", filters=FILTERS, override=override)


TARGET = Target(
    name="idl",
    description="OMG IDL 4 as rosidl writes it: one .idl file per message, service and action",
    generate=generate,
    templates=str(TEMPLATES),
)
