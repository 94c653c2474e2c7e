"""The ``rclcpp`` target: a ROS 2 component package (ament_cmake, C++) beside its interface package.

``iface-lsp generate robot_arm.iface --target rclcpp --out src`` writes

- ``src/<interface package>/``: the ``ros2`` target's package, as the ``rclpy`` target does
  (``iface.nodes.nodepkg``);
- ``src/iface_msgs/`` and ``src/iface_runtime_cpp/``, the shared packages (``iface.nodes.shared``;
  the library is the real package ``runtimes/iface_runtime_cpp``), once per output folder;
- ``src/<component>/``: ``package.xml``, ``CMakeLists.txt`` (a component library registered with
  ``rclcpp_components_register_node``, and the executable), ``config/<node>.params.yaml``,
  ``launch/<node>.launch.py``, ``include/<component>/base.hpp`` (the generated lifecycle-node base
  class), ``src/base.cpp``, ``src/main.cpp``, and ``src/node.cpp``, the user's class, written once and
  never overwritten.

The node is the rclpy target's node in C++: the same description (``iface.nodes.component``),
node and service names, command line, parameter checks and state document (docs/runtime.md).

May import: what ``runtime`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit``,
``compat``) and the other modules of ``runtime``.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ...emit.base import GeneratedFile, Result, Target, TemplateSet, header_lines, sorted_files
from ...emit.ros2 import TEMPLATES as ROS2_TEMPLATES
from ...emit.ros2 import render_package
from ...emit.ros2.render import FILTERS as ROS2_FILTERS
from ...emit.ros2.render import xml
from ...emit.json import generate as generate_json
from ...semantics.compile import Compilation
from .. import protocol
from ..codes import diag
from ..component import ComponentSpec
from ..nodepkg import launch_text, prepare, protocol_refs, read_user_file, types_only
from ..shared import shared_files
from .render import CppPackage, build, cpp_comment, cpp_double, cpp_str
from .usercode import check_user_source

TEMPLATES = Path(__file__).parent / "templates"
FILTERS: dict[str, Callable[..., Any]] = {"cpp": cpp_str, "cstr": lambda s: cpp_str(s)[1:-1], "comment": cpp_comment,
                                          "cppdouble": cpp_double, "xml": xml}
#: What every component package needs to build and run, beside the message packages it uses.
RUNTIME_DEPENDS = ("iface_runtime_cpp", "rclcpp", "rclcpp_action", "rclcpp_components", "rclcpp_lifecycle")
#: The user's file, relative to the component package.
USER_FILE = "src/node.cpp"


def component_files(spec: ComponentSpec, v: CppPackage, templates: TemplateSet, ros2: TemplateSet,
                    interface: GeneratedFile) -> list[GeneratedFile]:
    """The component package."""
    root = v.pkg
    header = header_lines("//", spec.source_name).rstrip("\n")
    hash_header = header_lines("#", spec.source_name).rstrip("\n")
    xml_header = header_lines("<!--", spec.source_name, end=" -->").rstrip("\n")
    origin = (spec.ros.name_source, spec.ros.node_span)
    msg_depends = sorted(set(spec.depends))
    ctx: dict[str, Any] = {
        "v": v, "header": header, "interface_file": interface.path,
        "depends": sorted(set(RUNTIME_DEPENDS) | set(msg_depends)),
        "cmake_depends": sorted(set(RUNTIME_DEPENDS) | set(msg_depends)), "msg_depends": msg_depends}

    def render(name: str, **extra: Any) -> str:
        return templates.render(name, **{**ctx, **extra})

    params_pkg = dataclasses.replace(spec.ros, node="/**")
    return [
        GeneratedFile(f"{root}/package.xml", render("package.xml.j2", header=xml_header), origin),
        GeneratedFile(f"{root}/CMakeLists.txt", render("CMakeLists.txt.j2", header=hash_header), origin),
        GeneratedFile(f"{root}/config/{v.params_file}", ros2.render("params.yaml.j2", package=params_pkg,
                                                                     header=hash_header), origin),
        GeneratedFile(f"{root}/launch/{v.launch_file}", launch_text(v, hash_header, f"ros2 run {root} {root}"),
                      origin),
        GeneratedFile(f"{root}/include/{root}/base.hpp", render("base.hpp.j2"), origin),
        GeneratedFile(f"{root}/src/base.cpp", render("base.cpp.j2"), origin),
        GeneratedFile(f"{root}/src/main.cpp", render("main.cpp.j2"), origin),
        GeneratedFile(f"{root}/{USER_FILE}", render("node.cpp.j2"), origin, once=True),
        GeneratedFile(f"{root}/{interface.path}", interface.text, origin),
    ]


def user_file_path(out: str, spec: ComponentSpec) -> str:
    """Where the user's file of ``spec`` is under the output folder ``out``."""
    return os.path.join(out, spec.package, *USER_FILE.split("/"))


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Both packages; with ``out`` in the options, the user's file there is checked against the interface."""
    result, pkg, spec = prepare(comp, "c++", shared_protocol=True)
    if pkg is None or spec is None:
        return result
    if types_only(spec):
        result.files = sorted_files(render_package(pkg, TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)))
        return result
    v = build(spec)
    if v.unsupported:
        state = comp.interface.state
        where = state[0].span if state else spec.ros.node_span
        result.diagnostics.append(diag(
            "runtime-unsupported", f"the state uses {', '.join(v.unsupported)} from another package: the rclcpp "
            "target writes the state document only for messages of the interface's own package (the rclpy target "
            "reads any)", comp.interface.source, where))
        return result
    ros2 = TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)
    templates = TemplateSet(TEMPLATES, "rclcpp", filters=FILTERS, override=options.get("templates"))
    out = options.get("out")
    if isinstance(out, str):
        path = user_file_path(out, spec)
        text = read_user_file(path)
        if text is not None:
            result.diagnostics.extend(check_user_source(spec, path, text, strict=bool(options.get("check"))))
    shared, result.notes = shared_files("rclcpp", out if isinstance(out, str) else None)
    result.files = sorted_files([*shared, *render_package(pkg, ros2),
                                 *component_files(spec, v, templates, ros2, generate_json(comp, {}).files[0])])
    return result


TARGET = Target(
    name="rclcpp",
    description="ROS 2 component package in C++ (rclcpp lifecycle node: parameters, QoS, state save/restore, "
                "diagnostics, launch file) beside its interface package",
    generate=generate,
    templates=str(TEMPLATES),
)

__all__ = ["TARGET", "generate"]
