"""AP_Param documentation fields from annotations, checked as ArduPilot's param_parse.py checks them.

``@Units`` must be one of ArduPilot's unit names (``units.json``, from
``Tools/autotest/param_metadata/param.py`` ``known_units``); the ``ap.*`` annotations give
``@Increment``, ``@Values``, ``@Bitmask``, ``@User`` and ``@RebootRequired``.
"""

from __future__ import annotations

import difflib
import functools
import json
import re
from dataclasses import dataclass
from pathlib import Path

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...model.source import Source
from ..text import compact_number, one_line
from .codes import diag

UNITS_FILE = Path(__file__).parent / "units.json"
USERS = ("Standard", "Advanced")
#: Spellings other targets use for a unit ArduPilot names otherwise: offered as the did-you-mean.
_SPELLINGS = {"m/s^2": "m/s/s", "m/s2": "m/s/s", "m/s^3": "m/s/s/s", "rad/s^2": "rad/s/s", "deg/s^2": "deg/s/s",
              "cm/s^2": "cm/s/s", "degrees": "deg", "degree": "deg", "celsius": "degC", "°c": "degC", "c": "degC",
              "percent": "%", "rpm": "RPM", "g": "gravities", "mah": "mAh", "gauss": "Gauss", "sec": "s",
              "seconds": "s", "meters": "m", "metres": "m", "radians": "rad", "volts": "V", "amps": "A"}
_PAIRS = re.compile(r"^\s*(-?\d+)\s*:\s*([^,:]+?)\s*(,\s*(-?\d+)\s*:\s*([^,:]+?)\s*)*$")
_PAIR = re.compile(r"(-?\d+)\s*:\s*([^,]+)")
_BITS = {"AP_Int8": 8, "AP_Int16": 16, "AP_Int32": 32}


@functools.cache
def known_units() -> dict[str, str]:
    """ArduPilot's unit names → full text."""
    data: dict[str, dict[str, str]] = json.loads(UNITS_FILE.read_text(encoding="utf-8"))
    return data["units"]


def suggest_unit(unit: str) -> str | None:
    """The ArduPilot unit name ``unit`` most likely means, if one is close."""
    units = known_units()
    folded = {u.lower(): u for u in units}
    key = unit.strip().lower()
    if key in _SPELLINGS:
        return _SPELLINGS[key]
    if key in folded:
        return folded[key]
    close = difflib.get_close_matches(unit.strip(), list(units), n=1, cutoff=0.6)
    return close[0] if close else None


@dataclass(slots=True)
class Metadata:
    """The optional ``// @`` fields of one parameter."""

    units: str | None = None
    increment: str | None = None
    values: str | None = None
    bitmask: str | None = None
    user: str = "Standard"
    reboot_required: bool = False


def read_metadata(f: m.Field, ap_type: str, values: str | None, src: Source) -> tuple[Metadata, list[Diagnostic]]:
    """The documentation fields of parameter ``f`` (of AP type ``ap_type``; ``values`` from its enum)."""
    out: list[Diagnostic] = []
    meta = Metadata(values=values)
    unit_ann = m.annotation(f.annotations, "ap.units") or m.annotation(f.annotations, "unit")
    if unit_ann is not None and unit_ann.text.strip():
        unit = one_line(unit_ann.text).strip()
        if unit in known_units():
            meta.units = unit
        else:
            hint = suggest_unit(unit)
            fix = (f"; did you mean '{hint}'? (write `ap.units = \"{hint}\"` to keep '{unit}' for the other "
                   "targets)" if unit_ann.key == "unit" else f"; did you mean '{hint}'?") if hint else ""
            out.append(diag("ap-param-units", f"parameter '{f.name}': '{unit}' is not one of ArduPilot's unit names "
                            f"(Tools/autotest/param_metadata/param.py), so @Units is left out{fix}", src,
                            unit_ann.span))
    inc = m.annotation(f.annotations, "ap.increment")
    if inc is not None:
        number = _number(inc.text)
        if number is None or number <= 0:
            out.append(_bad(f, inc, "a positive number, the step a ground station uses", src))
        else:
            meta.increment = compact_number(number)
    vals = m.annotation(f.annotations, "ap.values")
    if vals is not None:
        if not _PAIRS.match(vals.text):
            out.append(_bad(f, vals, "value:Label pairs separated by commas, like \"0:Off,1:On\"", src))
        else:
            meta.values = ",".join(f"{v}:{label.strip()}" for v, label in _PAIR.findall(vals.text))
    bits = m.annotation(f.annotations, "ap.bitmask")
    if bits is not None:
        width = _BITS.get(ap_type)
        pairs = _PAIR.findall(bits.text) if _PAIRS.match(bits.text) else []
        if width is None:
            out.append(_bad(f, bits, "a bitmask on an integer parameter, and this one is an AP_Float", src))
        elif not pairs or any(not 0 <= int(b) < width for b, _ in pairs):
            out.append(_bad(f, bits, f"bit:Label pairs separated by commas, bits 0..{width - 1} for an {ap_type}, "
                            "like \"0:Roll,1:Pitch\"", src))
        else:
            meta.bitmask = ",".join(f"{b}:{label.strip()}" for b, label in pairs)
    user = m.annotation(f.annotations, "ap.user")
    if user is not None:
        if user.text not in USERS:
            out.append(_bad(f, user, " or ".join(USERS), src))
        else:
            meta.user = user.text
    reboot = m.annotation(f.annotations, "ap.reboot_required")
    if reboot is not None:
        flag = reboot.text.strip().lower() if reboot.value is not None else "true"
        if flag not in ("true", "false"):
            out.append(_bad(f, reboot, "true or false", src))
        else:
            meta.reboot_required = flag == "true"
    return meta, out


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _bad(f: m.Field, a: m.Annotation, expected: str, src: Source) -> Diagnostic:
    return diag("ap-param-annotation", f"parameter '{f.name}': {a.key} = {a.text!r} — expected {expected}", src,
                a.span)
