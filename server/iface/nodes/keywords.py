"""Keywords in a node target's interface package: what the ``ros2`` target warns about, refused where it breaks.

The ``ros2`` target only warns about keywords (``ros2-reserved-name``, ``ros2-python-keyword``):
its ``.msg`` files are valid and may be read by tools other than rosidl. A node target's packages
are built and run, so its own languages decide. rosidl_generator_cpp writes every name unchanged
into C++ headers that every ROS 2 package of messages compiles (the typesupports include them),
so a C/C++ keyword stops the interface package from building, whichever language the node is in.
rosidl_generator_py writes a Python keyword unchanged (``self.from = …``, ``class True``) and
its message module cannot be imported: the rclpy node imports it, the rclcpp node does not.
No spelling escapes these: the names are rosidl's, not the node's; the node code's own names
(accessors, aliases) are escaped where they are made.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from ..emit.ros2.keywords import check_keywords
from ..emit.ros2.package import RosPackage
from ..model.diagnostics import Diagnostic
from .codes import diag

#: The ``ros2`` codes a node target refuses, by the language of the node: C++ keywords break both.
_REFUSED = {"python": ("ros2-reserved-name", "ros2-python-keyword"), "c++": ("ros2-reserved-name",)}
_WHY = {"ros2-reserved-name": "is a C/C++ keyword: rosidl_generator_cpp writes it unchanged into the headers the "
                              "interface package compiles, so colcon cannot build it",
        "ros2-python-keyword": "is a Python keyword: rosidl_generator_py writes it unchanged and the message "
                               "module the rclpy node imports cannot be loaded"}


def node_keywords(language: str) -> Callable[[RosPackage], Iterator[Diagnostic]]:
    """The keyword check of the interface package for a node in ``language`` (``python`` or ``c++``)."""
    refused = _REFUSED[language]

    def check(pkg: RosPackage) -> Iterator[Diagnostic]:
        names: dict[tuple[str, int, int], str] = {}
        for what, _, source, span in pkg.identifiers():
            names.setdefault((source.path, span.start, span.end), what)
        for d in check_keywords(pkg):
            if d.code not in refused:
                yield d
                continue
            what = names.get((d.source.path, d.span.start, d.span.end), "the name")
            yield diag("runtime-reserved-name", f"{what} {_WHY[d.code]}; rename it", d.source, d.span)

    return check


__all__ = ["node_keywords"]
