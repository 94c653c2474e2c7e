"""``iface_runtime_py``: the node machinery every generated rclpy component imports, as one shared package.

An ament_python package (``iface_runtime_py.runtime``: the lifecycle node; ``iface_runtime_py.contract``:
its rules without ROS) that ``generate --target rclpy`` writes once beside the components
(``iface.nodes.shared``). Raise ``VERSION`` whenever a template of it changes, so an older copy in
an output folder is updated and a newer one kept.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...emit.base import GENERATED_MARK, GeneratedFile, TemplateSet, header_lines
from ...emit.ros2.render import xml
from .. import protocol
from ..component import HANDLER_PREFIXES
from .render import py

NAME = "iface_runtime_py"
VERSION = "1.1.0"
TEMPLATES = Path(__file__).parent / "templates" / NAME
#: What the runtime imports at run time.
DEPENDS = ("ament_index_python", "diagnostic_msgs", protocol.PACKAGE, "lifecycle_msgs", "rcl_interfaces", "rclpy")


def runtime_files(maintainer: tuple[str, str], license_name: str) -> list[GeneratedFile]:
    """The package's files, paths under the output folder."""
    templates = TemplateSet(TEMPLATES, "iface_runtime_py", filters={"py": py, "xml": xml})
    source_name = f"{NAME} {VERSION}"
    header = header_lines("#", source_name).rstrip("\n")
    ctx: dict[str, Any] = {
        "pkg_name": NAME, "version": VERSION, "header": header, "protocol_version": protocol.PROTOCOL_VERSION,
        "maintainer": maintainer[0], "maintainer_email": maintainer[1], "license": license_name,
        "depends": sorted(DEPENDS), "state_format": protocol.STATE_FORMAT,
        "handler_prefixes": list(HANDLER_PREFIXES), "diagnostics_topic": protocol.DIAGNOSTICS_TOPIC,
        "default_timeout": repr(protocol.DEFAULT_TIMEOUT_SEC), "runtime_version": VERSION,
        "align_sec": repr(protocol.ALIGN_SEC),
        "generated_mark": GENERATED_MARK,
        "commands": ", ".join(str(c) for c in (protocol.STATUS, protocol.PAUSE, protocol.RESUME, protocol.SAVE)),
    }

    def render(name: str, **extra: Any) -> str:
        return templates.render(name, **{**ctx, **extra})

    xml_header = header_lines("<!--", source_name, end=" -->").rstrip("\n")
    return [
        GeneratedFile(f"{NAME}/package.xml", render("package.xml.j2", header=xml_header)),
        GeneratedFile(f"{NAME}/setup.py", render("setup.py.j2")),
        GeneratedFile(f"{NAME}/setup.cfg", render("setup.cfg.j2")),
        GeneratedFile(f"{NAME}/resource/{NAME}", render("resource.j2")),
        GeneratedFile(f"{NAME}/{NAME}/__init__.py", render("init.py.j2")),
        GeneratedFile(f"{NAME}/{NAME}/contract.py", render("contract.py.j2")),
        GeneratedFile(f"{NAME}/{NAME}/runtime.py", render("runtime.py.j2")),
    ]
