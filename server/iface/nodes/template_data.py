"""What the templates of both node targets read of a component: its names, files, type aliases and members."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Generic, Protocol, TypeVar

from ..emit.text import one_line
from .component import ComponentSpec, Member, ParamSpec, RosRef
from .remap import ACTION_PARTS


@dataclass
class MemberView:
    """A member as a node target's templates write it: its type's local name, its QoS and doc lines as the
    language writes them, and what it is (``subscribes M on /x``), made safe for the language's comments."""

    m: Member
    type: str
    qos: str
    doc: list[str]
    what: str


class _MemberView(Protocol):
    m: Member


V = TypeVar("V", bound=_MemberView)


def type_aliases(spec: ComponentSpec, taken: Iterable[str],
                 reserved: Callable[[str], bool] = lambda _: False) -> dict[RosRef, str]:
    """A local name for every interface type the node uses: its own name, or, where that is taken, reserved
    or the node's own class names, the package's CamelCase name before it (``SensorMsgsImage``)."""
    own = {f"{spec.class_name}Base", f"{spec.class_name}Parameters", spec.class_name, *taken}
    used: dict[str, RosRef] = {}
    out: dict[RosRef, str] = {}
    for ref in spec.types():
        alias = ref.name
        if alias in used or alias in own or reserved(alias):
            alias = "".join(w[:1].upper() + w[1:] for w in ref.package.split("_")) + ref.name
        while alias in used:
            alias += "_"
        used[alias] = ref
        out[ref] = alias
    return out


#: The launch arguments every component launch file declares besides one per wired name.
LAUNCH_ARGUMENTS = ("params_file", "namespace", "node_name")


def remappings(spec: ComponentSpec) -> list[tuple[str, str, bool]]:
    """(name, launch argument, whether it is an action) for each wired name that can be remapped."""
    out: list[tuple[str, str, bool]] = []
    seen: set[str] = set()
    for m in spec.all_members():
        name = m.name
        if name.startswith("~") or name in (n for n, _, _ in out):
            continue
        arg = m.slug if m.slug not in seen else m.full_slug
        while arg in seen or arg in LAUNCH_ARGUMENTS:
            arg += "_"
        seen.add(arg)
        out.append((name, arg, m.kind in ("action_server", "action_client")))
    return out


@dataclass
class NodeView(Generic[V]):
    """The part of a node package's view that does not depend on the client library."""

    spec: ComponentSpec
    source_name: str
    aliases: dict[RosRef, str] = field(default_factory=dict)
    members: list[V] = field(default_factory=list)

    #: ``rclpy`` or ``rclcpp``, as the package's description names it.
    client_library = ""

    @property
    def pkg(self) -> str:
        return self.spec.package

    @property
    def cls(self) -> str:
        return self.spec.class_name

    @property
    def description(self) -> str:
        return (f"The {self.spec.component} component: a ROS 2 lifecycle node ({self.client_library}) generated "
                f"by iface from {self.source_name}.")

    @property
    def params_file(self) -> str:
        return f"{self.spec.node}.params.yaml"

    @property
    def launch_file(self) -> str:
        return f"{self.spec.node}.launch.py"

    def name(self, ref: RosRef) -> str:
        return self.aliases[ref]

    def of_kind(self, *kinds: str) -> list[V]:
        return [v for v in self.members if v.m.kind in kinds]

    def remappings(self) -> list[tuple[str, str, bool]]:
        """(name, launch argument, whether it is an action) for each wired name that can be remapped."""
        return remappings(self.spec)

    @property
    def action_parts(self) -> tuple[str, ...]:
        """The five names of an action relative to it, which a launch file remaps on every release."""
        return ACTION_PARTS

    def comment(self, text: str) -> str:
        """``text`` on one line, safe inside the language's comments and docstrings (the language's view says how)."""
        return one_line(text)

    def param_doc(self, p: ParamSpec) -> str:
        """A parameter's description, its constraints and whether it is read-only, for its accessor's doc."""
        parts = [p.description]
        if p.constraints:
            parts.append(f"({p.constraints})")
        if p.read_only:
            parts.append("Read-only.")
        return self.comment(" ".join(parts))


__all__ = ["MemberView", "NodeView", "remappings", "type_aliases"]
