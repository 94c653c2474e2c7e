"""``iface-lsp schema``: print the JSON Schema (draft 2020-12) of the json target's output."""

from __future__ import annotations

import argparse
import sys
from importlib.resources import files


def schema_text() -> str:
    """The schema file shipped with the package."""
    return files("iface").joinpath("schema/iface.schema.json").read_text(encoding="utf-8")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The command takes no arguments."""


def run(args: argparse.Namespace) -> int:
    """Print the schema; exit 0."""
    sys.stdout.write(schema_text())
    return 0
