"""Paths of the importer fixtures."""

from __future__ import annotations

from pathlib import Path

DATA = Path(__file__).parent / "data"
TESTS = Path(__file__).resolve().parents[1]
ROS2 = DATA / "ros2"
ROBOT_MSGS = ROS2 / "robot_msgs"
ROBOT_GEOMETRY = ROS2 / "robot_geometry"
BROKEN = DATA / "ros2_broken" / "broken_msgs"
GAPS = DATA / "ros2_emitter_gaps" / "gap_msgs"
PX4 = DATA / "px4" / "msg"
PX4_BROKEN = DATA / "px4_broken"
PX4_ACCEPTED = DATA / "px4_accepted" / "msg"


def ros_files(*packages: Path) -> list[Path]:
    """Every .msg/.srv/.action file of the packages."""
    return sorted(p for pkg in packages for kind in ("msg", "srv", "action") for p in (pkg / kind).glob(f"*.{kind}"))
