"""Diagnostics with stable codes, independent of any editor protocol."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

from .source import Source, Span


class Severity(IntEnum):
    """Severity, numbered as in LSP."""

    ERROR = 1
    WARNING = 2
    INFORMATION = 3
    HINT = 4

    @property
    def label(self) -> str:
        """The lower-case name used in CLI output."""
        return self.name.lower()


#: Every diagnostic code iface emits, with its default severity and a summary.
CODES: dict[str, tuple[Severity, str]] = {
    # input
    "syntax-error": (Severity.ERROR, "The text does not follow the grammar."),
    "invalid-encoding": (Severity.ERROR, "The file is not valid UTF-8."),
    "invalid-escape": (Severity.ERROR, "A string escape that stands for no character (a lone UTF-16 surrogate)."),
    "binary-file": (Severity.ERROR, "The file holds NUL bytes: not an interface file."),
    "file-too-large": (Severity.ERROR, "The file is larger than iface reads."),
    "empty-file": (Severity.INFORMATION, "The file defines nothing."),
    "cannot-read": (Severity.ERROR, "A file named on the command line that cannot be read (exit code 2)."),
    "nesting-too-deep": (Severity.ERROR, "Containers nested deeper than iface allows."),
    "too-many-findings": (Severity.INFORMATION, "The editor shows the first findings of a file only "
                          "(500): this one says how many more there are."),
    # names and references
    "unknown-type": (Severity.ERROR, "A type name that no definition, include or external package provides."),
    "duplicate-definition": (Severity.ERROR, "Two definitions with one name."),
    "duplicate-field": (Severity.ERROR, "Two fields or constants with one name in one body."),
    "duplicate-field-id": (Severity.ERROR, "Two fields with one id in one body."),
    "duplicate-enum-value": (Severity.ERROR, "Two enum values with one name or number."),
    "wrong-kind": (Severity.ERROR, "A name used where a different kind of definition is needed."),
    # values
    "invalid-default": (Severity.ERROR, "A default or constant value that its type cannot hold."),
    "int-out-of-range": (Severity.ERROR, "An integer outside the range of its type."),
    "number-out-of-range": (Severity.ERROR, "A number no type holds (an integer beyond 64 bits, a float beyond "
                            "float64 or float32) or a bound that is not a finite number."),
    "bounds-misuse": (Severity.ERROR, "A bound or array size that is not meaningful."),
    "invalid-field-id": (Severity.ERROR, "A field id outside 1..32767."),
    # files
    "include-not-found": (Severity.ERROR, "An include that names no readable file."),
    "include-cycle": (Severity.ERROR, "Files that include each other."),
    "include-error": (Severity.ERROR, "An included file has errors."),
    "include-too-deep": (Severity.ERROR, "Includes nested deeper than iface reads (1000 files); the message names "
                         "the chain."),
    # component interface
    "topic-type-conflict": (Severity.ERROR, "One topic used with two message types."),
    "duplicate-wiring": (Severity.WARNING, "The same wiring stated twice."),
    "invalid-topic-name": (Severity.ERROR, "A topic or service name that ROS 2 rejects."),
    "invalid-qos": (Severity.ERROR, "A QoS annotation with an unknown policy or a value ROS 2 cannot take."),
    "qos-not-in-rmw": (Severity.WARNING, "A QoS value of the DDS vocabulary that ROS 2 (rmw) has no setting for "
                       "(durability transient or persistent, liveliness manual_by_node): a generated node asks for "
                       "the nearest one (transient_local, manual_by_topic), as generate's runtime-qos-downgraded "
                       "says."),
    "include-not-interface": (Severity.ERROR, "An include that names a file which is not .iface or .thrift."),
    "recursive-type": (Severity.ERROR, "A type that contains itself, which ROS 2 and PX4 cannot represent."),
    "typedef-cycle": (Severity.ERROR, "Typedefs that stand for themselves: no type results."),
    "extends-cycle": (Severity.ERROR, "Services that extend themselves."),
    "service-part-missing": (Severity.ERROR, "A service or action without one of its parts."),
    "unknown-section": (Severity.ERROR, "A section name a service or action does not have."),
    "mixed-service-forms": (Severity.ERROR, "A service mixing Thrift functions with fields or sections."),
    "flat-service": (Severity.WARNING, "A service body of plain fields: read as request, then the last field as response."),
    "flat-action": (Severity.WARNING, "An action body of plain fields: read as goal, feedback, result."),
    "message-no-direction": (Severity.HINT, "A message that nobody publishes or subscribes: a type definition."),
    "implicit-provides": (Severity.HINT, "Services and actions provided under their own names because nothing is wired."),
    "diagnostics-service": (Severity.HINT, "An unwired diagnostics service: Δ, served under its own name."),
    "ros-naming": (Severity.WARNING, "A name that ROS 2 does not allow; it is converted when generating."),
    "ros-name-invalid": (Severity.ERROR, "A name that cannot be converted to a valid ROS 2 name."),
    "ros-constant-as-field": (Severity.WARNING, "An UPPER_CASE field with a default: ROS 2's constant spelling, a field in .iface."),
    "oneway-not-void": (Severity.ERROR, "A oneway function that returns a value or throws."),
    "throws-not-exception": (Severity.ERROR, "A throws clause naming a type that is not an exception."),
    "required-in-union": (Severity.WARNING, "A union field marked required."),
    "deprecated-syntax": (Severity.WARNING, "Syntax Thrift itself deprecates."),
    "duplicate-component": (Severity.ERROR, "More than one component declaration."),
    "param-range": (Severity.ERROR, "A configuration range that is malformed or excludes the default."),
    "missing-default": (Severity.INFORMATION, "A configuration parameter without a default value."),
    # system files
    "duplicate-system": (Severity.ERROR, "More than one system declaration."),
    "system-content": (Severity.ERROR, "A system file that also declares a component, definitions or wiring."),
    "instance-outside-system": (Severity.ERROR, "An instance in a file that declares no system."),
    "unknown-component": (Severity.ERROR, "An instance of a component that no included file declares."),
    "duplicate-instance": (Severity.ERROR, "Two instances with one name."),
    "duplicate-node-name": (Severity.ERROR, "Two instances that would run under one node name."),
    "unknown-instance-annotation": (Severity.ERROR, "An instance annotation iface does not know."),
    "invalid-instance-annotation": (Severity.ERROR, "An instance annotation with a value iface cannot use "
                                    "(restart, snapshot, node, package, executable, parameters, container, runtime, plugin, "
                                    "intra_process)."),
    "unknown-instance": (Severity.ERROR, "An `after` that names no instance of the system."),
    "instance-cycle": (Severity.ERROR, "Instances that start after each other."),
    "container-needs-rclcpp": (Severity.ERROR, "An instance in a container that runs its rclpy package: a container "
                               "loads rclcpp components."),
    "container-name-clash": (Severity.ERROR, "A container whose name is the node name of an instance or of the "
                             "component manager."),
}


@dataclass(eq=False)
class Related:
    """A second location that explains a diagnostic."""

    source: Source
    span: Span
    message: str


@dataclass(eq=False)
class Diagnostic:
    """One finding located in a source file."""

    code: str
    message: str
    source: Source
    span: Span
    severity: Severity = Severity.ERROR
    related: list[Related] = field(default_factory=list)
    data: dict[str, Any] = field(default_factory=dict)

    @property
    def path(self) -> str:
        """Path of the file the finding is in."""
        return self.source.path

    def location(self) -> tuple[int, int, int, int]:
        """1-based (line, column, end line, end column)."""
        line, col = self.source.position(self.span.start)
        eline, ecol = self.source.position(self.span.end)
        return line + 1, col + 1, eline + 1, ecol + 1

    def format(self, path: str | None = None) -> str:
        """The CLI text form ``path:line:col: severity[code]: message``."""
        line, col, _, _ = self.location()
        return f"{path or self.path}:{line}:{col}: {self.severity.label}[{self.code}]: {self.message}"

    def to_json(self, path: str | None = None) -> dict[str, Any]:
        """The CLI JSON form of the finding."""
        line, col, eline, ecol = self.location()
        return {
            "file": path or self.path,
            "line": line,
            "column": col,
            "end_line": eline,
            "end_column": ecol,
            "severity": self.severity.label,
            "code": self.code,
            "message": self.message,
        }


def make(code: str, message: str, source: Source, span: Span, *,
         severity: Severity | None = None, related: list[Related] | None = None,
         **data: Any) -> Diagnostic:
    """Build a diagnostic with the code's default severity."""
    return Diagnostic(code, message, source, span,
                      severity if severity is not None else CODES[code][0],
                      related or [], data)
