"""Plugins found through entry points: generation targets and importers."""

from __future__ import annotations

from importlib.metadata import entry_points
from typing import TypeVar

T = TypeVar("T")


def load(group: str, kind: type[T]) -> dict[str, T]:
    """Every entry point of ``group`` whose value is a ``kind``, by its ``name``, in name order.

    A plugin that fails to load is left out, so one broken third-party package
    cannot break the others.
    """
    found: dict[str, T] = {}
    for ep in sorted(entry_points(group=group), key=lambda e: e.name):
        try:
            obj = ep.load()
        except Exception:
            continue
        if isinstance(obj, kind):
            found[getattr(obj, "name")] = obj
    return found
