"""Independent parsers of generated files, used as oracles by the emitter tests.

- ROS 2's own .msg/.srv/.action parser (rosidl_adapter, vendored in ``mcap-ros2-support``);
- ``rosbags`` (``get_types_from_msg``, ``get_types_from_idl``);
- ``catkin_pkg`` for package.xml; PyYAML for YAML.
"""

from __future__ import annotations

import re
from typing import Any

import yaml
from catkin_pkg.package import Package, parse_package_string
from mcap_ros2._vendor.rosidl_adapter import parser as rosidl
from rosbags.typesys import get_types_from_idl, get_types_from_msg

_SEPARATOR = re.compile(r"^---$", re.MULTILINE)
_PARTS = {"msg": ("",), "srv": ("_Request", "_Response"), "action": ("_Goal", "_Result", "_Feedback")}


def rosidl_parse(text: str, package: str, kind: str, name: str) -> list[rosidl.MessageSpecification]:
    """The message specifications rosidl reads from a .msg/.srv/.action text (one per part)."""
    if kind == "msg":
        return [rosidl.parse_message_string(package, name, text)]
    if kind == "srv":
        spec = rosidl.parse_service_string(package, name, text)
        return [spec.request, spec.response]
    spec = rosidl.parse_action_string(package, name, text)
    return [spec.goal, spec.result, spec.feedback]


def rosbags_parse(text: str, package: str, kind: str, name: str) -> list[dict[str, Any]]:
    """What rosbags reads from each part of a .msg/.srv/.action text, as ``{typename: (consts, fields)}``."""
    parts = _SEPARATOR.split(text)
    if len(parts) != len(_PARTS[kind]):
        raise ValueError(f"{kind} text has {len(parts)} parts")
    out = []
    for part, suffix in zip(parts, _PARTS[kind]):
        body = part.lstrip("\n") if part.startswith("\n") else part
        out.append(dict(get_types_from_msg(body, f"{package}/msg/{name}{suffix}")))
    return out


def rosbags_idl(text: str) -> dict[str, Any]:
    """What rosbags reads from an .idl text (``#include`` lines are the preprocessor's, so dropped)."""
    body = "\n".join("" if line.startswith("#include") else line for line in text.splitlines())
    return dict(get_types_from_idl(body + "\n"))


def catkin_package(text: str) -> Package:
    """package.xml parsed and validated by catkin_pkg."""
    pkg = parse_package_string(text)
    pkg.validate()
    return pkg


def load_yaml(text: str) -> Any:
    """YAML loaded safely."""
    return yaml.safe_load(text)
