"""The ``ros2`` target: an ament package of .msg/.srv/.action files a ROS 2 user builds with colcon.

Layout under the output folder: ``<package>/msg/*.msg``, ``srv/*.srv``, ``action/*.action``,
``package.xml``, ``CMakeLists.txt`` and ``config/<component>.params.yaml``. How the model is
mapped is described in ``lower`` and in docs/targets.md.

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
    sort_diagnostics,
    sorted_files,
)
from .codes import CODES
from .filenames import check_rosidl_names
from .idlfile import check_idl_interfaces, needs_idl, render_idl
from .keywords import check_keywords
from .lower import lower_checked
from .metadata import missing_metadata
from .package import RosPackage
from .render import FILTERS, check_msg_values

TEMPLATES = Path(__file__).parent / "templates"
KINDS = ("msg", "srv", "action")

__all__ = ["CODES", "TARGET", "generate"]


def render_package(pkg: RosPackage, templates: TemplateSet) -> list[GeneratedFile]:
    """Every file of the package, in a stable order; an interface .msg syntax cannot hold as .idl."""
    root = pkg.name
    files: list[GeneratedFile] = []
    interface_files: list[str] = []
    for kind in KINDS:
        for ri in pkg.of_kind(kind):
            if needs_idl(ri):
                rel = f"{kind}/{ri.name}.idl"
                text = render_idl(ri, pkg)
            else:
                rel = f"{kind}/{ri.name}.{kind}"
                text = templates.render(f"{kind}.j2", interface=ri, package=pkg.name,
                                        header=header_lines("#", pkg.source_name).rstrip("\n"))
            interface_files.append(rel)
            files.append(GeneratedFile(f"{root}/{rel}", text, (ri.source, ri.span)))
    named = (pkg.name_source, pkg.name_span)
    xml_header = header_lines("<!--", pkg.source_name, end=" -->").rstrip("\n")
    files.append(GeneratedFile(f"{root}/package.xml", templates.render("package.xml.j2", package=pkg,
                                                                      header=xml_header), named))
    hash_header = header_lines("#", pkg.source_name).rstrip("\n")
    files.append(GeneratedFile(f"{root}/CMakeLists.txt", templates.render(
        "CMakeLists.txt.j2", package=pkg, files=interface_files, header=hash_header), named))
    if pkg.params:
        files.append(GeneratedFile(f"{root}/config/{pkg.node}.params.yaml", templates.render(
            "params.yaml.j2", package=pkg, header=hash_header), (pkg.name_source, pkg.node_span)))
    return sorted_files(files)


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Lower the compilation, refuse what .msg syntax cannot hold, render the package."""
    pkg, diagnostics = lower_checked(comp, check_msg_values, check_idl_interfaces, check_keywords,
                                     check_rosidl_names)
    result = Result(diagnostics=diagnostics)
    if pkg is None or result.has_errors:
        return result
    missing = missing_metadata(comp.interface, pkg)
    if missing is not None:
        result.diagnostics = sort_diagnostics([*result.diagnostics, missing])
    templates = TemplateSet(TEMPLATES, "ros2", filters=FILTERS, override=options.get("templates"))
    result.files = render_package(pkg, templates)
    return result


TARGET = Target(
    name="ros2",
    description="ROS 2 ament package: msg/srv/action files, package.xml, CMakeLists.txt, parameter YAML",
    generate=generate,
    templates=str(TEMPLATES),
)
