"""Remapping a node's names so that the rules hold on every ROS 2 release, actions included.

``--ros-args -r OLD:=NEW`` remaps topics and services on every release, but an action's name only
from Kilted on (rcl 10, ros2/rcl#1170): Jazzy's rcl 9.2 leaves the action where it was. An action is
three services and two topics under ``<name>/_action/``; rules for those five move it on both
releases (on Kilted beside the action's own rule, which renames them first: the five then match
nothing). The generated launch files and every tool that remaps an action use these rules.
"""

from __future__ import annotations

#: The services and topics of an action: what follows its name.
ACTION_PARTS = ("/_action/send_goal", "/_action/cancel_goal", "/_action/get_result", "/_action/feedback",
                "/_action/status")


def rules(name: str, to: str, action: bool = False) -> list[tuple[str, str]]:
    """The (from, to) rules that move ``name`` to ``to``: the name's own, and an action's five parts."""
    out = [(name, to)]
    if action:
        out += [(name + part, to + part) for part in ACTION_PARTS]
    return out


def arguments(name: str, to: str, action: bool = False) -> list[str]:
    """``rules`` as command-line arguments after ``--ros-args``: ``-r FROM:=TO`` each."""
    return [word for old, new in rules(name, to, action) for word in ("-r", f"{old}:={new}")]


__all__ = ["ACTION_PARTS", "arguments", "rules"]
