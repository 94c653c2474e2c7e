"""The ``launch`` target: one ROS 2 launch file for a whole system file.

``iface-lsp generate living_room.iface --target launch --out DIR`` writes
``DIR/<system>.launch.py``: each instance's package, executable, node name and parameter file, in
the system's start order (``nodes.system``), and, with the launch argument ``manager:=true``, the
system's component manager in their place (``iface-lsp manager``, which starts the instances itself).
A file that declares no system is refused.

May import: what ``runtime`` may, and the other modules of ``runtime``.
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
from ..system import InstanceSpec, SystemFileError, spec_of

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


def launch_instance(spec: InstanceSpec, out: str) -> LaunchInstance:
    """One instance as the launch file written to the folder ``out`` starts it."""
    params = None
    if spec.parameters is not None:
        params = Path(os.path.relpath(spec.parameters, os.path.abspath(out))).as_posix()
    return LaunchInstance(spec.name, spec.package, spec.executable, spec.node, params, spec.restart != "never")


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
    out = options.get("out")
    instances = [launch_instance(i, out if isinstance(out, str) else ".") for i in system.instances]
    templates = TemplateSet(TEMPLATES, "launch", filters={"pystr": repr}, override=options.get("templates"))
    name = f"{system.name}.launch.py"
    here = os.path.abspath(out if isinstance(out, str) else ".")
    system_file = Path(os.path.relpath(os.path.abspath(comp.path), here)).as_posix()
    text = templates.render("system.launch.py.j2", system=system, instances=instances, file_name=name,
                            system_file=system_file, down_timeout=down_timeout(len(instances)),
                            header=header_lines("#", Path(comp.path).name).rstrip("\n"))
    return Result(files=[GeneratedFile(name, text, (comp.source, iface.system.name_span))])


TARGET = Target(
    name="launch",
    description="one ROS 2 launch file for a system file: every instance's package, executable, node name "
                "and parameters, in start order",
    generate=generate,
    templates=str(TEMPLATES),
)

__all__ = ["TARGET", "LaunchInstance", "down_timeout", "generate", "launch_instance"]
