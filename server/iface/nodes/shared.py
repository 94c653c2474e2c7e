"""The packages every generated component shares, written once into the output folder beside them.

``iface_msgs`` (the protocol's interface package, from ``iface.nodes.protocol``) and the
runtime packages (``iface_runtime_py``…) are the same for every component. ``generate`` writes
the ones its target needs into the output folder, so ``colcon build`` of that folder builds
everything; a second component generated into the same folder finds them there. What is found
decides what is written, by the version in the package's ``package.xml``:

- no copy, or a copy of this version: written (unchanged files stay as they are);
- an older copy: updated (written over);
- a newer copy (from a newer iface): kept, not a file of it written;

and one line says which (``Result.notes``). A package is listed in ``PACKAGES`` with the
targets that need it; its files are made once per process.
"""

from __future__ import annotations

import functools
import os
import re
from collections.abc import Callable
from dataclasses import dataclass

from ..emit.base import GeneratedFile, TemplateSet
from ..emit.ros2 import TEMPLATES as ROS2_TEMPLATES
from ..emit.ros2 import render_package
from ..emit.ros2.package import RosConst, RosField, RosInterface, RosPackage, RosSection, RosType
from ..emit.ros2.render import FILTERS as ROS2_FILTERS
from ..model.source import Source, Span
from . import protocol

#: Who maintains the shared packages (package.xml wants someone).
MAINTAINER = ("iface", "iface@example.invalid")
LICENSE = "Apache-2.0"
#: The name generated headers give as the source of the shared packages.
SOURCE_NAME = "iface.nodes.protocol"
_VERSION = re.compile(r"<version>\s*([^<\s]+)\s*</version>")


@dataclass(frozen=True, slots=True)
class SharedPackage:
    """A package written beside the components: name, version, files (paths under the output folder)."""

    name: str
    version: str
    files: tuple[GeneratedFile, ...]


@dataclass(frozen=True, slots=True)
class SharedEntry:
    """A shared package as listed: its name, the targets that need it, and how its files are made."""

    name: str
    targets: tuple[str, ...]
    make: Callable[[], SharedPackage]


@dataclass(frozen=True, slots=True)
class Placement:
    """What becomes of one shared package in one output folder: ``write``, ``update`` or ``keep``."""

    name: str
    version: str
    found: str | None
    action: str
    where: str

    @property
    def line(self) -> str:
        """The line that says what was done."""
        if self.found is None:
            return f"{self.name} {self.version}: new in {self.where}"
        if self.action == "keep":
            return (f"{self.name}: the copy in {self.where} ({self.found}) is newer than this iface's "
                    f"({self.version}): kept")
        if self.action == "update":
            return (f"{self.name}: the copy in {self.where} ({self.found}) is older than this iface's "
                    f"({self.version}): updated")
        return f"{self.name} {self.version}: the copy in {self.where} is this version: reused"


def _ros_type(text: str) -> RosType:
    if text.endswith("[]"):
        return RosType(primitive=text[:-2], array="unbounded")
    return RosType(primitive=text)


def protocol_interfaces(source: Source, span: Span) -> list[RosInterface]:
    """The messages and services of ``protocol`` as interface files, located at ``source``/``span``."""
    def section(name: str, fields: tuple[protocol.SrvField, ...],
                consts: tuple[protocol.SrvConst, ...] = ()) -> RosSection:
        return RosSection(name, [RosField(f.name, _ros_type(f.type), None, [f.comment] if f.comment else [],
                                          source, span) for f in fields],
                          [RosConst(c.name, c.type, c.value, [c.comment] if c.comment else [], source, span)
                           for c in consts])

    out = [RosInterface("msg", m.type_name, [section("message", m.fields, m.consts)], list(m.doc), source, span)
           for m in protocol.MESSAGES]
    out += [RosInterface("srv", s.type_name, [section("request", s.request, s.consts),
                                              section("response", s.response)], list(s.doc), source, span)
            for s in protocol.SERVICES]
    return out


def msgs_package() -> SharedPackage:
    """``iface_msgs``: the protocol's messages and services (ament_cmake + rosidl)."""
    source = Source(SOURCE_NAME, "")
    span = Span(0, 0)
    pkg = RosPackage(protocol.PACKAGE, "", "", protocol.PACKAGE_VERSION,
                     f"The iface component protocol, version {protocol.PROTOCOL_VERSION}: save, restore, control "
                     "and describe a running component", MAINTAINER[0], MAINTAINER[1], LICENSE, SOURCE_NAME,
                     source, span, protocol_interfaces(source, span))
    files = render_package(pkg, TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS))
    return SharedPackage(pkg.name, pkg.version, tuple(files))


def runtime_py_package() -> SharedPackage:
    """``iface_runtime_py``: the rclpy components' runtime (ament_python)."""
    from .rclpy.runtime_package import NAME, VERSION, runtime_files

    return SharedPackage(NAME, VERSION, tuple(runtime_files(MAINTAINER, LICENSE)))


def runtime_cpp_package() -> SharedPackage:
    """``iface_runtime_cpp``: the C++ node machinery (``iface.nodes.rclcpp.library``)."""
    from .rclcpp.library import package

    return package()


#: Every shared package, with the targets that write it.
PACKAGES: list[SharedEntry] = [
    SharedEntry(protocol.PACKAGE, ("rclpy", "rclcpp"), msgs_package),
    SharedEntry("iface_runtime_py", ("rclpy",), runtime_py_package),
    SharedEntry("iface_runtime_cpp", ("rclcpp",), runtime_cpp_package),
]


@functools.lru_cache(maxsize=None)
def _made(name: str) -> SharedPackage:
    entry = next(e for e in PACKAGES if e.name == name)
    return entry.make()


def packages_for(target: str) -> list[SharedPackage]:
    """The shared packages ``target`` writes, in the order listed."""
    return [_made(e.name) for e in PACKAGES if target in e.targets]


def version_key(version: str) -> tuple[int, ...] | None:
    """``1.2.0`` → (1, 2, 0); None when it is not dotted numbers."""
    parts = version.split(".")
    if not all(p.isdigit() for p in parts):
        return None
    return tuple(int(p) for p in parts)


def found_version(out: str, name: str) -> str | None:
    """The version in ``out/name/package.xml``; None when there is no readable one."""
    try:
        with open(os.path.join(out, name, "package.xml"), encoding="utf-8") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError):
        return None
    match = _VERSION.search(text)
    return match.group(1) if match else None


def place(package: SharedPackage, out: str | None) -> Placement:
    """What to do with ``package`` in the output folder ``out`` (None: nothing is there to look at)."""
    where = os.path.join(out, package.name) if out else package.name
    found = found_version(out, package.name) if out else None
    if found is None:
        exists = bool(out) and os.path.isdir(os.path.join(out, package.name))  # type: ignore[arg-type]
        return Placement(package.name, package.version, "unknown" if exists else None,
                         "update" if exists else "write", where)
    ours, theirs = version_key(package.version), version_key(found)
    if theirs is None or ours is None or theirs < ours:
        return Placement(package.name, package.version, found, "update", where)
    if theirs > ours:
        return Placement(package.name, package.version, found, "keep", where)
    return Placement(package.name, package.version, found, "write", where)


def shared_files(target: str, out: str | None) -> tuple[list[GeneratedFile], list[str]]:
    """The files of the shared packages ``target`` writes into ``out``, and a line for each package."""
    files: list[GeneratedFile] = []
    lines: list[str] = []
    for package in packages_for(target):
        placement = place(package, out)
        lines.append(placement.line)
        if placement.action != "keep":
            files.extend(package.files)
    return files, lines


__all__ = ["PACKAGES", "Placement", "SharedEntry", "SharedPackage", "msgs_package", "packages_for", "place",
           "runtime_py_package", "shared_files"]
