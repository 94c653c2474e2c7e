"""Targets found through the ``iface.targets`` entry point group."""

from __future__ import annotations

from importlib.metadata import entry_points
from typing import Any

from ..compile import Compilation
from .base import Result, Target

GROUP = "iface.targets"


def targets() -> dict[str, Target]:
    """Every installed target by name (entry point value: a ``Target`` object)."""
    found: dict[str, Target] = {}
    for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
        try:
            target = ep.load()
        except Exception:  # a broken third-party target must not break the others
            continue
        if isinstance(target, Target):
            found[target.name] = target
    return found


def get_target(name: str) -> Target | None:
    """The target called ``name``, if installed."""
    return targets().get(name)


def generate(comp: Compilation, target: str, **options: Any) -> Result:
    """Render ``comp`` for ``target``; an unknown target raises KeyError."""
    t = get_target(target)
    if t is None:
        raise KeyError(target)
    return t.generate(comp, options)
