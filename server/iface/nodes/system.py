"""A system file as the component manager reads it: the instances to run, in the order they start.

``system_spec(path)`` compiles a system file (docs/language.md, Systems) and gives each instance
what starting it needs: the ROS 2 package and executable (by default those ``generate --target
rclpy`` writes for its component), its node name, restart policy, snapshot period, the instances
it starts after, its parameter file and its component's interface hash; for an instance in a
component container, the container, its runtime (rclcpp) and the component class the container
loads, and whether it uses intra-process communication. A file with errors, or one
that declares no system, raises ``SystemFileError`` naming the first error as ``file:line:col``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from ..compat.canon import interface_hash
from ..compat.systemfile import instance_compilations, system_findings
from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Severity
from ..semantics.compile import Compilation, Workspace
from ..semantics.systems import DEFAULT_RESTART, intra_process, period, runtime, standby, start_order
from .component import ComponentSpec, node_spec


class SystemFileError(ValueError):
    """A system file that cannot be run: its message names the file, line and column of the first problem."""


@dataclass(frozen=True)
class InstanceSpec:
    """One instance of a system: what the manager starts, and how it keeps it up."""

    name: str
    node: str
    component: str
    iface_file: Path
    interface_hash: str
    package: str
    executable: str
    restart: str
    snapshot_period: float | None
    after: tuple[str, ...]
    parameters: Path | None
    #: The 1-based line of the instance in its system file.
    line: int
    #: The component container it is loaded into (its node name), or None: a process of its own.
    container: str | None = None
    #: "rclpy" or "rclcpp": the component package it runs (rclcpp in a container).
    runtime: str = "rclpy"
    #: The rclcpp component class a container loads (``counter::Counter``); for rclpy, None.
    plugin: str | None = None
    #: In a container: its publishers and subscriptions use intra-process communication where the QoS allows it.
    intra_process: bool = False
    #: A spare process kept started ahead (of the instance, or of its container), which becomes it at a restart.
    standby: bool = False


@dataclass(frozen=True)
class SystemSpec:
    """A system: its name, version, file, and its instances in start order (reverse it to stop)."""

    name: str
    version: str | None
    file: Path
    #: In the order they start (reverse it to stop).
    instances: tuple[InstanceSpec, ...]

    def instance(self, name: str) -> InstanceSpec | None:
        """The instance called ``name``, if any."""
        return next((i for i in self.instances if i.name == name), None)

    @property
    def containers(self) -> tuple[str, ...]:
        """The component containers the instances name, in the order of their first instance to start."""
        return tuple(dict.fromkeys(i.container for i in self.instances if i.container))

    def in_container(self, container: str) -> tuple[InstanceSpec, ...]:
        """The instances loaded into ``container``, in start order."""
        return tuple(i for i in self.instances if i.container == container)


def system_spec(path: str | os.PathLike[str], include_paths: tuple[str, ...] = ()) -> SystemSpec:
    """The system a system file declares; ``SystemFileError`` for a file with errors or no system."""
    file = Path(os.path.abspath(path))
    if not file.is_file():
        raise SystemFileError(f"{path}: cannot read the system file")
    comp = Workspace(include_paths).compile_path(str(file))
    return spec_of(comp)


def spec_of(comp: Compilation) -> SystemSpec:
    """The system of a compiled system file (see ``system_spec``)."""
    errors = [d for d in [*comp.all_diagnostics(), *system_findings(comp)] if d.severity == Severity.ERROR]
    if errors:
        more = f" (and {len(errors) - 1} more; `iface-lsp check {comp.path}` lists them)" if len(errors) > 1 else ""
        raise SystemFileError(_where(errors[0]) + more)
    iface = comp.interface
    if iface.system is None:
        raise SystemFileError(f"{comp.path}:1:1: error[no-system]: the file declares no system "
                              "(a system file starts with `system NAME`)")
    compiled = {inst.name: c for inst, c in instance_compilations(comp)}
    base = Path(comp.path).parent
    described: dict[str, tuple[ComponentSpec | None, str]] = {}  # a component's node and hash, made once
    out: list[InstanceSpec] = []
    for inst in start_order(iface.instances):
        c = compiled[inst.name]
        if c.path not in described:
            described[c.path] = (node_spec(c), interface_hash(c))
        out.append(_instance(comp, inst, c, described[c.path], base))
    return SystemSpec(iface.system.name, iface.system.version, Path(comp.path), tuple(out))


def _instance(system: Compilation, inst: m.Instance, comp: Compilation,
              described: tuple[ComponentSpec | None, str], base: Path) -> InstanceSpec:
    """One instance: its annotations, else what ``generate --target rclpy`` names for its component."""
    spec, hashed = described
    if spec is None:
        raise SystemFileError(f"{_at(system, inst)}: error[instance-not-generated]: component "
                              f"'{inst.component}' of instance '{inst.name}' cannot be generated for ROS 2: "
                              f"`iface-lsp generate {comp.path} --target rclpy` says why")
    package = inst.value("package") or spec.package
    snapshot = inst.value("snapshot")
    parameters = inst.value("parameters")
    line = system.source.position(inst.span.start)[0] + 1
    run = runtime(inst)
    plugin = (inst.value("plugin") or f"{package}::{spec.class_name}") if run == "rclcpp" else None
    return InstanceSpec(
        name=inst.name, node=inst.node, component=inst.component, iface_file=Path(comp.path),
        interface_hash=hashed, package=package,
        executable=inst.value("executable") or package,
        restart=inst.value("restart") or DEFAULT_RESTART,
        snapshot_period=period(snapshot) if snapshot is not None else None,
        after=tuple(dict.fromkeys(a.text for a in inst.after)),
        parameters=(base / parameters).resolve() if parameters else None, line=line,
        container=inst.value("container"), runtime=run, plugin=plugin, intra_process=intra_process(inst),
        standby=standby(inst))


def _at(comp: Compilation, inst: m.Instance) -> str:
    line, col = comp.source.position(inst.span.start)
    return f"{comp.path}:{line + 1}:{col + 1}"


def _where(d: Diagnostic) -> str:
    """``file:line:col: error[code]: message``."""
    return d.format()


__all__ = ["InstanceSpec", "SystemFileError", "SystemSpec", "spec_of", "system_spec"]
