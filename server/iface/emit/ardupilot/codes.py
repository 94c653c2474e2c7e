"""Diagnostic codes of the ardupilot target."""

from __future__ import annotations

from ...model.diagnostics import Severity
from ..base import CodeTable

CODES: dict[str, tuple[Severity, str]] = {
    "ap-name-invalid": (Severity.ERROR, "A component name that cannot be made a C++ class name."),
    "ap-reserved-name": (Severity.ERROR, "A package, message, field or constant named like a C or C++ keyword "
                         "(class, delete…): the code built from the IDL would not compile."),
    "ap-no-actions": (Severity.WARNING, "AP_DDS has no actions: they are not generated."),
    "ap-param-unsupported-type": (Severity.WARNING, "A parameter type AP_Param cannot hold: left out of the table."),
    "ap-param-precision": (Severity.WARNING, "A float64 parameter: AP_Float is 32-bit."),
    "ap-param-name-too-long": (Severity.ERROR, "An ArduPilot parameter name over 16 characters."),
    "ap-param-name-invalid": (Severity.ERROR, "An ArduPilot parameter name or prefix that is not UPPER_CASE."),
    "ap-param-name-conflict": (Severity.ERROR, "Two parameters with one ArduPilot name."),
    "ap-param-index-implicit": (Severity.WARNING, "A parameter without a field id or ap.index: its index follows "
                                "the declaration order and changes when parameters are inserted before it."),
    "ap-param-index-range": (Severity.ERROR, "An AP_Param group index outside 0..63."),
    "ap-param-index-conflict": (Severity.ERROR, "Two parameters with one AP_Param index."),
    "ap-param-default": (Severity.ERROR, "A parameter default AP_Param cannot state."),
    "ap-param-enable-type": (Severity.ERROR, "A parameter named ENABLE (the group's enable switch) that is not an "
                             "AP_Int8 (bool or i8): AP_Param honours AP_PARAM_FLAG_ENABLE on AP_Int8 only."),
    "ap-param-units": (Severity.WARNING, "A unit that is not one of ArduPilot's unit names: @Units is left out "
                       "(ArduPilot's param_parse.py refuses unknown units)."),
    "ap-param-annotation": (Severity.ERROR, "An ap.increment, ap.values, ap.bitmask, ap.user or ap.reboot_required "
                            "annotation ArduPilot's parameter documentation cannot state."),
    "ap-dds-qos-unsupported": (Severity.WARNING, "A QoS policy AP_DDS cannot carry: uxrQoS_t holds durability, "
                               "reliability, history and depth only."),
    "ap-dds-qos-depth": (Severity.ERROR, "A qos.depth over 65535: AP_DDS keeps it in a uint16_t."),
    "ap-dds-too-many": (Severity.ERROR, "More than 256 topics or services: AP_DDS numbers them with uint8_t."),
}

diag = CodeTable(CODES)
