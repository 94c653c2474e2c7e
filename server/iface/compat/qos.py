"""QoS annotations (``qos.reliability = "reliable"`` …) and the ROS 2 / DDS matching rules.

A publisher *offers* and a subscriber *requests*; they match when, policy by
policy, the offer is at least as strong as the request:
reliability best_effort < reliable; durability volatile < transient_local
< transient < persistent; liveliness automatic < manual_by_node <
manual_by_topic; deadline and liveliness lease duration: a shorter period is
stronger. Unset policies take the ROS 2 defaults (reliable, volatile, infinite,
automatic, infinite). Depth, history and lifespan do not take part in matching.
"""

from __future__ import annotations

import math

from ..model.qos import ALIASES as _ALIASES
from ..model.qos import ORDERS, duration

#: Policies that take part in matching, with their ROS 2 defaults.
DURATIONS = ("deadline", "liveliness_lease_duration")
#: A policy's value: a level name (reliability, durability, liveliness) or a duration in seconds.
Policy = str | float
DEFAULTS: dict[str, Policy] = {"reliability": "reliable", "durability": "volatile", "liveliness": "automatic",
                               "deadline": math.inf, "liveliness_lease_duration": math.inf}


def policies(qos: dict[str, str]) -> dict[str, Policy]:
    """The matching-relevant policies with defaults filled in; unreadable values are left at the default."""
    out = dict(DEFAULTS)
    for key, raw in qos.items():
        key = _ALIASES.get(key, key)
        value = raw.strip().lower()
        if key in ORDERS:
            if value in ORDERS[key]:
                out[key] = value
        elif key in DURATIONS:
            d = duration(value)
            if d is not None:
                out[key] = d
    return out


def _stronger_or_equal(key: str, a: Policy, b: Policy) -> bool:
    """True when value ``a`` of policy ``key`` is at least as strong as ``b``."""
    if key in ORDERS:
        order = ORDERS[key]
        return order.index(str(a)) >= order.index(str(b))
    return float(a) <= float(b)


def _show(key: str, v: Policy) -> str:
    if key in DURATIONS:
        f = float(v)
        return "infinite" if f == math.inf else f"{f:g}s"
    return str(v)


def mismatches(offered: dict[str, str], requested: dict[str, str]) -> list[str]:
    """Why a publisher offering ``offered`` cannot match a subscriber requesting ``requested`` (empty: they match)."""
    o, r = policies(offered), policies(requested)
    out = []
    for key in (*ORDERS, *DURATIONS):
        if not _stronger_or_equal(key, o[key], r[key]):
            out.append(f"{key}: offered {_show(key, o[key])}, requested {_show(key, r[key])}")
    return out


def weakened(old: dict[str, str], new: dict[str, str], role: str) -> list[str]:
    """Policies in which NEW can match fewer peers than OLD (``role``: publishes or subscribes)."""
    o, n = policies(old), policies(new)
    out = []
    for key in (*ORDERS, *DURATIONS):
        if role == "publishes":
            ok = _stronger_or_equal(key, n[key], o[key])
            what = "offers"
        else:
            ok = _stronger_or_equal(key, o[key], n[key])
            what = "requests"
        if not ok:
            out.append(f"{key}: NEW {what} {_show(key, n[key])} where OLD {what} {_show(key, o[key])}")
    return out
