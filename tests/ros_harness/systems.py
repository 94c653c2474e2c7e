"""The manager tests' packages: the system's generated components with their test user modules.

``generate`` writes ``iface_msgs`` (the protocol and the manager's types) beside them.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from .ros import DATA, ROOT, generate

#: package → (interface, the tests' user module)
COMPONENTS = {
    "room_sensor": (ROOT / "examples" / "room_sensor.iface", DATA / "room_sensor_node.py"),
    "thermostat": (ROOT / "examples" / "thermostat.iface", DATA / "thermostat_node.py"),
}


def generate_system(gen: Path) -> None:
    """Generate every component with the tests' user module in place (and iface_msgs beside them)."""
    for package, (iface, user) in COMPONENTS.items():
        first = generate(iface, gen)
        assert first.returncode == 0, first.stderr
        shutil.copyfile(user, gen / package / package / "node.py")
    assert (gen / "iface_msgs" / "srv" / "SystemStatus.srv").is_file(), "generate wrote no iface_msgs"
