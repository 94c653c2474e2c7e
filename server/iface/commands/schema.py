"""``iface-lsp schema``: print the JSON Schema (draft 2020-12) of the json target's output."""

from __future__ import annotations

import argparse
import sys

from ..forms.jsonform import schema_text

__all__ = ["schema_text", "add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The command takes no arguments."""


def run(args: argparse.Namespace) -> int:
    """Print the schema; exit 0."""
    sys.stdout.write(schema_text())
    return 0
