"""The AP_Param table of a component: names, stable indices, types and documentation.

Index stability: an AP_Param group index is the key under which a value is
stored in EEPROM, so it must never change for a parameter. The index is taken
from the interface itself, never from the order of the generated table:

1. ``(ap.index = N)`` on the field, else
2. the Thrift field id (``3: float max_speed``), else
3. the position among the parameters without either, after the explicit
   indices (with a warning, because inserting a parameter renumbers the ones
   after it).

The group's enable switch: as ArduPilot's libraries do (AP_ADSB, AP_DDS…), a group has an
``ENABLE`` parameter flagged ``AP_PARAM_FLAG_ENABLE``, which hides the others while 0. A
parameter the component names ENABLE is that switch; otherwise one is added at index 0
(default 0, disabled), and index 0 is not free for other parameters.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...model.walk import resolve_typedefs, type_text
from ...semantics.compile import Compilation
from ..support import (
    PARAM_NAME,
    camel,
    component_span,
    enum_of,
    humanize,
    literal,
    parameter_prefixes,
    snake,
    upper,
)
from ..text import compact_number, number, one_line, summary
from .codes import diag
from .metadata import read_metadata

MAX_NAME = 16
ENABLE = "ENABLE"
MAX_INDEX = 63
_AP_TYPES = {"bool": "AP_Int8", "i8": "AP_Int8", "u8": "AP_Int16", "i16": "AP_Int16", "char": "AP_Int16",
             "octet": "AP_Int16", "u16": "AP_Int32", "i32": "AP_Int32", "float32": "AP_Float",
             "float64": "AP_Float"}
_INT_RANGES = (("AP_Int8", -(2**7), 2**7 - 1), ("AP_Int16", -(2**15), 2**15 - 1),
               ("AP_Int32", -(2**31), 2**31 - 1))


@dataclass(slots=True)
class ApParam:
    """One AP_GROUPINFO entry with its ``// @`` documentation."""

    name: str
    full_name: str
    index: int
    ap_type: str
    member: str
    default: str
    display_name: str
    description: str
    user: str = "Standard"
    units: str | None = None
    range: str | None = None
    increment: str | None = None
    values: str | None = None
    bitmask: str | None = None
    reboot_required: bool = False
    flags: str | None = None


@dataclass(slots=True)
class ApParams:
    """The parameter class: its name, group prefix and entries (sorted by index)."""

    class_name: str
    library: str
    prefix: str
    component: str
    params: list[ApParam] = field(default_factory=list)


class ParamBuilder:
    """Builds the AP_Param table, reporting what ArduPilot cannot hold."""

    def __init__(self, comp: Compilation) -> None:
        self.iface = comp.interface
        self.src = comp.interface.source
        self.diagnostics: list[Diagnostic] = []

    def build(self) -> ApParams | None:
        """The table, or None when the component name cannot name a class."""
        iface = self.iface
        base = camel(iface.name)
        if base is None:
            self.diagnostics.append(diag("ap-name-invalid", f"component name '{iface.name}' cannot be made a C++ "
                                         "class name", self.src, component_span(iface)))
            return None
        table = ApParams(f"AP_{base}_Params", f"AP_{base}", "", snake(iface.name))
        entries: list[tuple[m.Field, ApParam, bool]] = []
        names: dict[str, m.Field] = {}
        for block, prefix, span in parameter_prefixes(iface, "ap.prefix"):
            if not PARAM_NAME.match(prefix):
                self.diagnostics.append(diag("ap-param-name-invalid", f"parameter prefix '{prefix}' is not UPPER_CASE "
                                             "letters and digits (set ap.prefix)", self.src, span))
                continue
            table.prefix = table.prefix or prefix
            for f in block.fields:
                p = self._param(f, prefix)
                if p is None:
                    continue
                if p.full_name in names:
                    self.diagnostics.append(diag("ap-param-name-conflict", f"parameter '{f.name}' becomes "
                                                 f"{p.full_name}, as '{names[p.full_name].name}' does", self.src,
                                                 f.name_span))
                    continue
                names[p.full_name] = f
                entries.append((f, p, p.index >= 0))
        declared = next(((f, p) for f, p, _ in entries if p.name == ENABLE), None)
        enable = None
        if entries and declared is None:
            enable = self._enable(table)
        elif declared is not None:
            f, p = declared
            p.flags = "AP_PARAM_FLAG_ENABLE"
            if p.ap_type != "AP_Int8":
                self.diagnostics.append(diag("ap-param-enable-type", f"parameter '{f.name}' is the group's enable "
                                             f"switch ({p.full_name}) but an {p.ap_type}: AP_Param honours "
                                             "AP_PARAM_FLAG_ENABLE on an AP_Int8 only (make it bool or i8)",
                                             self.src, f.type.span))
        table.params = self._indices(entries, enable)
        return table

    def _enable(self, table: ApParams) -> ApParam | None:
        """The ``<PREFIX>_ENABLE`` switch ArduPilot's conventions expect, None when its name is too long."""
        full = f"{table.prefix}_{ENABLE}"
        if len(full) > MAX_NAME:
            span = next(span for _, prefix, span in parameter_prefixes(self.iface, "ap.prefix")
                        if prefix == table.prefix)
            self.diagnostics.append(diag("ap-param-name-too-long", f"the group's enable switch would be {full}, "
                                         f"{len(full)} characters: ArduPilot parameter names have at most {MAX_NAME} "
                                         "(shorten the prefix or declare the switch: `bool enable (ap.name = ...)`)",
                                         self.src, span))
            return None
        name = humanize(self.iface.name)
        return ApParam(ENABLE, full, 0, "AP_Int8", "_enable", "0", f"{name} enable",
                       f"Enables {name}; while 0, its other parameters are hidden.", values="0:Disabled,1:Enabled",
                       flags="AP_PARAM_FLAG_ENABLE")

    def _indices(self, entries: list[tuple[m.Field, ApParam, bool]], enable: ApParam | None) -> list[ApParam]:
        used: dict[int, m.Field] = {}
        out: list[ApParam] = [enable] if enable is not None else []
        for f, p, explicit in entries:
            if not explicit:
                continue
            if enable is not None and p.index == enable.index:
                self.diagnostics.append(diag("ap-param-index-conflict", f"parameter '{f.name}' has index {p.index}, "
                                             f"which is {enable.full_name}'s, the group's enable switch (added "
                                             "because no parameter is named ENABLE): give it another index, or "
                                             "declare the switch yourself (`bool enable (ap.index = 0)`)", self.src,
                                             f.id_span or f.name_span))
                continue
            if p.index > MAX_INDEX:
                self.diagnostics.append(diag("ap-param-index-range", f"parameter '{f.name}' has index {p.index}: "
                                             f"AP_Param group indices are 0..{MAX_INDEX}", self.src,
                                             f.id_span or f.name_span))
                continue
            if p.index in used:
                self.diagnostics.append(diag("ap-param-index-conflict", f"parameter '{f.name}' has index {p.index}, "
                                             f"as '{used[p.index].name}' does", self.src, f.id_span or f.name_span))
                continue
            used[p.index] = f
            out.append(p)
        following = max(used, default=enable.index if enable is not None else 0) + 1
        for f, p, explicit in entries:
            if explicit:
                continue
            p.index = following
            following += 1
            if p.index > MAX_INDEX:
                self.diagnostics.append(diag("ap-param-index-range", f"parameter '{f.name}' would get index "
                                             f"{p.index}: AP_Param groups hold indices 0..{MAX_INDEX}", self.src,
                                             f.name_span))
                continue
            self.diagnostics.append(diag("ap-param-index-implicit", f"parameter '{f.name}' has no field id: it gets "
                                         f"AP_Param index {p.index} from its position, which changes if parameters "
                                         f"are inserted before it (write `{p.index}: {type_text(f.type)} {f.name}`)",
                                         self.src, f.name_span))
            out.append(p)
        return sorted(out, key=lambda p: p.index)

    def _param(self, f: m.Field, prefix: str) -> ApParam | None:
        # the type first: a parameter left out for its type gets no further diagnostics
        ap_type, values = self._type(f)
        if ap_type is None:
            return None
        explicit = m.annotation(f.annotations, "ap.name")
        name = explicit.text if explicit else upper(f.name)
        if explicit and name.startswith(f"{prefix}_") and len(name) > len(prefix) + 1:
            name = name[len(prefix) + 1:]  # written with its prefix (ap.name = "ARM_SPD"): not added twice
        span = explicit.span if explicit else f.name_span
        full = f"{prefix}_{name}"
        named = True
        if not PARAM_NAME.match(name):
            self.diagnostics.append(diag("ap-param-name-invalid", f"parameter '{f.name}': '{name}' is not an "
                                         "ArduPilot parameter name (UPPER_CASE)", self.src, span))
            named = False
        elif len(full) > MAX_NAME:
            self.diagnostics.append(diag("ap-param-name-too-long", f"parameter '{f.name}' becomes {full}, "
                                         f"{len(full)} characters: ArduPilot parameter names have at most {MAX_NAME} "
                                         "(shorten it or set ap.name / ap.prefix)", self.src, span))
            named = False
        if not named:
            return None
        default = self._default(f, ap_type)
        if default is None:
            return None
        index_ann = m.annotation(f.annotations, "ap.index")
        index = -1
        if index_ann is not None and index_ann.value is not None and index_ann.value.kind == "int":
            index = int(index_ann.value.value)
        elif f.id is not None:
            index = f.id
        meta, problems = read_metadata(f, ap_type, values, self.src)
        self.diagnostics.extend(problems)
        p = ApParam(name, full, index, ap_type, f"_{snake(f.name)}", default,
                    summary(f.doc).rstrip(".") or humanize(f.name), one_line(f.doc) or humanize(f.name),
                    meta.user, meta.units, None, meta.increment, meta.values, meta.bitmask, meta.reboot_required)
        rng = f.range
        if rng is not None and rng[0] is not None and rng[1] is not None:
            p.range = f"{compact_number(rng[0])} {compact_number(rng[1])}"
        return p

    def _type(self, f: m.Field) -> tuple[str | None, str | None]:
        t = resolve_typedefs(f.type)
        enum = enum_of(f.type)
        if enum is not None:
            vals = [v.value for v in enum.values] or [0]
            ap_type = next((n for n, lo, hi in _INT_RANGES if lo <= min(vals) and max(vals) <= hi), None)
            if ap_type is not None:
                return ap_type, ",".join(f"{v.value}:{humanize(v.name)}" for v in enum.values)
        elif isinstance(t, m.BaseType) and t.bound is None and t.name in _AP_TYPES:
            if t.name == "float64":
                self.diagnostics.append(diag("ap-param-precision", f"parameter '{f.name}' is {type_text(f.type)}: "
                                             "AP_Float stores 32 bits", self.src, f.type.span))
            return _AP_TYPES[t.name], ("0:Disabled,1:Enabled" if t.name == "bool" else None)
        self.diagnostics.append(diag("ap-param-unsupported-type", f"parameter '{f.name}' is {type_text(f.type)}: "
                                     f"{_why_not(t, enum)}; it is left out of the ArduPilot parameter table",
                                     self.src, f.type.span))
        return None, None

    def _default(self, f: m.Field, ap_type: str) -> str | None:
        if f.default is None:
            return "0" if ap_type != "AP_Float" else "0.0f"
        value = literal(self.iface, f.default)
        if isinstance(value, bool):
            return "1" if value else "0"
        if isinstance(value, (int, float)):
            if ap_type == "AP_Float":
                return number(float(value)) + "f"
            if isinstance(value, int):
                return str(value)
        self.diagnostics.append(diag("ap-param-default", f"parameter '{f.name}': the default "
                                     f"{f.default.text or f.default.value!r} cannot be an {ap_type} value",
                                     self.src, f.default.span))
        return None


#: What AP_Param can hold, said in every unsupported-type message.
_HOLDS = ("AP_Param holds signed integers of up to 32 bits (AP_Int8, AP_Int16, AP_Int32) and 32-bit floats "
          "(AP_Float)")


def _why_not(t: m.TypeRef, enum: m.Enum | None) -> str:
    """Why AP_Param cannot hold a (typedef-resolved) type, with what would fit when there is such a type."""
    if enum is not None:
        return f"{_HOLDS}, and the values of enum '{enum.name}' do not fit AP_Int32"
    if isinstance(t, m.BaseType) and t.bound is None:
        if t.name == "u32":
            return f"{_HOLDS}, and u32 values above 2147483647 do not fit AP_Int32 (use i32)"
        if t.name in ("i64", "u64"):
            return f"{_HOLDS}; a 64-bit integer does not fit"
    return _HOLDS
