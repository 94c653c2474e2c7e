"""Diagnostic codes of the component (node) targets."""

from __future__ import annotations

from ..emit.base import CodeTable
from ..emit.ros2.codes import CODES as ROS2_CODES
from ..model.diagnostics import CODES as CORE_CODES
from ..model.diagnostics import Severity

CODES: dict[str, tuple[Severity, str]] = {
    "runtime-annotation": (Severity.ERROR, "An annotation the node generators read (a diagnostics rate, "
                           "read_only) with a value they cannot use."),
    "runtime-interface-package": (Severity.INFORMATION, "A component that wires nothing and has no parameter, "
                                  "state or diagnostics (an interface package, as `import --from ros2` writes "
                                  "one): only its interface package is written, no component package."),
    "runtime-name-clash": (Severity.ERROR, "A definition named like a service of the component protocol "
                           "(SaveState, RestoreState, ComponentControl), or two members whose handlers would "
                           "get one name."),
    "runtime-qos-downgraded": (Severity.WARNING, "A QoS value ROS 2 (rmw) has no setting for (durability "
                               "transient or persistent, liveliness manual_by_node): the node asks for the "
                               "nearest one it has (transient_local, manual_by_topic)."),
    "runtime-reserved-name": (Severity.ERROR, "A name of the interface package that the node's packages cannot "
                              "be built or run with: a C/C++ keyword (both node targets), a Python keyword "
                              "(the rclpy target)."),
    "runtime-unsupported": (Severity.ERROR, "What one node target cannot generate yet (the rclcpp target: a "
                            "state that uses a message of another package)."),
    "runtime-user-code": (Severity.WARNING, "The user module of a generated component no longer matches the "
                          "interface: a handler is missing, takes other arguments, or handles nothing "
                          "(an error with `generate --check`)."),
}

diag = CodeTable(CODES, {**CORE_CODES, **ROS2_CODES})
