"""The ``rclcpp`` target: a ROS 2 component package (ament_cmake, C++) beside its interface package.

``iface-lsp generate robot_arm.iface --target rclcpp --out src`` writes

- ``src/<interface package>/``: the ``ros2`` target's package, as the ``rclpy`` target does
  (``iface.nodes.nodepkg``);
- ``src/iface_msgs/`` and ``src/iface_runtime_cpp/``, the shared packages (``iface.nodes.shared``;
  the library is the real package ``runtimes/iface_runtime_cpp``), once per output folder;
- ``src/<component>/``: ``package.xml``, ``CMakeLists.txt`` (a component library registered with
  ``rclcpp_components_register_node``, and the executable), ``config/<node>.params.yaml``,
  ``launch/<node>.launch.py``, ``<stem>.json`` (the interface as the ``json`` target writes it),
  ``include/<component>/base.hpp`` (the generated lifecycle-node base class), ``src/base.cpp``,
  ``src/main.cpp``, and ``src/node.cpp``, the user's class, written once and never overwritten.

The steps are the node targets' one pipeline (``iface.nodes.pipeline``); this module says what C++
makes of them. The node is the rclpy target's node in C++: the same description
(``iface.nodes.component``), node and service names, command line, parameter checks and state
document (docs/runtime.md).

May import: what ``nodes`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit``,
``compat``) and the other modules of ``nodes``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...emit.ros2.render import xml
from ...model.diagnostics import Diagnostic
from ...semantics.compile import Compilation
from ..codes import diag
from ..layout import comment, fit
from ..pipeline import NodeLanguage, PackageFile
from ..template_data import NodeView
from .render import CppPackage, build, cpp_comment, cpp_double, cpp_str
from .usercode import check_user_source

FILTERS: dict[str, Callable[..., Any]] = {"cpp": cpp_str, "cstr": lambda s: cpp_str(s)[1:-1], "comment": cpp_comment,
                                          "cppdouble": cpp_double, "xml": xml, "fit": fit, "wrapped": comment}
#: The component package (``{pkg}``: its name): ``src/node.cpp`` is the user's.
FILES = (PackageFile("package.xml", "package.xml.j2", "<!--"), PackageFile("CMakeLists.txt", "CMakeLists.txt.j2", "#"),
         PackageFile("include/{pkg}/base.hpp", "base.hpp.j2", "//"), PackageFile("src/base.cpp", "base.cpp.j2", "//"),
         PackageFile("src/main.cpp", "main.cpp.j2", "//"), PackageFile("src/node.cpp", "node.cpp.j2", None))


def _refuse(view: NodeView[Any], comp: Compilation) -> list[Diagnostic]:
    """A state holding a message of another package: the C++ state document is written for the own package's."""
    assert isinstance(view, CppPackage)
    unsupported = view.unsupported
    if not unsupported:
        return []
    state = comp.interface.state
    where = state[0].span if state else view.spec.ros.node_span
    return [diag("runtime-unsupported", f"the state uses {', '.join(unsupported)} from another package: the rclcpp "
                 "target writes the state document only for messages of the interface's own package (the rclpy "
                 "target reads any)", comp.interface.source, where)]


LANGUAGE = NodeLanguage(target="rclcpp", language="c++", files=FILES, filters=FILTERS, refuse=_refuse,
                        start_command="ros2 run {pkg} {pkg}", view=build, check_user=check_user_source,
                        runtime_depends=("iface_runtime_cpp", "rclcpp", "rclcpp_action", "rclcpp_components",
                                         "rclcpp_lifecycle"), written_in=" in C++")
TARGET = LANGUAGE.target_descriptor()

__all__ = ["LANGUAGE", "TARGET"]
