"""The manager tests' packages: the system's generated components with their test user modules, and the
replacements by another implementation.

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
#: Another team's thermostat (component thermostat_pro, interface package thermostat_msgs): NEW of the manager's
#: replacements by another implementation. Built in a workspace of its own (its interface package has the
#: system thermostat's name).
PRO = (DATA / "thermostat_pro.iface", DATA / "thermostat_pro_node.py")


def generate_system(gen: Path) -> None:
    """Generate every component with the tests' user module in place (and iface_msgs beside them)."""
    for package, (iface, user) in COMPONENTS.items():
        first = generate(iface, gen)
        assert first.returncode == 0, first.stderr
        shutil.copyfile(user, gen / package / package / "node.py")
    assert (gen / "iface_msgs" / "srv" / "SystemStatus.srv").is_file(), "generate wrote no iface_msgs"


def generate_pro(folder: Path, gen: Path, component: str = "thermostat_pro",
                 interface_package: str = "thermostat_msgs") -> Path:
    """thermostat_pro as ``component`` with the interface package ``interface_package``: its file written into
    ``folder`` (beside room_sensor.iface, which it includes), its packages generated into ``gen`` with the tests'
    user module, and the interface package it depends on (room_sensor_msgs) beside them; the file."""
    iface, user = PRO
    names = {"thermostat_pro": component, "ThermostatPro": "".join(p.title() for p in component.split("_")),
             "thermostat_msgs": interface_package}
    text, code = iface.read_text(encoding="utf-8"), user.read_text(encoding="utf-8")
    for old, new in names.items():
        text, code = text.replace(f"component {old}" if old == "thermostat_pro" else old,
                                  f"component {new}" if old == "thermostat_pro" else new), code.replace(old, new)
    file = folder / f"{component}.iface"
    file.write_text(text, encoding="utf-8")
    done = generate(file, gen)
    assert done.returncode == 0, done.stderr
    # its workspace holds the interface package it depends on (room_sensor_msgs), as another team's would
    included = generate(folder / "room_sensor.iface", gen)
    assert included.returncode == 0, included.stderr
    shutil.rmtree(gen / "room_sensor")
    (gen / component / component / "node.py").write_text(code, encoding="utf-8")
    return file
