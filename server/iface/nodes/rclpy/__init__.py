"""The ``rclpy`` target: a ROS 2 component package (ament_python) beside its interface package.

``iface-lsp generate robot_arm.iface --target rclpy --out src`` writes

- ``src/<interface package>/``: the ``ros2`` target's package;
- ``src/<component>/``: ``package.xml``, ``setup.py``, ``setup.cfg``, ``resource/``,
  ``config/<node>.params.yaml``, ``launch/<node>.launch.py`` and the Python package:
  ``base.py`` (the generated lifecycle-node base class), ``__main__.py`` (``python -m``), and
  ``node.py``, the user's module, written once and never overwritten;
- once for every component in the folder (``iface.nodes.shared``): ``src/iface_msgs/`` (the
  protocol's services) and ``src/iface_runtime_py/`` (the node machinery every component imports).

How the interface becomes a node: ``iface.nodes.component`` and docs/runtime.md.

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
from ...emit.json import generate as generate_json
from ...emit.ros2 import TEMPLATES as ROS2_TEMPLATES
from ...emit.ros2 import render_package
from ...emit.ros2.render import FILTERS as ROS2_FILTERS
from ...emit.ros2.render import xml
from ...semantics.compile import Compilation
from ..component import ComponentSpec
from ..shared import shared_files
from ..nodepkg import add_protocol, launch_text, prepare, read_user_file, types_only
from ..usercode import check_user_module
from .render import PyPackage, build, doc_text, docstring, py

TEMPLATES = Path(__file__).parent / "templates"
FILTERS: dict[str, Callable[..., Any]] = {"py": py, "doctext": doc_text, "docstring": docstring, "xml": xml}
#: What every component package needs at run time, beside the message packages it uses.
RUNTIME_DEPENDS = ("iface_runtime_py", "rclpy")
#: The user's module, relative to the component package.
USER_MODULE = "node.py"


def component_files(spec: ComponentSpec, templates: TemplateSet, ros2: TemplateSet,
                    interface: GeneratedFile) -> list[GeneratedFile]:
    """The component package."""
    v = build(spec)
    root = v.pkg
    header = header_lines("#", spec.source_name).rstrip("\n")
    xml_header = header_lines("<!--", spec.source_name, end=" -->").rstrip("\n")
    origin = (spec.ros.name_source, spec.ros.node_span)
    exec_depends = sorted(set(RUNTIME_DEPENDS) | set(spec.depends))
    ctx: dict[str, Any] = {"v": v, "header": header, "exec_depends": exec_depends,
                           "interface_file": interface.path}

    def render(name: str, **extra: Any) -> str:
        return templates.render(name, **{**ctx, **extra})

    params_pkg = dataclasses.replace(spec.ros, node="/**")
    files = [
        GeneratedFile(f"{root}/package.xml", render("package.xml.j2", header=xml_header), origin),
        GeneratedFile(f"{root}/setup.py", render("setup.py.j2"), origin),
        GeneratedFile(f"{root}/setup.cfg", render("setup.cfg.j2"), origin),
        GeneratedFile(f"{root}/resource/{root}", render("resource.j2"), origin),
        GeneratedFile(f"{root}/config/{v.params_file}", ros2.render("params.yaml.j2", package=params_pkg,
                                                                     header=header), origin),
        GeneratedFile(f"{root}/launch/{v.launch_file}", launch_text(v, header, f"python -m {root}"), origin),
        GeneratedFile(f"{root}/{root}/__init__.py", render("init.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/__main__.py", render("main.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/base.py", render("base.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/{USER_MODULE}", render("node.py.j2"), origin, once=True),
        GeneratedFile(f"{root}/{interface.path}", interface.text, origin),
    ]
    return files


def user_module_path(out: str, spec: ComponentSpec) -> str:
    """Where the user's module of ``spec`` is under the output folder ``out``."""
    return os.path.join(out, spec.package, spec.package, USER_MODULE)


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Both packages; with ``out`` in the options, the user's module there is checked against the interface."""
    result, pkg, spec = prepare(comp, "python", shared_protocol=True)
    if pkg is None or spec is None:
        return result
    if types_only(spec):
        result.files = sorted_files(render_package(pkg, TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)))
        return result
    ros2 = TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)
    templates = TemplateSet(TEMPLATES, "rclpy", filters=FILTERS, override=options.get("templates"))
    out = options.get("out")
    if isinstance(out, str):
        path = user_module_path(out, spec)
        text = read_user_file(path)
        if text is not None:
            result.diagnostics.extend(check_user_module(spec, path, text, strict=bool(options.get("check"))))
    shared, result.notes = shared_files("rclpy", out if isinstance(out, str) else None)
    result.files = sorted_files([*shared, *render_package(pkg, ros2), *component_files(spec, templates, ros2, generate_json(comp, {}).files[0])])
    return result


TARGET = Target(
    name="rclpy",
    description="ROS 2 component package (rclpy lifecycle node: parameters, QoS, state save/restore, "
                "diagnostics, launch file) beside its interface package",
    generate=generate,
    templates=str(TEMPLATES),
)

__all__ = ["TARGET", "PyPackage", "add_protocol", "doc_text", "generate"]
