"""The manager tests' packages: the system's generated components, their test user modules, and ``iface_msgs``.

``iface_msgs`` is written here only when ``generate`` did not write it: a stand-in holding the
manager's types (``protocol.MANAGER_MESSAGES``/``MANAGER_SERVICES``) with the protocol's services.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from iface.runtime import protocol

from .ros import DATA, ROOT, generate

#: package → (interface, the tests' user module)
COMPONENTS = {
    "room_sensor": (ROOT / "examples" / "room_sensor.iface", DATA / "room_sensor_node.py"),
    "thermostat": (ROOT / "examples" / "thermostat.iface", DATA / "thermostat_node.py"),
}


def write_iface_msgs(gen: Path) -> None:
    """A minimal ament_cmake interface package ``iface_msgs`` with the manager's types (unless one is there)."""
    root = gen / "iface_msgs"
    if root.exists():
        return
    items = [*protocol.MANAGER_MESSAGES, *protocol.MANAGER_SERVICES, *protocol.SERVICES]
    files = []
    for item in items:
        kind = "msg" if isinstance(item, protocol.ProtocolMessage) else "srv"
        path = root / kind / f"{item.type_name}.{kind}"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(protocol.interface_text(item), encoding="utf-8")
        files.append(f"{kind}/{item.type_name}.{kind}")
    (root / "package.xml").write_text(
        '<?xml version="1.0"?>\n<package format="3">\n  <name>iface_msgs</name>\n  <version>0.1.0</version>\n'
        "  <description>iface protocol and manager types (test stand-in)</description>\n"
        '  <maintainer email="test@example.com">iface tests</maintainer>\n  <license>Apache-2.0</license>\n'
        "  <buildtool_depend>ament_cmake</buildtool_depend>\n"
        "  <buildtool_depend>rosidl_default_generators</buildtool_depend>\n"
        "  <exec_depend>rosidl_default_runtime</exec_depend>\n"
        "  <member_of_group>rosidl_interface_packages</member_of_group>\n"
        "  <export><build_type>ament_cmake</build_type></export>\n</package>\n", encoding="utf-8")
    listed = "\n".join(f'  "{f}"' for f in files)
    (root / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.8)\nproject(iface_msgs)\nfind_package(ament_cmake REQUIRED)\n"
        f"find_package(rosidl_default_generators REQUIRED)\nrosidl_generate_interfaces(${{PROJECT_NAME}}\n{listed}\n)\n"
        "ament_export_dependencies(rosidl_default_runtime)\nament_package()\n", encoding="utf-8")


def generate_system(gen: Path) -> None:
    """Generate every component with the tests' user module in place, and iface_msgs."""
    for package, (iface, user) in COMPONENTS.items():
        first = generate(iface, gen)
        assert first.returncode == 0, first.stderr
        shutil.copyfile(user, gen / package / package / "node.py")
    write_iface_msgs(gen)
