"""Diagnostic codes of the ROS 2 and IDL targets, and a helper to build them."""

from __future__ import annotations

from ...model.diagnostics import CODES as CORE_CODES
from ...model.diagnostics import Severity
from ..base import CodeTable

#: Codes this package reports, with their severity and a summary (core codes are reused as they are).
CODES: dict[str, tuple[Severity, str]] = {
    "ros2-unsupported": (Severity.ERROR, "A construct ROS 2 interfaces cannot express "
                         "(union, senum, map, set, nested arrays, throws, a non-constant top-level const…)."),
    "ros2-hash-in-string": (Severity.ERROR, "A string default or constant containing '#': "
                            "ROS 2 parsers read the rest of the line as a comment."),
    "ros2-unwritable-string": (Severity.ERROR, "A string default or constant a .msg line cannot hold "
                               "(line break, control character, '=' in a field default, quotes in an array)."),
    "ros2-unsupported-default": (Severity.ERROR, "A default ROS 2 cannot state (on a nested message, "
                                 "a map, a value of the wrong kind)."),
    "ros2-name-clash": (Severity.ERROR, "Two names that become the same after conversion to ROS 2 rules."),
    "ros2-reserved-name": (Severity.WARNING, "A package, message, field or constant named like a C or C++ keyword "
                           "(class, delete, restrict…): rosidl's C++ code for it does not compile."),
    "ros2-python-keyword": (Severity.WARNING, "A name that is a Python keyword (from, lambda…): rosidl_generator_py "
                            "does not support it; the Python module cannot be imported."),
    "ros2-name-too-long": (Severity.ERROR, "A type name whose rosidl-generated file names would be longer than "
                           "file systems allow."),
    "ros2-param-type": (Severity.ERROR, "A configuration field whose type a ROS 2 parameter cannot have "
                        "(a message, map, set, nested array)."),
    "ros2-param-value": (Severity.ERROR, "A parameter default ROS 2 cannot hold: an integer outside int64."),
    "ros2-param-empty-list": (Severity.WARNING, "An empty list as a parameter default, which ROS 2 cannot load "
                              "from YAML: written as a comment (no default)."),
    "ros2-param-uint64": (Severity.WARNING, "A u64 parameter: ROS 2 integer parameters are int64."),
    "ros2-package-metadata": (Severity.WARNING, "A component version or maintainer e-mail package.xml "
                              "cannot hold; a neutral value is written instead."),
    "ros2-package-metadata-missing": (Severity.WARNING, ("A component without a license or a maintainer: "
                                                         "package.xml gets the placeholders TODO and unknown.")),
    "idl-unwritable-string": (Severity.ERROR, "A string default or constant with a backslash, "
                              "which IDL readers decode differently."),
    "idl-escaped-name": (Severity.WARNING, "A package, message, field or constant name that collides with an OMG "
                         "IDL keyword (struct, DEFAULT…), written with IDL's escape (_struct), which ROS 2's "
                         "IDL readers do not take."),
    "idl-reserved-name": (Severity.ERROR, "ardupilot: a field whose type is a message named like an OMG IDL "
                          "keyword, a reference Fast-DDS-Gen cannot resolve escaped and others refuse unescaped."),
}


#: A diagnostic with one of this package's codes or a core code, at its default severity.
diag = CodeTable(CODES, CORE_CODES)
