"""Diagnostic codes of the px4 target."""

from __future__ import annotations

from ...model.diagnostics import Severity
from ..base import CodeTable

CODES: dict[str, tuple[Severity, str]] = {
    "px4-unsupported-type": (Severity.ERROR, "A field or constant type uORB cannot hold (string, map, set, "
                             "union, nested array, …)."),
    "px4-variable-array": (Severity.ERROR, "A bounded or unbounded array: uORB has fixed arrays T[N] only."),
    "px4-default": (Severity.ERROR, "A default value on a message field: uORB messages have none."),
    "px4-external-type": (Severity.ERROR, "A type from an external package other than px4_msgs."),
    "px4-timestamp-added": (Severity.INFORMATION, "A message without 'uint64 timestamp' gets one, first."),
    "px4-timestamp-type": (Severity.ERROR, "A field named timestamp whose type is not u64."),
    "px4-name-invalid": (Severity.ERROR, "A name that cannot be made a uORB message, field or module name."),
    "px4-name-conflict": (Severity.ERROR, "Two definitions that become one uORB message name."),
    "px4-reserved-name": (Severity.ERROR, "A field or constant named like a C++ keyword (class, delete…), or a "
                          "component whose module class would redeclare a PX4 class (ModuleBase…): the C++ PX4 "
                          "builds would not compile."),
    "px4-topic-invalid": (Severity.ERROR, "A topic name with no uORB topic counterpart."),
    "px4-topic-assumed": (Severity.WARNING, "A topic of a px4_msgs type that is not a uXRCE-DDS bridge name "
                          "(/fmu/out/<topic>, /fmu/in/<topic>): the uORB topic is assumed to be the snake_case "
                          "message name."),
    "px4-topic-too-long": (Severity.WARNING, "A uORB topic name longer than 57 characters: PX4 builds it, but "
                           "its node path /obj/<topic><instance> does not fit in uORB's 64 bytes, so it cannot be "
                           "advertised."),
    "px4-queue-length": (Severity.WARNING, "An ORB_QUEUE_LENGTH constant that is not a uint8: PX4 builds it and "
                         "reads it as a uint8, as its own messages declare it."),
    "px4-queue-length-rounded": (Severity.WARNING, "An ORB_QUEUE_LENGTH that is not a power of two from 1 to 128: "
                                 "uORB reads it as a uint8 and rounds it."),
    "px4-constant-fraction": (Severity.WARNING, "A float constant with a fraction: PX4 builds it, but its generator "
                              "writes constants into the C++ header as int(value)."),
    "px4-topic-conflict": (Severity.ERROR, "One uORB topic used for two message types."),
    "px4-upstream-name": (Severity.WARNING, ("A message or topic with the name of one of PX4's own uORB messages "
                                             "or topics (the list shipped with iface, with its PX4 version).")),
    "px4-no-services": (Severity.WARNING, "PX4 has no services or actions: they are not generated."),
    "px4-no-state": (Severity.INFORMATION, "PX4 has no state set: state is not generated."),
    "px4-message-library": (Severity.INFORMATION, "No topic wired and no parameter: only the uORB messages are "
                            "generated, no module."),
    "px4-param-type": (Severity.ERROR, "A parameter type PX4 parameters cannot hold (INT32 and FLOAT only)."),
    "px4-param-precision": (Severity.WARNING, "A float64 parameter: PX4 stores FLOAT (32-bit)."),
    "px4-param-name-too-long": (Severity.ERROR, "A PX4 parameter name longer than 16 characters."),
    "px4-param-name-invalid": (Severity.ERROR, "A PX4 parameter name or prefix that is not UPPER_CASE."),
    "px4-param-name-conflict": (Severity.ERROR, "Two parameters with one PX4 name."),
    "px4-param-unit": (Severity.WARNING, "A parameter unit PX4's module.yaml does not accept: it is left out."),
    "px4-param-default": (Severity.ERROR, "A parameter default PX4 cannot state."),
    "px4-annotation": (Severity.ERROR, "A px4.work_queue, px4.interval_us or px4.increment annotation PX4 "
                       "cannot use."),
}

diag = CodeTable(CODES)
