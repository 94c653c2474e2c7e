"""QoS values a ROS 2 node cannot ask for, the nearest it asks for instead, and the warning that says so.

``qos.durability = "transient"`` and ``"persistent"`` are DDS durabilities that rmw has no
setting for (``rmw_qos_durability_policy_t``: volatile, transient_local, best_available);
``qos.liveliness = "manual_by_node"`` is deprecated in rmw's ``types.h`` and gone from rclpy's
``LivelinessPolicy`` (rclpy 9.1.2, Kilted). The node targets give the node the nearest setting
rmw has and warn at the annotation (``runtime-qos-downgraded``).
"""

from __future__ import annotations

import math

from ..model import nodes as m
from ..model import qos as rules
from ..model.diagnostics import Diagnostic
from .codes import diag
from .component import ComponentSpec

def rmw_value(key: str, value: str) -> str:
    """The value a node asks rmw for ``qos.<key> = value`` (lower case, full policy name)."""
    return rules.DOWNGRADES.get((key, value), value)


def node_qos(qos: dict[str, str]) -> list[tuple[str, int | float | str]]:
    """A member's QoS as a node asks for it: depth a number, durations in seconds, other policies as rmw names them.

    Infinite or unreadable durations and ``system_default`` of the duration-like policies are left to rmw.
    """
    out: list[tuple[str, int | float | str]] = []
    for key, value in qos.items():
        if key == "depth":
            out.append((key, int(value)))
        elif key in rules.DURATIONS:
            seconds = rules.duration(value)
            if seconds is None or math.isinf(seconds):
                continue
            out.append((key, seconds))
        elif value != "system_default" or key in ("reliability", "durability", "history", "liveliness"):
            out.append((key, rmw_value(key, value)))
    return out


def check_downgrades(spec: ComponentSpec) -> list[Diagnostic]:
    """A warning at each QoS annotation of the members whose value a node cannot ask for."""
    out: list[Diagnostic] = []
    seen: set[int] = set()
    for member in spec.all_members():
        w: m.Wiring | None = member.wiring
        if w is None or id(w) in seen:
            continue
        seen.add(id(w))
        for a in w.annotations:
            if not a.key.startswith("qos."):
                continue
            message = rules.downgrade(a.key[4:], a.text)
            if message is not None:
                out.append(diag("runtime-qos-downgraded", message, member.source, a.span))
    return sorted(out, key=lambda d: (d.span.start, d.span.end))


DOWNGRADES = rules.DOWNGRADES

__all__ = ["DOWNGRADES", "check_downgrades", "node_qos", "rmw_value"]
