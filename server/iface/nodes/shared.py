"""The packages every generated component shares, written once into the output folder beside them.

``iface_msgs`` (the protocol's interface package, from ``iface.nodes.protocol``) and the
runtime packages (``iface_runtime_py``, ``iface_runtime_cpp``) are the same for every component. The
runtimes are real packages in ``runtimes/`` (linted, type-checked and tested as they are): ``generate``
copies their files verbatim, a generated-file header added to each. ``generate`` writes
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
from pathlib import Path

from ..emit.base import GeneratedFile, TemplateSet, header_lines
from ..emit.ros2 import TEMPLATES as ROS2_TEMPLATES
from ..emit.ros2 import render_package
from ..emit.ros2.package import RosConst, RosField, RosInterface, RosPackage, RosSection, RosType
from ..emit.ros2.render import FILTERS as ROS2_FILTERS
from ..model.source import Source, Span
from . import protocol

#: Who maintains the shared packages (package.xml wants someone).
MAINTAINER = ("iface", "iface@example.invalid")
LICENSE = "Apache-2.0"
#: The name generated headers give as the source of iface_msgs.
SOURCE_NAME = "iface.nodes.protocol"
#: The runtime packages, as they are copied (each a folder: ``iface_runtime_py/``, ``iface_runtime_cpp/``).
RUNTIMES = Path(__file__).parent / "runtimes"
_VERSION = re.compile(r"<version>\s*([^<\s]+)\s*</version>")
#: The comment a generated header takes in a file, by the file's suffix (a file without one: ``#``).
_COMMENTS = {".py": ("#", ""), ".cfg": ("#", ""), ".txt": ("#", ""), "": ("#", ""), ".cpp": ("//", ""),
             ".hpp": ("//", ""), ".xml": ("<!--", " -->")}


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


def source_files(name: str) -> list[tuple[str, str]]:
    """(path under the package, text) of every file of the runtime package ``name``, sorted.

    Python's byte-code caches (left by the tests that import the package) are not files of it.
    """
    root = RUNTIMES / name
    out = []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if path.is_file() and "__pycache__" not in rel.parts and path.suffix != ".pyc":
            out.append((rel.as_posix(), path.read_text(encoding="utf-8")))
    return out


def with_header(path: str, text: str, source_name: str) -> str:
    """``text`` with the generated-file header in the comment syntax of ``path`` (XML: after its declarations)."""
    suffix = os.path.splitext(path)[1]
    if suffix not in _COMMENTS:
        raise ValueError(f"no comment syntax for {path}: add its suffix to shared._COMMENTS")
    comment, end = _COMMENTS[suffix]
    header = header_lines(comment, source_name, end=end)
    if suffix != ".xml":
        return header + text
    lines = text.splitlines(keepends=True)
    declarations = 0
    while declarations < len(lines) and lines[declarations].startswith("<?"):
        declarations += 1
    return "".join(lines[:declarations]) + header + "".join(lines[declarations:])


def source_version(name: str) -> str:
    """The version in the runtime package's own package.xml (the one place it is written)."""
    found = _VERSION.search((RUNTIMES / name / "package.xml").read_text(encoding="utf-8"))
    if found is None:
        raise ValueError(f"{RUNTIMES / name / 'package.xml'} has no <version>")
    return found.group(1)


def runtime_package(name: str) -> SharedPackage:
    """The runtime package ``name`` as ``generate`` writes it: its files verbatim, each with a header."""
    version = source_version(name)
    source_name = f"{name} {version}"
    return SharedPackage(name, version, tuple(GeneratedFile(f"{name}/{path}", with_header(path, text, source_name))
                                              for path, text in source_files(name)))


def runtime_py_package() -> SharedPackage:
    """``iface_runtime_py``: the rclpy components' runtime (ament_python)."""
    return runtime_package("iface_runtime_py")


def runtime_cpp_package() -> SharedPackage:
    """``iface_runtime_cpp``: the rclcpp components' node machinery, one library they link (ament_cmake)."""
    return runtime_package("iface_runtime_cpp")


#: Every shared package, with the targets that write it.
PACKAGES: list[SharedEntry] = [
    SharedEntry(protocol.PACKAGE, ("rclpy", "rclcpp"), msgs_package),
    SharedEntry("iface_runtime_py", ("rclpy",), runtime_py_package),
    SharedEntry("iface_runtime_cpp", ("rclcpp",), runtime_cpp_package),
]


@functools.cache
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


__all__ = ["PACKAGES", "RUNTIMES", "Placement", "SharedEntry", "SharedPackage", "msgs_package", "packages_for",
           "place", "runtime_cpp_package", "runtime_package", "runtime_py_package", "shared_files", "source_files",
           "source_version", "with_header"]
