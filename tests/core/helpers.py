"""Helpers for the core tests."""

from __future__ import annotations

import re
from pathlib import Path

from iface.semantics.compile import Compilation, Workspace

DATA = Path(__file__).parent / "data"
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
EXPECT = re.compile(r"expect: ([a-z0-9-]+(?:\s*,\s*[a-z0-9-]+)*)")


def compile_file(path: Path | str) -> Compilation:
    """Compile a file with a fresh workspace."""
    return Workspace().compile_path(str(path))


def expectations(path: Path) -> set[tuple[int, str]]:
    """(1-based line, code) pairs marked in a fixture with ``// expect: code``."""
    out = set()
    for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        m = EXPECT.search(line)
        if m:
            for code in m.group(1).split(","):
                out.add((i, code.strip()))
    return out


#: A system of the examples' components: three instances, every annotation, a parameter file.
HOME = """/** The examples' living room, with two sensors and parameters. */
system home version "0.2.0"
include "room_sensor.iface"
include "thermostat.iface"

instance hall : room_sensor (node = "hall_sensor", restart = "always")
instance kitchen : room_sensor (snapshot = "500ms", parameters = "kitchen.yaml")
instance heating : thermostat (after = "kitchen", after = "hall", restart = "never")
"""
KITCHEN_YAML = """/**:
  ros__parameters:
    rate_hz: 5.0
"""


def write_home(folder: Path) -> Path:
    """``home.iface`` (``HOME``) in ``folder``, beside copies of the components it includes and its parameter
    file; its path. Written where a test wants it, so the sweeps over the files of tests/ do not run it."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in ("room_sensor.iface", "thermostat.iface"):
        (folder / name).write_text((EXAMPLES / name).read_text(encoding="utf-8"), encoding="utf-8")
    (folder / "kitchen.yaml").write_text(KITCHEN_YAML, encoding="utf-8")
    path = folder / "home.iface"
    path.write_text(HOME, encoding="utf-8")
    return path
