"""Units written in ROS comments (``# range data [m]``, ``# Voltage in Volts``, ``# rad``), as ``unit`` values.

A unit is taken only where the comment says it unambiguously: in its first line (the comment on
the field's own line, or the first line above it), a unit in brackets or parentheses (``[m]``, ``(A)``), ``in <unit>``, or a line that
is nothing but a unit, naming exactly one unit of the table below. Anything
else (``[device-specific units]``, ``[enum]``, two different units) gives none; the comment is
kept either way. Spellings are normalised to the symbols iface and its targets use (``seconds``
→ ``s``, ``Volts`` → ``V``, ``Degrees Celsius`` → ``degC``).
"""

from __future__ import annotations

import re

#: spelling (lower case) -> unit; single letters are matched case-sensitively in _SYMBOLS instead.
_WORDS: dict[str, str] = {
    "m": "m", "meter": "m", "meters": "m", "metre": "m", "metres": "m",
    "mm": "mm", "millimeters": "mm", "cm": "cm", "centimeters": "cm", "km": "km", "kilometers": "km",
    "m/s": "m/s", "meters/second": "m/s", "meters per second": "m/s", "m/sec": "m/s",
    "m/s^2": "m/s^2", "m/s2": "m/s^2", "m/s/s": "m/s^2", "meters/second^2": "m/s^2",
    "rad": "rad", "radian": "rad", "radians": "rad",
    "rad/s": "rad/s", "rad/sec": "rad/s", "radians/s": "rad/s", "radians/second": "rad/s",
    "radians per second": "rad/s", "rad/s^2": "rad/s^2", "rad/s2": "rad/s^2",
    "deg": "deg", "degree": "deg", "degrees": "deg", "deg/s": "deg/s",
    "s": "s", "sec": "s", "secs": "s", "second": "s", "seconds": "s",
    "ms": "ms", "millisecond": "ms", "milliseconds": "ms",
    "us": "us", "microsecond": "us", "microseconds": "us",
    "ns": "ns", "nanosecond": "ns", "nanoseconds": "ns",
    "hz": "Hz", "hertz": "Hz",
    "volt": "V", "volts": "V", "amp": "A", "amps": "A", "ampere": "A", "amperes": "A", "ah": "Ah",
    "watt": "W", "watts": "W", "kelvin": "K",
    "celsius": "degC", "degrees celsius": "degC", "degree celsius": "degC", "degc": "degC",
    "pa": "Pa", "pascal": "Pa", "pascals": "Pa", "hpa": "hPa",
    "tesla": "T", "gauss": "G", "lux": "lx", "lx": "lx",
    "kg": "kg", "kilogram": "kg", "kilograms": "kg", "newton": "N", "newtons": "N",
    "n.m": "N.m", "nm": "N.m", "newton meters": "N.m",
    "percent": "%", "%": "%",
}
#: one-letter symbols, case-sensitive (``[V]`` is volts, ``in a`` is English)
_SYMBOLS = {"m": "m", "s": "s", "V": "V", "A": "A", "K": "K", "T": "T", "N": "N", "W": "W"}
_BRACKET = re.compile(r"\[([^\[\]]{1,30})\]|\(([^()]{1,30})\)")
_IN = re.compile(r"\bin\s+((?:[A-Za-z%][A-Za-z0-9/^.%]*)(?:\s+[A-Za-z][A-Za-z]*)?)")


def _unit(text: str) -> str | None:
    """The unit ``text`` names (a symbol, a word or two words), or None."""
    text = text.strip().rstrip(".,;:)")
    if text in _SYMBOLS:
        return _SYMBOLS[text]
    if len(text) < 2:
        return None
    return _WORDS.get(text.lower())


def unit_of_comment(lines: list[str]) -> str | None:
    """The one unit the first line of a field's comment names, or None when it names none or several."""
    first = [line.strip() for line in lines if line.strip()][:1]
    if not first:
        return None
    text = first[0]  # the field's own line or the first line above it: further lines explain, and may name other units
    found: set[str] = set()
    whole = _unit(text)
    if whole is not None:
        found.add(whole)
    for m in _BRACKET.finditer(text):
        unit = _unit(m.group(1) or m.group(2))
        if unit is not None:
            found.add(unit)
    for m in _IN.finditer(text):
        words = m.group(1).split()
        unit = _unit(" ".join(words)) or _unit(words[0])
        if unit is not None:
            found.add(unit)
    return found.pop() if len(found) == 1 else None
