"""The ``launch`` target: one ROS 2 launch file for a whole system file.

``iface-lsp generate living_room.iface --target launch --out DIR`` writes
``DIR/<system>.launch.py``: each instance's package, executable, node name and parameter file, in
the system's start order (``nodes.system``); the instances of a component container as the
``ComposableNode``s of one ``ComposableNodeContainer`` (iface_runtime_cpp's ``iface_container``),
with intra-process communication where the instance has it; and, with the launch argument
``manager:=true``, the system's component manager in their place (``iface-lsp manager``, which starts
the instances itself). A file that declares no system is refused.

May import: what ``nodes`` may, and the other modules of ``nodes``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...emit.base import CodeTable, GeneratedFile, Result, Target, TemplateSet, header_lines
from ...model.diagnostics import CODES as CORE_CODES
from ...model.diagnostics import Severity
from ...model.source import Span
from ...semantics.compile import Compilation
from ..system import InstanceSpec, SystemFileError, SystemSpec, spec_of

TEMPLATES = Path(__file__).parent / "templates"
CODES: dict[str, tuple[Severity, str]] = {
    "launch-needs-system": (Severity.ERROR, "The launch target was given a file that declares no system."),
    "instance-not-generated": (Severity.ERROR, "An instance whose component cannot be generated for ROS 2, "
                               "so it has no package to launch."),
}
_diag = CodeTable(CODES, CORE_CODES)


@dataclass(frozen=True)
class LaunchInstance:
    """What the launch file says of one instance."""

    name: str
    package: str
    executable: str
    node: str
    #: The parameter file relative to the launch file, or None.
    parameters: str | None
    respawn: bool


@dataclass(frozen=True)
class LaunchComposable:
    """What the launch file says of one instance in a container."""

    name: str
    package: str
    plugin: str
    node: str
    #: The parameter file relative to the launch file, or None.
    parameters: str | None
    intra_process: bool


@dataclass(frozen=True)
class LaunchContainer:
    """A component container and the instances it loads, in start order."""

    name: str
    nodes: tuple[LaunchComposable, ...]


def _relative(path: Path | None, out: str) -> str | None:
    return None if path is None else Path(os.path.relpath(path, os.path.abspath(out))).as_posix()


def launch_instance(spec: InstanceSpec, out: str) -> LaunchInstance:
    """One instance as the launch file written to the folder ``out`` starts it."""
    return LaunchInstance(spec.name, spec.package, spec.executable, spec.node, _relative(spec.parameters, out),
                          spec.restart != "never")


def launch_container(system: SystemSpec, container: str, out: str) -> LaunchContainer:
    """A container as the launch file written to ``out`` starts it: its instances as composable nodes."""
    return LaunchContainer(container, tuple(
        LaunchComposable(i.name, i.package, i.plugin or "", i.node, _relative(i.parameters, out), i.intra_process)
        for i in system.in_container(container)))


def start_order(system: SystemSpec) -> list[tuple[str, str]]:
    """What the launch file starts, in start order: ("instance", name) or ("container", name) at its first instance."""
    order: list[tuple[str, str]] = []
    for i in system.instances:
        unit = ("container", i.container) if i.container else ("instance", i.name)
        if unit not in order:
            order.append(unit)
    return order


def down_timeout(instances: int) -> int:
    """Seconds a manager started by launch has to take ``instances`` down (each: deactivate, snapshot, shutdown,
    the process's end) before launch sends it SIGTERM; SIGKILL follows 10 s later and would leave them running."""
    return 30 + 30 * instances


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """``<system>.launch.py`` for a system file."""
    iface = comp.interface
    if iface.system is None:
        return Result(diagnostics=[_diag("launch-needs-system", "the launch target writes a system's launch file: "
                                         "give it a system file (`system NAME` and its instances)",
                                         comp.source, Span(0, 0))])
    try:
        system = spec_of(comp)
    except SystemFileError as e:
        return Result(diagnostics=[_diag("instance-not-generated", str(e), comp.source, iface.system.name_span)])
    given = options.get("out")
    out = given if isinstance(given, str) else "."
    instances = [launch_instance(i, out) for i in system.instances if i.container is None]
    containers = [launch_container(system, c, out) for c in system.containers]
    templates = TemplateSet(TEMPLATES, "launch", filters={"pystr": repr}, override=options.get("templates"))
    name = f"{system.name}.launch.py"
    system_file = Path(os.path.relpath(os.path.abspath(comp.path), os.path.abspath(out))).as_posix()
    text = templates.render("system.launch.py.j2", system=system, instances=instances, containers=containers,
                            order=start_order(system), file_name=name, system_file=system_file,
                            down_timeout=down_timeout(len(system.instances)),
                            header=header_lines("#", Path(comp.path).name).rstrip("\n"))
    return Result(files=[GeneratedFile(name, text, (comp.source, iface.system.name_span))])


TARGET = Target(
    name="launch",
    description="one ROS 2 launch file for a system file: every instance's package, executable, node name "
                "and parameters, in start order; a container's instances as composable nodes",
    generate=generate,
    templates=str(TEMPLATES),
)

__all__ = ["TARGET", "LaunchComposable", "LaunchContainer", "LaunchInstance", "down_timeout", "generate",
           "launch_container", "launch_instance", "start_order"]
