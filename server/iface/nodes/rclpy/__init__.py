"""The ``rclpy`` target: a ROS 2 component package (ament_python) beside its interface package.

``iface-lsp generate robot_arm.iface --target rclpy --out src`` writes

- ``src/<interface package>/``: the ``ros2`` target's package;
- ``src/<component>/``: ``package.xml``, ``setup.py``, ``setup.cfg``, ``resource/``,
  ``config/<node>.params.yaml``, ``launch/<node>.launch.py``, ``<stem>.json`` (the interface as the
  ``json`` target writes it) and the Python package: ``base.py`` (the generated lifecycle-node base
  class), ``__main__.py`` (``python -m``), and ``node.py``, the user's module, written once and never
  overwritten;
- once for every component in the folder (``iface.nodes.shared``): ``src/iface_msgs/`` (the
  protocol's services) and ``src/iface_runtime_py/`` (the node machinery every component imports).

The steps are the node targets' one pipeline (``iface.nodes.pipeline``); this module says what Python
makes of them. How the interface becomes a node: ``iface.nodes.component`` and docs/runtime.md.

May import: what ``nodes`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit``,
``compat``) and the other modules of ``nodes``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...emit.ros2.render import xml
from ..layout import comment, fit
from ..pipeline import NodeLanguage, PackageFile
from ..usercode import check_user_module
from .render import PyPackage, build, doc_text, docstring, py

FILTERS: dict[str, Callable[..., Any]] = {"py": py, "doctext": doc_text, "docstring": docstring, "xml": xml,
                                          "fit": fit, "wrapped": comment}
#: The component package (``{pkg}``: its name): ``node.py`` is the user's.
FILES = (PackageFile("package.xml", "package.xml.j2", "<!--"), PackageFile("setup.py", "setup.py.j2", "#"),
         PackageFile("setup.cfg", "setup.cfg.j2", "#"), PackageFile("resource/{pkg}", "resource.j2", "#"),
         PackageFile("{pkg}/__init__.py", "init.py.j2", "#"), PackageFile("{pkg}/__main__.py", "main.py.j2", "#"),
         PackageFile("{pkg}/base.py", "base.py.j2", "#"), PackageFile("{pkg}/node.py", "node.py.j2", None))

LANGUAGE = NodeLanguage(target="rclpy", language="python", files=FILES, filters=FILTERS, start_command="python -m {pkg}",
                        view=build, check_user=check_user_module, runtime_depends=("iface_runtime_py", "rclpy"))
TARGET = LANGUAGE.target_descriptor()

__all__ = ["LANGUAGE", "TARGET", "PyPackage", "doc_text"]
