"""Component containers: what loading a system's rclcpp instance into one takes, and whether a NEW can share one.

A container (iface_runtime_cpp's ``iface_container``) loads a component from the ament index entry of
its package, ``<prefix>/share/ament_index/resource_index/rclcpp_components/<package>``, a line
``<class>;<library>`` per component. The manager names that entry by its absolute path (the
container accepts one), so the library loaded is the one found here, and, with a trust store, the
one whose signature was checked (``Component.untrusted``) before the container is asked to load it.

NEW may share OLD's process when every library its component library needs is the very file the
container already has loaded, or would load, under that name: one interface package and one
``iface_runtime_cpp`` per process (docs/runtime.md, "One container, many components").
``sharing_problem`` says why not, else None. The libraries a library needs are the dynamic
loader's own answer (``ldd`` in each environment), the libraries a process has loaded its memory map
(``/proc/<pid>/maps``).
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

from .trust import SIGNATURE_FILE, TrustError, verify

#: The executable of a container (package, executable).
CONTAINER_PACKAGE, CONTAINER_EXECUTABLE = "iface_runtime_cpp", "iface_container"
INDEX = Path("share") / "ament_index" / "resource_index" / "rclcpp_components"
#: The protocol library every component links: its name in the messages.
RUNTIME_LIBRARY = "libiface_runtime_cpp.so"
_LDD_LINE = re.compile(r"^\s*(\S+)\s+=>\s+(\S+)(?:\s+\(0x[0-9a-f]+\))?\s*$")
_LDD_NOT_FOUND = "not found"


class ContainerError(Exception):
    """A component cannot be loaded as asked: the message says why."""


@dataclass(frozen=True, slots=True)
class Component:
    """An rclcpp component as a container loads it: its package's install prefix, index entry, class and library."""

    package: str
    plugin: str
    prefix: Path
    #: ``<prefix>/share/ament_index/resource_index/rclcpp_components/<package>``: what the container is asked to load.
    resource: Path
    library: Path

    def untrusted(self, store: Path) -> list[str]:
        """What keeps the trust store from trusting this component's library (empty: trusted).

        The signed folder is the package's install prefix; its signature must hold (``trust.verify``) and
        cover the index entry and the library the container loads from it.
        """
        try:
            problems = verify(self.prefix, store)
        except TrustError as e:
            return [str(e)]
        if problems:
            return problems
        for path in (self.resource, self.library):
            try:
                path.resolve().relative_to(self.prefix.resolve())
            except ValueError:
                return [f"{path} is outside the signed package folder {self.prefix}"]
        if not (self.prefix / SIGNATURE_FILE).is_file():  # pragma: no cover - verify said so
            return [f"{self.prefix} is not signed"]
        return []


def resource_lines(resource: Path) -> list[tuple[str, str]]:
    """The (class, library) lines of an rclcpp_components index entry."""
    out = []
    for line in resource.read_text(encoding="utf-8").splitlines():
        if line.strip():
            cls, _, lib = line.partition(";")
            out.append((cls.strip(), lib.strip()))
    return out


def component_in(prefix: Path, package: str, plugin: str) -> Component:
    """The component ``plugin`` of ``package`` installed in the prefix ``prefix``; ContainerError when it is not."""
    resource = prefix / INDEX / package
    if not resource.is_file():
        raise ContainerError(f"{prefix} registers no rclcpp component of package {package} (no {INDEX}/{package}): "
                             "a container loads the package `generate --target rclcpp` writes, once built")
    lines = resource_lines(resource)
    library = next((lib for cls, lib in lines if cls == plugin), None)
    if library is None:
        known = ", ".join(cls for cls, _ in lines) or "none"
        raise ContainerError(f"package {package} in {prefix} registers no component {plugin} (it registers: {known})")
    path = Path(library) if os.path.isabs(library) else prefix / library
    return Component(package, plugin, prefix, resource, path)


def find_component(package: str, plugin: str, env: dict[str, str]) -> Component:
    """The component ``plugin`` of ``package`` in the first prefix of ``AMENT_PREFIX_PATH`` that registers the package."""
    prefixes = [Path(p) for p in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    for prefix in prefixes:
        if (prefix / INDEX / package).is_file():
            return component_in(prefix, package, plugin)
    raise ContainerError(f"no rclcpp component of package {package} in the sourced workspace ({len(prefixes)} "
                         f"prefixes on AMENT_PREFIX_PATH): generate it with --target rclcpp, build it and source its "
                         "install/setup.bash")


def installed_parameters(component: Component) -> Path | None:
    """The package's installed parameter file (``share/<package>/config/<package>.params.yaml``), if any."""
    path = component.prefix / "share" / component.package / "config" / f"{component.package}.params.yaml"
    return path if path.is_file() else None


# ---- whether NEW can share a running container --------------------------------------------------------------


def needed(library: Path, env: dict[str, str]) -> dict[str, str | None]:
    """Every library ``library`` needs, by the name it needs it under, as the dynamic loader resolves it in ``env``
    (None: not found). ContainerError when ``ldd`` cannot tell."""
    ldd = shutil.which("ldd", path=env.get("PATH")) or shutil.which("ldd")
    if ldd is None:
        raise ContainerError("ldd is not installed: cannot tell which libraries NEW needs")
    try:
        done = subprocess.run([ldd, str(library)], env=env, capture_output=True, text=True, timeout=60, check=False)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise ContainerError(f"ldd {library} did not run: {e}") from e
    if done.returncode != 0:
        raise ContainerError(f"ldd {library}: {(done.stderr or done.stdout).strip()[-300:]}")
    out: dict[str, str | None] = {}
    for line in done.stdout.splitlines():
        found = _LDD_LINE.match(line)
        if found:
            name, where = found.groups()
            out[name] = None if where == "not" else os.path.realpath(where)
        elif _LDD_NOT_FOUND in line:
            out[line.split()[0]] = None
    return out


def mapped_files(pid: int) -> set[str]:
    """The files a running process has mapped (its loaded libraries among them), as real paths."""
    try:
        text = Path(f"/proc/{pid}/maps").read_text()
    except OSError as e:
        raise ContainerError(f"cannot read the memory map of process {pid}: {e.strerror or e}") from e
    out = set()
    for line in text.splitlines():
        parts = line.split(None, 5)
        if len(parts) == 6 and parts[5].startswith("/"):
            out.add(os.path.realpath(parts[5].removesuffix(" (deleted)")))
    return out


def process_environment(pid: int) -> dict[str, str] | None:
    """The environment a running process was started with (``/proc/<pid>/environ``), None when it cannot be read."""
    try:
        raw = Path(f"/proc/{pid}/environ").read_bytes()
    except OSError:
        return None
    return dict(item.split("=", 1) for item in raw.decode(errors="replace").split("\0") if "=" in item)


_digests: dict[tuple[str, int, int], str] = {}


def _digest(path: str) -> str:
    stat = os.stat(path)
    key = (path, stat.st_mtime_ns, stat.st_size)
    if key not in _digests:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        _digests[key] = h.hexdigest()
    return _digests[key]


def same_file(a: str, b: str) -> bool:
    """The same file, or two files with the same content."""
    if os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return _digest(a) == _digest(b)
    except OSError:
        return False


def _version(library: str, package: str) -> str:
    """The version in ``<prefix>/share/<package>/package.xml`` of the prefix that holds ``library``, or "?"."""
    xml = Path(library).parent.parent / "share" / package / "package.xml"
    try:
        found = re.search(r"<version>\s*([^<\s]+)\s*</version>", xml.read_text(encoding="utf-8"))
    except OSError:
        return "?"
    return found.group(1) if found else "?"


def why_not(name: str, new: str, there: str) -> str:
    """Why NEW, which needs the library ``new`` under ``name``, cannot run beside the container's ``there``."""
    if name == RUNTIME_LIBRARY:
        return (f"another iface_runtime_cpp: NEW's is {new} ({_version(new, 'iface_runtime_cpp')}), the container "
                f"runs {there} ({_version(there, 'iface_runtime_cpp')}); one iface_runtime_cpp per process")
    found = re.match(r"^lib(.+?)__(rosidl_|.*typesupport)", name)
    if found:
        package = found.group(1)
        return (f"another {package} (an interface package): NEW's {name} is {new} ({_version(new, package)}), the "
                f"container has {there} ({_version(there, package)}) loaded; one interface package per process")
    return f"NEW needs {name} as {new}, the container has {there}: another library under the same name"


def sharing_problem(library: Path, container_pid: int, container_env: dict[str, str],
                    new_env: dict[str, str]) -> str | None:
    """Why NEW's component ``library`` cannot be loaded into the running container ``container_pid``; None when it can.

    Each library NEW needs (resolved in NEW's environment) must be the file the container binds under that name:
    the one it has loaded, else the one its own environment resolves.
    """
    mine = needed(library, new_env)
    theirs = needed(library, container_env)
    loaded = mapped_files(container_pid)
    by_name: dict[str, str] = {}
    for file in loaded:
        by_name.setdefault(os.path.basename(file), file)
    for name, path in sorted(mine.items()):
        if path is None:
            return f"NEW's {library.name} needs {name}, which NEW's own environment does not find"
        there = by_name.get(name) or theirs.get(name)
        if there is None:
            return f"the container would not find {name}, which NEW's {library.name} needs (NEW's is {path})"
        if not same_file(path, there):
            return why_not(name, path, there)
    return None


__all__ = ["CONTAINER_EXECUTABLE", "CONTAINER_PACKAGE", "Component", "ContainerError", "component_in",
           "find_component", "installed_parameters", "mapped_files", "needed", "process_environment", "same_file",
           "sharing_problem", "why_not"]
