"""The interface packages the rclpy target writes (each component's and ``iface_msgs``) build with Debian's rosidl.

``../shared/ros2-build/build.sh`` compiles every message, service and action in C and C++ and runs a
program for each; it needs its apt packages (its README; .ci/run installs them) and skips without
them. The component packages are ament_python packages that need rclpy, which Debian does not ship:
they are built and run with the ROS 2 runtime (test_rclpy_e2e.py). The outcome comes from the test cache
when the same packages were built with the same script and Debian packages (tests/ros_harness/workspaces.py).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ..ros_harness.ros import generate, shared_dir
from ..ros_harness.workspaces import debian_build
from .conftest import COMPONENTS


def test_interface_packages_build_in_c_and_cpp(tmp_path: Path) -> None:
    shared = shared_dir()
    if shared is None or not (shared / "ros2-build" / "build.sh").is_file():
        pytest.skip("no ../shared/ros2-build (set IFACE_ROS2_SHARED): Debian's rosidl build is not available")
    gen = tmp_path / "gen"
    for iface, _ in COMPONENTS.values():
        done = generate(iface, gen)
        assert done.returncode == 0, done.stderr
    for package_xml in list(gen.glob("*/package.xml")):
        if "<build_type>ament_python</build_type>" in package_xml.read_text():
            shutil.rmtree(package_xml.parent)
    interface_packages = sorted(p.parent.name for p in gen.glob("*/package.xml"))
    # each component's interface package and the protocol's, written once beside them
    assert interface_packages == sorted([f"{name}_msgs" for name in COMPONENTS] + ["iface_msgs"]), interface_packages
    done = debian_build(gen)
    last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else done.stderr
    if done.returncode == 2:
        pytest.skip(f"Debian's rosidl is not installed ({last}): apt-get install the packages of "
                    "../shared/ros2-build/apt-packages.txt")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "ros2-build: OK:" in last and f"({len(interface_packages)} generated)" in last, last
    print(f"\n{last}")
