"""The ardupilot target: OMG IDL for AP_DDS and an AP_Param table.

ArduPilot talks to ROS 2 through AP_DDS, which reads ROS 2 types as OMG IDL in
the rosidl shape (``libraries/AP_DDS/Idl/<pkg>/msg|srv/<Name>.idl``). The IDL is
the ``idl`` target's, lowered exactly as for ``ros2`` so both sides agree on the
wire; AP_DDS has no actions, so those are left out with a warning. The
configuration set P becomes an ``AP_Param`` group class whose indices are kept
stable from field ids; see docs/targets-px4-ardupilot.md.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...compile import Compilation
from ..base import GeneratedFile, Result, Target, TemplateSet, sorted_files
from ..idl import TEMPLATES as IDL_TEMPLATES
from ..idl import render_package
from ..idl.render import FILTERS as IDL_FILTERS
from ..idl.render import ROS_TO_IDL, check_idl_values
from ..px4.escape import cpp_string, one_line
from ..px4.support import source_name
from ..ros2.lower import lower
from .codes import CODES, diag
from .params import ParamBuilder

TEMPLATES = Path(__file__).parent / "templates"
IDL_ROOT = "libraries/AP_DDS/Idl"
IGNORED = frozenset({"ros2-package-metadata"})


FILTERS = {"cpp_string": cpp_string, "one_line": one_line}


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """IDL files for messages and services, and the AP_Param class; errors mean no files."""
    pkg, lowered = lower(comp)
    # package.xml is the ros2 target's business, not ArduPilot's
    diagnostics = [d for d in lowered if d.code not in IGNORED]
    if pkg is not None:
        diagnostics.extend(check_idl_values(pkg))
        for action in pkg.of_kind("action"):
            diagnostics.append(diag("ap-no-actions", f"AP_DDS has no actions: action '{action.name}' is not "
                                    "generated for ardupilot", action.source, action.span))
    params = ParamBuilder(comp)
    table = params.build()
    diagnostics.extend(params.diagnostics)
    diagnostics.sort(key=lambda d: (d.path, d.span.start, d.span.end, d.code))
    result = Result(diagnostics=diagnostics)
    if result.has_errors or table is None or pkg is None:
        return result
    ts = TemplateSet(TEMPLATES, "ardupilot", filters=FILTERS, override=options.get("templates"))
    idl_ts = TemplateSet(IDL_TEMPLATES, "idl", filters={**IDL_FILTERS, "idl_primitive": ROS_TO_IDL.__getitem__})
    common = {"source_name": source_name(comp), "open": "//", "close": ""}
    files = [GeneratedFile(f"{IDL_ROOT}/{f.path}", f.text) for f in render_package(pkg, idl_ts)
             if "/action/" not in f.path]
    if table.params:
        folder = f"libraries/{table.library}"
        files.append(GeneratedFile(f"{folder}/{table.class_name}.h", ts.render("params.h.j2", table=table, **common)))
        files.append(GeneratedFile(f"{folder}/{table.class_name}.cpp",
                                   ts.render("params.cpp.j2", table=table, **common)))
    result.files = sorted_files(files)
    return result


TARGET = Target("ardupilot", "ArduPilot: OMG IDL for AP_DDS (rosidl shape) and an AP_Param table with stable "
                "indices", generate, str(TEMPLATES))

__all__ = ["CODES", "TARGET", "generate"]
