"""The ``rclpy`` target: a ROS 2 component package (ament_python) beside its interface package.

``iface-lsp generate robot_arm.iface --target rclpy --out src`` writes

- ``src/<interface package>/``: the ``ros2`` target's package plus the protocol services
  (``SaveState``, ``RestoreState``, ``ComponentControl``; ``iface.runtime.protocol``);
- ``src/<component>/``: ``package.xml``, ``setup.py``, ``setup.cfg``, ``resource/``,
  ``config/<node>.params.yaml``, ``launch/<node>.launch.py`` and the Python package:
  ``base.py`` (the generated lifecycle-node base class), ``_runtime.py`` and ``_contract.py``
  (the node machinery, the same for every component), ``__main__.py`` (``python -m``), and
  ``node.py``, the user's module, written once and never overwritten.

How the interface becomes a node: ``iface.runtime.component`` and docs/runtime.md.

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
from ...emit.ros2.filenames import check_rosidl_names
from ...emit.ros2.keywords import check_keywords
from ...emit.ros2.lower import lower_run
from ...emit.ros2.package import RosConst, RosField, RosInterface, RosPackage, RosSection, RosType
from ...emit.ros2.render import FILTERS as ROS2_FILTERS
from ...emit.ros2.render import check_msg_values, xml
from ...emit.support import component_span
from ...semantics.compile import Compilation
from .. import protocol
from ..component import ComponentSpec, describe
from ..usercode import check_user_module
from .render import PyPackage, build, doc_text, docstring, py

TEMPLATES = Path(__file__).parent / "templates"
FILTERS: dict[str, Callable[..., Any]] = {"py": py, "doctext": doc_text, "docstring": docstring, "xml": xml}
#: What every component package needs at run time, beside the message packages it uses.
RUNTIME_DEPENDS = ("ament_index_python", "diagnostic_msgs", "lifecycle_msgs", "rcl_interfaces", "rclpy")
#: The user's module, relative to the component package.
USER_MODULE = "node.py"


def _ros_type(text: str) -> RosType:
    if text.endswith("[]"):
        return RosType(primitive=text[:-2], array="unbounded")
    return RosType(primitive=text)


def add_protocol(pkg: RosPackage, comp: Compilation) -> None:
    """Put the protocol services into the interface package."""
    src = comp.interface.source
    span = component_span(comp.interface)
    for s in protocol.SERVICES:
        def section(name: str, fields: tuple[protocol.SrvField, ...],
                    consts: tuple[protocol.SrvConst, ...] = ()) -> RosSection:
            return RosSection(name, [RosField(f.name, _ros_type(f.type), None, [f.comment] if f.comment else [],
                                              src, span) for f in fields],
                              [RosConst(c.name, c.type, c.value, [c.comment] if c.comment else [], src, span)
                               for c in consts])
        pkg.interfaces.append(RosInterface("srv", s.type_name, [section("request", s.request, s.consts),
                                                                section("response", s.response)],
                                           list(s.doc), src, span))


def component_files(spec: ComponentSpec, templates: TemplateSet, ros2: TemplateSet) -> list[GeneratedFile]:
    """The component package."""
    v = build(spec)
    root = v.pkg
    header = header_lines("#", spec.source_name).rstrip("\n")
    xml_header = header_lines("<!--", spec.source_name, end=" -->").rstrip("\n")
    origin = (spec.ros.name_source, spec.ros.node_span)
    exec_depends = sorted(set(RUNTIME_DEPENDS) | set(spec.depends))
    ctx: dict[str, Any] = {"v": v, "header": header, "exec_depends": exec_depends,
                           "protocol": [v.name(r) for r in _protocol_refs(spec)],
                           "state_format": protocol.STATE_FORMAT, "handler_prefixes": _prefixes(),
                           "diagnostics_topic": protocol.DIAGNOSTICS_TOPIC,
                           "default_timeout": repr(protocol.DEFAULT_TIMEOUT_SEC),
                           "commands": ", ".join(str(c) for c in (protocol.STATUS, protocol.PAUSE, protocol.RESUME,
                                                                   protocol.SAVE))}

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
        GeneratedFile(f"{root}/launch/{v.launch_file}", render("launch.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/__init__.py", render("init.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/__main__.py", render("main.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/_contract.py", render("contract.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/_runtime.py", render("runtime.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/base.py", render("base.py.j2"), origin),
        GeneratedFile(f"{root}/{root}/{USER_MODULE}", render("node.py.j2"), origin, once=True),
    ]
    return files


def _protocol_refs(spec: ComponentSpec) -> list[Any]:
    from ..component import RosRef

    return [RosRef(spec.interface_package, "srv", s.type_name) for s in protocol.SERVICES]


def _prefixes() -> list[str]:
    from ..component import HANDLER_PREFIXES

    return list(HANDLER_PREFIXES)


def user_module_path(out: str, spec: ComponentSpec) -> str:
    """Where the user's module of ``spec`` is under the output folder ``out``."""
    return os.path.join(out, spec.package, spec.package, USER_MODULE)


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """Both packages; with ``out`` in the options, the user's module there is checked against the interface."""
    pkg, diagnostics, run = lower_run(comp, check_msg_values, check_keywords, check_rosidl_names)
    result = Result(diagnostics=diagnostics)
    if pkg is None or result.has_errors:
        return result
    spec, found = describe(comp, pkg, run)
    result.diagnostics.extend(found)
    if result.has_errors:
        return result
    add_protocol(pkg, comp)
    ros2 = TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)
    templates = TemplateSet(TEMPLATES, "rclpy", filters=FILTERS, override=options.get("templates"))
    out = options.get("out")
    if isinstance(out, str):
        path = user_module_path(out, spec)
        if os.path.isfile(path):
            try:
                with open(path, encoding="utf-8") as f:
                    text = f.read()
            except (OSError, UnicodeDecodeError):
                text = None
            if text is not None:
                result.diagnostics.extend(check_user_module(spec, path, text, strict=bool(options.get("check"))))
    result.files = sorted_files([*render_package(pkg, ros2), *component_files(spec, templates, ros2)])
    return result


TARGET = Target(
    name="rclpy",
    description="ROS 2 component package (rclpy lifecycle node: parameters, QoS, state save/restore, "
                "diagnostics, launch file) beside its interface package",
    generate=generate,
    templates=str(TEMPLATES),
)

__all__ = ["TARGET", "PyPackage", "doc_text", "generate"]
