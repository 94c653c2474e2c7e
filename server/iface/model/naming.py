"""Naming rules of the targets, and conversions to them."""

from __future__ import annotations

import re

_ROS_TYPE = re.compile(r"^[A-Z][A-Za-z0-9]*$")
_ROS_FIELD = re.compile(r"^(?!.*__)(?!.*_$)[a-z][a-z0-9_]*$")
_ROS_CONST = re.compile(r"^[A-Z](?!.*__)(?!.*_$)[A-Z0-9_]*$")
_WORDS = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+[0-9]*|[A-Z]+[0-9]*|[0-9]+")


def words(name: str) -> list[str]:
    """The words of an identifier in any case style."""
    return _WORDS.findall(name.replace(".", "_"))


def is_ros_type(name: str) -> bool:
    """True for a valid ROS 2 type name (CamelCase)."""
    return bool(_ROS_TYPE.match(name))


def is_ros_field(name: str) -> bool:
    """True for a valid ROS 2 field name (snake_case)."""
    return bool(_ROS_FIELD.match(name))


def is_ros_constant(name: str) -> bool:
    """True for a valid ROS 2 constant name (UPPER_CASE)."""
    return bool(_ROS_CONST.match(name))


def ros_type_name(name: str) -> str | None:
    """``message1`` → ``Message1``; None when no valid name results."""
    if is_ros_type(name):
        return name
    out = "".join(w[:1].upper() + w[1:] for w in words(name))
    return out if is_ros_type(out) else None


def ros_field_name(name: str) -> str | None:
    """``maxSpeed`` → ``max_speed``; None when no valid name results."""
    if is_ros_field(name):
        return name
    out = "_".join(w.lower() for w in words(name))
    return out if is_ros_field(out) else None


def ros_constant_name(name: str) -> str | None:
    """``maxSpeed`` → ``MAX_SPEED``; None when no valid name results."""
    if is_ros_constant(name):
        return name
    out = "_".join(w.upper() for w in words(name))
    return out if is_ros_constant(out) else None
