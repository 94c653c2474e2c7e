"""package.xml metadata the component leaves out: a license and a maintainer.

A package.xml without them still builds, but says ``TODO`` and ``unknown``, which
bloom, the ROS build farm and ``ament_copyright`` refuse and no user wants to publish.
The warning is on the component (the start of the file when it has no declaration);
its ``missing`` data lets the editor's quick fix add what is missing.
"""

from __future__ import annotations

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ..support import component_span
from .codes import diag
from .package import RosPackage

#: The values package.xml gets when the component does not say.
NO_LICENSE, NO_MAINTAINER = "TODO", "unknown"


def missing_metadata(iface: m.Interface, pkg: RosPackage) -> Diagnostic | None:
    """A warning when the package.xml of ``pkg`` would carry a placeholder license or maintainer."""
    missing = []
    if pkg.license.strip().upper().startswith(NO_LICENSE):
        missing.append("license")
    if pkg.maintainer == NO_MAINTAINER:
        missing.append("maintainer")
    if not missing:
        return None
    said = {"license": f"license {pkg.license}", "maintainer": f"maintainer '{pkg.maintainer}'"}
    keys = " and ".join(f"`{k} = \"…\"`" for k in missing)
    where = f"component {iface.name}" if iface.component is not None else f"a `component {iface.name}` line"
    found = diag("ros2-package-metadata-missing",
                 f"package.xml of {pkg.name} gets {' and '.join(said[k] for k in missing)}: add {keys} to "
                 f"{where} (ROS 2 tools and the build farm need both)", iface.source, component_span(iface))
    found.data = {"missing": missing}
    return found
