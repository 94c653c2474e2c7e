"""The manager's component containers: each container process, what it holds, and what its death means.

A system's instances with ``container = "C"`` are rclcpp components loaded into one ``iface_container``
process (``-r __node:=C``). The manager starts that process (``Host``) in the environment of the
instances' install folders, watched as an instance's process is (``processes.ExitWatcher``), and
loads each instance into it (``in_container.ContainerCalls.load``: its trust checked before the
container is asked, then configured, its last snapshot restored and activated in one LoadNode). The
container is a failure domain: when its process ends, every instance in it fails with the reason
``container_ended`` gives, each counted in its own ``restarts`` against its own intensity limit, and
the container is started again for those that are to be restarted, each loaded in start order with
its last snapshot. ``members`` says which instances a container holds, ``reload_order`` in which
order they come back. A replacement NEW that cannot share OLD's process goes into a second container
(``second_container``), named as ``second_container_name`` says, with the reason in the record.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from .containers import INDEX, Component, ContainerError, component_in, find_component, resource_lines
from .implementation import Implementation, install_prefixes
from .in_container import ContainerCalls
from .processes import InstanceProcess
from .standby import Standby


class Member(Protocol):
    """What this module needs of a managed instance."""

    container: str | None
    state: str

    @property
    def name(self) -> str: ...


@dataclass
class Host:
    """A container process the manager runs: its node name, the environment it runs in, its process and calls."""

    name: str
    env: dict[str, str] = field(repr=False)
    process: InstanceProcess | None = None
    calls: ContainerCalls | None = None
    #: Times its process was started again after it ended.
    restarts: int = 0
    #: Its spare process (an instance in it says ``standby = "true"``): ROS up, the container's node made when it
    #: is started again.
    standby: Standby = field(default_factory=Standby)

    def alive(self) -> bool:
        """Whether its process runs."""
        return self.process is not None and self.process.alive()

    @property
    def pid(self) -> int:
        """Its process id (0: none running)."""
        return self.process.pid if self.alive() and self.process is not None else 0


#: The states of an instance that a container's end brings down (the others are down already, or failed).
RUNNING = ("starting", "inactive", "active")


def container_argv(executable: str, name: str, standby: bool = False) -> list[str]:
    """The command line of the container process named ``name`` (a ``standby`` waits for SIGUSR1 to make its
    node)."""
    return [executable, *(["--standby"] if standby else []), "--ros-args", "-r", f"__node:={name}"]


def members(instances: Iterable[Any], container: str) -> list[Any]:
    """The instances loaded into ``container``, in start order."""
    return [m for m in instances if m.container == container]


def reload_order(instances: Iterable[Any], container: str) -> list[Any]:
    """The instances of ``container`` that its end brought down (running when it ended), in start order."""
    return [m for m in members(instances, container) if m.state in RUNNING]


def container_ended(container: str, pid: int, code: int | None) -> str:
    """The finding each instance of a container whose process ended is given (it names the container)."""
    how = f" (exit {code})" if code is not None else ""
    return f"container {container} (pid {pid}) ended{how}: every instance in it is restarted with its last snapshot"


def second_container_name(container: str, generation: int) -> str:
    """The node name of the container a replacement's NEW of ``generation`` gets when it cannot share OLD's."""
    return f"{container}_{generation}"


def second_container(container: str, name: str, problem: str) -> str:
    """The replacement record's reason for a second container."""
    return (f"NEW cannot share the process of container {container}: {problem}; NEW is loaded into a second "
            f"container {name} and handed over between the two processes")


def component_of(impl: Implementation, plugin: str | None, same_component: bool, env: dict[str, str]) -> Component:
    """The component a container loads for ``impl``: from its install folder when it has one (a replacement's),
    else from the first prefix of ``env`` that registers its package. ``plugin`` is the system file's class, used
    when ``impl`` is the system file's component; for another component, the one class its package registers."""
    prefix = None
    if impl.package_dir:
        prefix = next((p for p in install_prefixes(Path(impl.package_dir), impl.package)
                       if (p / INDEX / impl.package).is_file()), None)
        if prefix is None:
            raise ContainerError(f"{impl.package_dir} registers no rclcpp component of package {impl.package} (no "
                                 f"{INDEX}/{impl.package}): a container loads what `generate --target rclcpp` writes")
    if same_component and plugin:
        return component_in(prefix, impl.package, plugin) if prefix else find_component(impl.package, plugin, env)
    if prefix is None:
        raise ContainerError(f"no install folder for {impl.component}")  # pragma: no cover - a replacement has one
    classes = [cls for cls, _ in resource_lines(prefix / INDEX / impl.package)]
    if len(classes) != 1:
        raise ContainerError(f"package {impl.package} in {prefix} registers {len(classes)} components "
                             f"({', '.join(classes) or 'none'}): cannot tell which one is {impl.component}")
    return component_in(prefix, impl.package, classes[0])


def parameter_files(parameters: Path | None) -> tuple[Path, ...]:
    """The parameter files a container reads for an instance (its ``parameters`` annotation; a container does not
    read the package's installed ones, as ``ros2 run`` would not either without ``--params-file``)."""
    return (parameters,) if parameters is not None else ()


def ordered_down(instances: Sequence[Any]) -> list[Any]:
    """The order of ``down``: the reverse of start order (a container's instances unloaded before it stops)."""
    return list(reversed(instances))


__all__ = ["RUNNING", "Host", "Member", "component_of", "container_argv", "container_ended", "members",
           "ordered_down", "parameter_files", "reload_order", "second_container", "second_container_name"]
