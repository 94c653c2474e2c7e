"""``iface-lsp targets``: the installed generation targets, one line each."""

from __future__ import annotations

import argparse

from ..emit.registry import targets


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The command takes no arguments."""


def run(args: argparse.Namespace) -> int:
    """Print ``name  description`` for every target found through the ``iface.targets`` entry points."""
    found = targets()
    width = max((len(n) for n in found), default=0)
    for name, target in sorted(found.items()):
        print(f"{name.ljust(width)}  {target.description}")
    return 0
