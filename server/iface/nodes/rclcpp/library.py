"""``iface_runtime_cpp``: the C++ node machinery as one ament_cmake package that every rclcpp component links.

It holds what each component package held before (``iface_runtime.hpp``/``.cpp``): the state document,
parameter checks, work transactions, the lifecycle, Δ, and the protocol services of ``iface_msgs``
(``~/save_state``, ``~/restore_state``, ``~/control``, ``~/describe``). It exports the library target
``iface_runtime_cpp::iface_runtime_cpp``; a component package keeps only its base class, its entry point,
its launch and parameter files and the user's ``node.cpp``.

One copy of the library per process: two components in one container share it (no symbol is defined
twice), and their protocol services have the same types.
"""

from __future__ import annotations

from pathlib import Path

from ...emit.base import GeneratedFile, TemplateSet, header_lines
from .. import protocol
from ..shared import LICENSE, MAINTAINER, SOURCE_NAME, SharedPackage
from .render import cpp_str

PACKAGE = "iface_runtime_cpp"
#: The library's version: its major number is the protocol's; raise the minor one with every change.
VERSION = f"{protocol.PROTOCOL_VERSION}.2.0"
TEMPLATES = Path(__file__).parent / "templates"
#: What the library uses in its public headers (exported to the components) and privately.
PUBLIC_DEPENDS = ("diagnostic_msgs", protocol.PACKAGE, "rcl_interfaces", "rclcpp", "rclcpp_action", "rclcpp_lifecycle")
PRIVATE_DEPENDS = ("ament_index_cpp", "lifecycle_msgs")
#: What only the header-only component.hpp uses: the component packages that include it link it themselves.
HEADER_DEPENDS = ("rclcpp_components",)
#: The CMake targets of the public dependencies that are not message packages.
_TARGETS = {"rclcpp": "rclcpp::rclcpp", "rclcpp_action": "rclcpp_action::rclcpp_action",
            "rclcpp_lifecycle": "rclcpp_lifecycle::rclcpp_lifecycle"}


def generated_header(comment: str, end: str = "") -> str:
    """The "generated — do not edit" header of the library's files."""
    return header_lines(comment, SOURCE_NAME, end=end).rstrip("\n")


def package() -> SharedPackage:
    """``iface_runtime_cpp/``: package.xml, CMakeLists.txt, the header and the source (paths under the output folder)."""
    templates = TemplateSet(TEMPLATES, "rclcpp_runtime", filters={"cpp": cpp_str})
    ctx = {"runtime_version": VERSION, "protocol_version": protocol.PROTOCOL_VERSION,
           "state_format": protocol.STATE_FORMAT, "diagnostics_topic": protocol.DIAGNOSTICS_TOPIC,
           "default_timeout": repr(protocol.DEFAULT_TIMEOUT_SEC), "align_sec": repr(protocol.ALIGN_SEC),
           "commands": [protocol.STATUS, protocol.PAUSE, protocol.RESUME, protocol.SAVE],
           "depends": sorted(PUBLIC_DEPENDS + PRIVATE_DEPENDS + HEADER_DEPENDS),
           "exported": sorted(PUBLIC_DEPENDS + HEADER_DEPENDS),
           "public_depends": [_TARGETS.get(d, f"${{{d}_TARGETS}}") for d in PUBLIC_DEPENDS],
           "maintainer": MAINTAINER, "license": LICENSE}
    files = [("package.xml", "library.package.xml.j2", generated_header("<!--", " -->")),
             ("CMakeLists.txt", "library.CMakeLists.txt.j2", generated_header("#")),
             ("include/iface_runtime_cpp/iface_runtime.hpp", "iface_runtime.hpp.j2", generated_header("//")),
             ("include/iface_runtime_cpp/run.hpp", "run.hpp.j2", generated_header("//")),
             ("include/iface_runtime_cpp/component.hpp", "component.hpp.j2", generated_header("//")),
             ("src/iface_runtime.cpp", "iface_runtime.cpp.j2", generated_header("//"))]
    return SharedPackage(PACKAGE, VERSION, tuple(
        GeneratedFile(f"{PACKAGE}/{path}", templates.render(name, header=header, **ctx)) for path, name, header in files))


__all__ = ["PACKAGE", "VERSION", "package"]
