"""The first step of both node targets: the interface package and the node's description; the launch file.

The rclpy and rclcpp targets both write the ``ros2`` target's interface package (the protocol's
types are the shared ``iface_msgs``) and a component package read from one ``ComponentSpec``
(``iface.nodes.pipeline`` runs the steps).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..emit.base import Result, TemplateSet
from ..emit.ros2.filenames import check_rosidl_names
from ..emit.ros2.lower import lower_run
from ..emit.ros2.package import RosPackage
from ..emit.ros2.render import check_msg_values
from ..semantics.compile import Compilation
from .codes import diag
from .component import ComponentSpec, describe
from .keywords import node_keywords
from .qosmap import check_downgrades
from .template_data import NodeView


def prepare(comp: Compilation, language: str) -> tuple[Result, RosPackage | None, ComponentSpec | None]:
    """The interface package and the node description; None and the findings on errors.

    ``language`` (``python`` or ``c++``) is the node's: it decides which keywords are refused. The node
    speaks the protocol through ``iface_msgs`` (written beside it by ``iface.nodes.shared``).
    """
    pkg, diagnostics, run = lower_run(comp, check_msg_values, node_keywords(language), check_rosidl_names)
    result = Result(diagnostics=diagnostics)
    if pkg is None or result.has_errors:
        return result, None, None
    spec, found = describe(comp, pkg, run)
    result.diagnostics.extend(found)
    result.diagnostics.extend(check_downgrades(spec))
    if result.has_errors:
        return result, None, None
    if types_only(spec):
        result.diagnostics.append(diag(
            "runtime-interface-package", f"'{spec.component}' wires nothing and has no parameter, state or "
            f"diagnostics: an interface package, so only {pkg.name}/ is written (no component package; wire a "
            "topic, service or action, or add parameters, for a node)", comp.interface.source,
            spec.ros.node_span))
    return result, pkg, spec


def types_only(spec: ComponentSpec) -> bool:
    """An interface package: nothing wired (nor provided by default), no parameter, state or Δ: a node of nothing."""
    return not spec.all_members() and not spec.params and not spec.state


def read_user_file(path: str) -> str | None:
    """The text of the user's file at ``path``; None when it is missing or unreadable."""
    if not os.path.isfile(path):
        return None
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except (OSError, UnicodeDecodeError):
        return None


#: Templates every node target renders the same way (the launch file).
TEMPLATES = Path(__file__).parent / "templates"


def launch_text(view: NodeView[Any], header: str, start_command: str, override: str | None = None) -> str:
    """``launch/<node>.launch.py``: the node, its parameter file, a launch argument per wired name."""
    templates = TemplateSet(TEMPLATES, "runtime", filters={"pystr": repr}, override=override)
    context: dict[str, Any] = {"v": view, "header": header, "start_command": start_command}
    return templates.render("launch.py.j2", **context)


__all__ = ["launch_text", "prepare", "read_user_file", "types_only"]
