"""The QoS vocabulary of ROS 2 topics, shared by the checks and by compatibility.

Written as ``qos.<policy> = value`` annotations on wiring statements.
"""

from __future__ import annotations

import difflib
import math
import re

#: Policies whose values are ordered from weakest to strongest.
ORDERS: dict[str, tuple[str, ...]] = {
    "reliability": ("best_effort", "reliable"),
    "durability": ("volatile", "transient_local", "transient", "persistent"),
    "liveliness": ("automatic", "manual_by_node", "manual_by_topic"),
}
#: Policies whose values are durations.
DURATIONS = ("deadline", "liveliness_lease_duration", "lifespan")
ALIASES = {"lease_duration": "liveliness_lease_duration"}
HISTORY = ("keep_last", "keep_all")
#: (policy, value) of the DDS vocabulary rmw has no setting for → the nearest value a ROS 2 node asks for:
#: rmw's durabilities are volatile, transient_local and best_available (``rmw_qos_durability_policy_t``);
#: manual_by_node is deprecated in rmw's ``types.h`` and gone from rclpy's ``LivelinessPolicy`` (Kilted).
DOWNGRADES: dict[tuple[str, str], str] = {
    ("durability", "transient"): "transient_local",
    ("durability", "persistent"): "transient_local",
    ("liveliness", "manual_by_node"): "manual_by_topic",
}
_WHY = {"durability": "ROS 2 has no such durability (rmw's are volatile, transient_local, best_available)",
        "liveliness": "rmw marks it deprecated and rclpy's LivelinessPolicy no longer has it"}
KEYS = (*ORDERS, *DURATIONS, "history", "depth", *ALIASES)
_UNITS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
_DURATION = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)\s*(ns|us|ms|s)?\s*$")


def duration(text: str) -> float | None:
    """Seconds from ``"100ms"``, ``"0.5"`` (seconds) or ``"infinite"``; None when unreadable."""
    t = text.strip().lower()
    if t in ("", "infinite", "inf", "default", "system_default"):
        return math.inf
    mt = _DURATION.match(t)
    if mt is None:
        return None
    return float(mt.group(1)) * _UNITS[mt.group(2) or "s"]


def downgrade(key: str, value: str) -> str | None:
    """What ``check`` and the node targets say of ``qos.<key> = value`` when rmw has no such setting, else None."""
    key = ALIASES.get(key, key)
    v = value.strip().lower()
    given = DOWNGRADES.get((key, v))
    if given is None:
        return None
    return f"qos.{key} = {v}: {_WHY[key]}; the generated node asks for {given}"


def problem(key: str, value: str) -> tuple[bool, str] | None:
    """(is_error, message) when ``qos.<key> = value`` is not a ROS 2 QoS setting, else None."""
    if key not in KEYS:
        close = difflib.get_close_matches(key, KEYS, n=1)
        hint = f"; did you mean 'qos.{close[0]}'?" if close else f"; known: {', '.join(sorted(KEYS))}"
        return False, f"'qos.{key}' is not a QoS policy ROS 2 knows{hint}"
    key = ALIASES.get(key, key)
    v = value.strip().lower()
    if key in ORDERS:
        allowed = (*ORDERS[key], "system_default")
        if v not in allowed:
            return True, f"qos.{key} must be one of {', '.join(allowed)}, not '{value}'"
    elif key == "history":
        if v not in (*HISTORY, "system_default"):
            return True, f"qos.history must be keep_last, keep_all or system_default, not '{value}'"
    elif key == "depth":
        if not v.isdigit():
            return True, f"qos.depth must be a whole number of messages (0 or more), not '{value}'"
    elif duration(v) is None:
        return True, f"qos.{key} must be a duration like \"100ms\", \"0.5s\" or \"infinite\", not '{value}'"
    return None
