"""Plugins found through entry points: generation targets and importers."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable, Iterable
from importlib.metadata import EntryPoint, entry_points
from typing import Any, TypeVar

T = TypeVar("T")


def load(group: str, kind: type[T]) -> dict[str, T]:
    """Every entry point of ``group`` whose value is a ``kind``, by its ``name``, in name order.

    A plugin that fails to load is left out, so one broken third-party package
    cannot break the others. The installed distributions are read once per search path
    (``sys.path``): a plugin installed while a process runs is found by the next process.
    """
    found: dict[str, T] = {}
    for name, obj in _loaded(group, entry_points, tuple(sys.path)):
        if isinstance(obj, kind):
            found[name] = obj
    return found


@functools.lru_cache(maxsize=16)
def _loaded(group: str, find: Callable[..., Iterable[EntryPoint]], path: tuple[str, ...]) -> tuple[tuple[str, Any], ...]:
    """(name, loaded value) of each entry point of ``group`` that loads, in name order (``path``: the cache key)."""
    out = []
    for ep in sorted(find(group=group), key=lambda e: e.name):
        try:
            out.append((ep.name, ep.load()))
        except Exception:  # noqa: BLE001, S112 - a plugin that fails to load is left out
            continue
    return tuple(out)
