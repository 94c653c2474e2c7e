"""What runs for an instance: its component, interface, and the package and executable that start it.

An instance's first implementation is the system file's (``nodes.system``: the package and
executable its annotations name, else what ``generate --target rclpy`` writes for its component,
from the sourced workspace). A replacement gives it NEW's (``replacing``): the package ``generate``
names for NEW's component and the executable found in NEW's install folder, whose workspace is
sourced on top; the instance's ``package``/``executable`` annotations only where NEW is the same
component as what it replaces. From then on the instance *is* NEW: its restarts, its status, its
snapshots and a new manager use NEW's implementation, which the state folder keeps
(``Replacements``: ``<state dir>/instances/<instance>.json``) for as long as the system file names
for the instance the component it named when NEW replaced it.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from ..nodes.component import node_spec
from ..semantics.compile import Compilation


class NotStartable(Exception):
    """NEW cannot be started from what was given; the message says why."""


@dataclass(frozen=True, slots=True)
class Implementation:
    """What an instance runs."""

    component: str
    iface_file: str
    interface_hash: str
    package: str
    executable: str
    #: The install folder whose workspace is sourced on top of the manager's environment ("": none).
    package_dir: str = ""


def of_instance(spec: Any) -> Implementation:
    """The system file's implementation of an instance (a ``nodes.system.InstanceSpec``)."""
    return Implementation(str(spec.component), str(spec.iface_file), str(spec.interface_hash), str(spec.package),
                          str(spec.executable))


def replacing(current: Implementation, new: Compilation, new_hash: str, package_dir: Path) -> Implementation:
    """NEW's implementation (``new`` compiled, built in ``package_dir``) for an instance that runs ``current``."""
    spec = node_spec(new)
    if spec is None:
        raise NotStartable(f"{new.path}: cannot be generated for ROS 2 (`iface-lsp generate {new.path} --target "
                           "rclpy` says why)")
    component = spec.component
    if component == current.component:  # the same component: the instance's package and executable
        package, preferred = current.package, current.executable
    else:
        package, preferred = spec.package, spec.package
    executable = find_in_install(package_dir, package, preferred)
    return Implementation(component, os.path.abspath(new.path), new_hash, package, executable.name,
                          str(package_dir))


def install_prefixes(package_dir: Path, package: str) -> list[Path]:
    """Where ``package``'s ``lib/<package>/`` may be under an install folder: the folder itself (a package's
    prefix, ``ws/install/<package>``, or a merged install) or ``<folder>/<package>`` (a workspace's ``install``)."""
    return [package_dir, package_dir / package]


def find_in_install(package_dir: Path, package: str, preferred: str) -> Path:
    """The executable of ``package`` in the install folder ``package_dir``: ``lib/<package>/<preferred>``, else
    the only executable in ``lib/<package>/``; NotStartable when there is none, or several and not ``preferred``."""
    for prefix in install_prefixes(package_dir, package):
        folder = prefix / "lib" / package
        if not folder.is_dir():
            continue
        wanted = folder / preferred
        if wanted.is_file() and os.access(wanted, os.X_OK):
            return wanted
        found = sorted(p for p in folder.iterdir() if p.is_file() and os.access(p, os.X_OK))
        if len(found) == 1:
            return found[0]
        raise NotStartable(f"{folder}: no executable {preferred}" + (
            f" and {len(found)} others ({', '.join(p.name for p in found[:5])}): name it with the instance's "
            "`executable` annotation" if found else ""))
    raise NotStartable(f"{package_dir}: no lib/{package}/ here or in {package}/ (name the install folder of "
                       f"package {package}, e.g. ws/install/{package})")


@dataclass(frozen=True, slots=True)
class Replacement:
    """An instance replaced: its node, generation and implementation since, and the system file's component and
    interface hash it replaced (the record holds while the system file still names them)."""

    instance: str
    node: str
    generation: int
    implementation: Implementation
    replaces_component: str
    replaces_hash: str
    #: The component container NEW runs in ("": a process of its own, or the system file's container).
    container: str = ""

    def holds_for(self, spec: Any) -> bool:
        """Whether the system file still names for the instance what this replacement replaced."""
        return (spec.component, spec.interface_hash) == (self.replaces_component, self.replaces_hash)


class Replacements:
    """The replacement records of one state folder: ``<state dir>/instances/<instance>.json``."""

    def __init__(self, state_dir: Path) -> None:
        self.folder = state_dir / "instances"

    def save(self, record: Replacement) -> None:
        """Write ``record`` atomically."""
        write_json(self.folder / f"{record.instance}.json", asdict(record))

    def load(self, instance: str) -> Replacement | None:
        """The record of ``instance``; None when there is none or it cannot be read."""
        try:
            data = json.loads((self.folder / f"{instance}.json").read_text(encoding="utf-8"))
            data["implementation"] = Implementation(**data["implementation"])
            return Replacement(**data)
        except (OSError, ValueError, TypeError, KeyError):
            return None

    def remove(self, instance: str) -> None:
        """Forget ``instance``'s replacement."""
        (self.folder / f"{instance}.json").unlink(missing_ok=True)


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as JSON to ``path`` atomically: a temporary file beside it, fsynced, renamed over it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    temp = path.with_name(f".tmp-{path.stem}-{os.getpid()}")
    with open(temp, "w", encoding="utf-8") as f:
        json.dump(data, f, sort_keys=True)
        f.flush()
        os.fsync(f.fileno())
    os.replace(temp, path)
