"""The PX4 module of a component: its uORB publications and subscriptions, and its parameters."""

from __future__ import annotations

from dataclasses import dataclass, field

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...model.walk import resolve_typedefs, type_text
from ...semantics.compile import Compilation
from ..support import (
    PARAM_NAME,
    Owners,
    camel,
    component_span,
    enum_of,
    humanize,
    literal,
    parameter_prefixes,
    snake,
    upper,
)
from ..text import comment_lines, compact_number, number, one_line, summary
from .codes import diag
from .messages import PX4_PACKAGES, UorbMessage

MAX_PARAM_NAME = 16
#: PX4's limit for a parameter's short description (its parameter metadata and QGroundControl show this much).
MAX_SHORT_DESC = 70


def short_desc(text: str) -> str:
    """``text`` within MAX_SHORT_DESC characters: cut at a word and marked with "..." (the long one keeps all)."""
    if len(text) <= MAX_SHORT_DESC:
        return text
    cut = text[: MAX_SHORT_DESC - 3].rsplit(" ", 1)[0].rstrip(" ,;:") or text[: MAX_SHORT_DESC - 3]
    return cut + "..."
#: Units PX4's module.yaml schema accepts (validation/module_schema.yaml).
PX4_UNITS = frozenset({
    "%", "Hz", "mAh", "rad", "%/rad", "rad/s", "rad/s^2", "%/rad/s", "rad s^2/m", "rad s/m", "bit/s", "B/s",
    "deg", "deg*1e7", "deg/s", "celcius", "gauss", "gauss/s", "mgauss", "mgauss^2", "hPa", "kg", "kg/m^2",
    "kg m^2", "mm", "m", "m/s", "m^2", "m/s^2", "m/s^3", "m/s^2/sqrt(Hz)", "m/s/rad", "Ohm", "V", "us", "ms",
    "s", "S", "A/%", "(m/s^2)^2", "m/m", "tan(rad)^2", "(m/s)^2", "m/rad", "m/s^3/sqrt(Hz)", "m/s/sqrt(Hz)",
    "s/(1000*PWM)", "%m/s", "min", "us/C", "N/(m/s)", "Nm/(rad/s)", "Nm", "N",
})
#: Names the module header uses unqualified (PX4's global classes and the work item's method): a module class
#: of one of these names would redeclare it (px4_platform_common/module.h, module_params.h, param.h).
PX4_DECLARED = {
    "ModuleBase": "PX4's module base class ModuleBase (px4_platform_common/module.h)",
    "ModuleParams": "PX4's parameter base class ModuleParams (px4_platform_common/module_params.h)",
    "Param": "PX4's parameter template Param (px4_platform_common/param.h)",
    "ParamInt": "PX4's parameter class ParamInt (px4_platform_common/param.h)",
    "ParamFloat": "PX4's parameter class ParamFloat (px4_platform_common/param.h)",
    "ParamBool": "PX4's parameter class ParamBool (px4_platform_common/param.h)",
    "ParamExtInt": "PX4's parameter alias ParamExtInt (px4_platform_common/param.h)",
    "ParamExtFloat": "PX4's parameter alias ParamExtFloat (px4_platform_common/param.h)",
    "Run": "the class's own Run() method (a method named like its class is a constructor in C++)",
}
#: The work queues of PX4 (platforms/common/include/px4_platform_common/px4_work_queue/WorkQueueManager.hpp).
WORK_QUEUES = frozenset({"rate_ctrl", "SPI0", "SPI1", "SPI2", "SPI3", "SPI4", "SPI5", "SPI6", "I2C0", "I2C1",
                         "I2C2", "I2C3", "I2C4", "nav_and_controllers", "INS0", "INS1", "INS2", "INS3",
                         "hp_default", "uavcan", "ttyS0", "ttyS1", "ttyS2", "ttyS3", "ttyS4", "ttyS5", "ttyS6",
                         "ttyS7", "ttyS8", "ttyS9", "ttyACM0", "ttyUnknown", "lp_default", "test1", "test2"})
#: The user hooks the module class declares besides one per subscription.
HOOKS = frozenset({"on_start", "on_parameters_updated", "on_cycle"})
_INT32_SOURCES = frozenset({"i8", "i16", "i32", "u8", "u16", "char", "octet"})
_PARAM_CLASS = {"int32": "ParamInt", "enum": "ParamInt", "float": "ParamFloat", "boolean": "ParamBool"}


@dataclass(slots=True)
class Topic:
    """A publication or subscription member of the module class."""

    cls: str
    member: str
    topic: str
    message: str
    callback: bool = False
    #: The user's method called with each message of a subscription.
    handler: str = ""


@dataclass(slots=True)
class Param:
    """One PX4 parameter (module.yaml entry and DEFINE_PARAMETERS member)."""

    name: str
    type: str
    default: str
    short: str
    long: str
    min: str | None = None
    max: str | None = None
    unit: str | None = None
    decimal: str | None = None
    increment: str | None = None
    values: list[tuple[int, str]] = field(default_factory=list)

    @property
    def param_class(self) -> str:
        """The ModuleParams wrapper class."""
        return _PARAM_CLASS[self.type]

    @property
    def member(self) -> str:
        """The member name PX4 code uses for it."""
        return "_param_" + self.name.lower()


@dataclass(slots=True)
class Px4Module:
    """What the header and module.yaml render."""

    class_name: str
    module_name: str
    group: str
    doc: list[str]
    description: str
    includes: list[str] = field(default_factory=list)
    publications: list[Topic] = field(default_factory=list)
    subscriptions: list[Topic] = field(default_factory=list)
    params: list[Param] = field(default_factory=list)
    #: The work queue Run() is scheduled on (``px4.work_queue``), and its period without callback subscriptions.
    work_queue: str = "lp_default"
    interval_us: int = 10_000

    @property
    def callbacks(self) -> bool:
        """True when a subscription schedules Run()."""
        return any(t.callback for t in self.subscriptions)

    @property
    def summary(self) -> str:
        """The first line of the description."""
        return self.description.split("\n", 1)[0]

    @property
    def usage(self) -> str:
        """The text of PRINT_MODULE_DESCRIPTION."""
        return "\n### Description\n" + (self.description or self.module_name) + "\n"


class ModuleBuilder:
    """Builds the module view, reporting parameters PX4 cannot hold."""

    def __init__(self, comp: Compilation, owners: Owners, messages: dict[str, UorbMessage],
                 names: dict[int, str | None], wired: dict[int, str]) -> None:
        self.iface = comp.interface
        self.owners = owners
        self.messages = messages
        self.names = names
        self.wired = wired
        self.diagnostics: list[Diagnostic] = []

    def build(self) -> Px4Module | None:
        """The module; None for a message library (no topic wired, no parameter) or a name no class can have."""
        iface = self.iface
        comp_decl = iface.component
        if not iface.parameters and not any(w.direction in ("publishes", "subscribes") for w in iface.wirings):
            self.diagnostics.append(diag("px4-message-library", f"'{iface.name}' wires no topic and has no "
                                         "parameter: only its uORB messages are generated (a message library, "
                                         "no module)", iface.source, component_span(iface)))
            return None
        class_name = camel(iface.name)
        if class_name is None:
            self.diagnostics.append(diag("px4-name-invalid", f"component name '{iface.name}' cannot be made a "
                                         "C++ class name", iface.source, component_span(iface)))
            return None
        declared = PX4_DECLARED.get(class_name)
        if declared is not None:
            self.diagnostics.append(diag("px4-reserved-name", f"component '{iface.name}' becomes the C++ class "
                                         f"{class_name}, which would redeclare {declared}: rename the component",
                                         iface.source, component_span(iface)))
            return None
        doc = comment_lines(comp_decl.doc if comp_decl else None)
        group_ann = m.annotation(comp_decl.annotations, "px4.group") if comp_decl else None
        module = Px4Module(class_name, snake(iface.name), one_line(group_ann.text) if group_ann else
                           humanize(iface.name), doc, "\n".join(doc))
        self._topics(module)
        self._params(module)
        if comp_decl is not None:
            self._scheduling(module, comp_decl)
        return module

    def _scheduling(self, module: Px4Module, decl: m.ComponentDecl) -> None:
        """``px4.work_queue`` and ``px4.interval_us`` of the component."""
        queue = m.annotation(decl.annotations, "px4.work_queue")
        if queue is not None:
            name = one_line(queue.text or "")
            if name in WORK_QUEUES:
                module.work_queue = name
            else:
                self.diagnostics.append(diag("px4-annotation", f"px4.work_queue = {name!r} is not one of PX4's "
                                             f"work queues: {', '.join(sorted(WORK_QUEUES))}",
                                             self.iface.source, queue.span))
        interval = m.annotation(decl.annotations, "px4.interval_us")
        if interval is not None:
            text = one_line(interval.text or "")
            if text.isdigit() and 0 < int(text) <= 10_000_000:
                module.interval_us = int(text)
            else:
                self.diagnostics.append(diag("px4-annotation", f"px4.interval_us = {text!r}: a whole number of "
                                             "microseconds from 1 to 10000000", self.iface.source, interval.span))

    # ---- topics ------------------------------------------------------------------
    def _topics(self, module: Px4Module) -> None:
        seen: set[tuple[str, str]] = set()
        includes: set[str] = set()
        for w in self.iface.wirings:
            if w.direction not in ("publishes", "subscribes"):
                continue
            topic = self.wired.get(id(w))
            stem = self._message_stem(w.type)
            if topic is None or stem is None or (w.direction, topic) in seen:
                continue
            seen.add((w.direction, topic))
            includes.add(stem)
            if w.direction == "publishes":
                module.publications.append(Topic(f"uORB::Publication<{stem}_s>", f"_{topic}_pub", topic, stem))
            else:
                callback = m.annotation(w.annotations, "px4.callback") is not None
                cls = "uORB::SubscriptionCallbackWorkItem" if callback else "uORB::Subscription"
                handler = f"on_{topic}" if f"on_{topic}" not in HOOKS else f"on_{topic}_message"
                module.subscriptions.append(Topic(cls, f"_{topic}_sub", topic, stem, callback, handler))
        module.includes = sorted(includes)

    def _message_stem(self, t: m.NamedType) -> str | None:
        target = t.target
        if isinstance(target, m.Struct):
            name = self.names.get(id(target))
            return snake(name) if name else None
        if target is None and t.external in PX4_PACKAGES:
            return snake(t.local_name)
        return None

    # ---- parameters ------------------------------------------------------------------
    def _params(self, module: Px4Module) -> None:
        src = self.iface.source
        taken: dict[str, m.Field] = {}
        for block, prefix, span in parameter_prefixes(self.iface, "px4.prefix"):
            if not PARAM_NAME.match(prefix):
                self.diagnostics.append(diag("px4-param-name-invalid", f"parameter prefix '{prefix}' is not "
                                             "UPPER_CASE letters and digits (set px4.prefix)", src, span))
                continue
            for f in block.fields:
                param = self._param(f, prefix)
                if param is None:
                    continue
                if param.name in taken:
                    self.diagnostics.append(diag("px4-param-name-conflict", f"parameter '{f.name}' becomes "
                                                 f"{param.name}, as '{taken[param.name].name}' does", src,
                                                 f.name_span))
                    continue
                taken[param.name] = f
                module.params.append(param)

    def _param(self, f: m.Field, prefix: str) -> Param | None:
        src = self.iface.source
        explicit = m.annotation(f.annotations, "px4.name")
        name = explicit.text if explicit else f"{prefix}_{upper(f.name)}"
        span = explicit.span if explicit else f.name_span
        named = True
        if not PARAM_NAME.match(name):
            self.diagnostics.append(diag("px4-param-name-invalid", f"parameter '{f.name}': '{name}' is not a PX4 "
                                         "parameter name (UPPER_CASE)", src, span))
            named = False
        elif len(name) > MAX_PARAM_NAME:
            self.diagnostics.append(diag("px4-param-name-too-long", f"parameter '{f.name}' becomes {name}, "
                                         f"{len(name)} characters: PX4 parameter names have at most "
                                         f"{MAX_PARAM_NAME} (shorten it or set px4.name / px4.prefix)", src, span))
            named = False
        ptype = self._param_type(f)
        if ptype is None or not named:
            return None
        short = short_desc(summary(f.doc) or humanize(f.name))
        param = Param(name, ptype, "", short, one_line(f.doc) or short)
        if not self._param_default(f, param):
            return None
        rng = f.range
        if rng is not None and ptype in ("int32", "float", "enum"):
            lo, hi = rng
            param.min = None if lo is None else _bound(lo, ptype)
            param.max = None if hi is None else _bound(hi, ptype)
        if f.unit:
            if f.unit in PX4_UNITS:
                param.unit = f.unit
            else:
                self.diagnostics.append(diag("px4-param-unit", f"parameter '{f.name}': unit '{one_line(f.unit)}'"
                                             " is not one PX4's module.yaml accepts; it is left out of module.yaml",
                                             src, f.span))
        dec = m.annotation(f.annotations, "px4.decimal")
        if dec is not None and ptype == "float" and dec.text.isdigit():
            param.decimal = dec.text
        step = m.annotation(f.annotations, "px4.increment")
        if step is not None and ptype == "float":
            param.increment = _increment(step.text)
            if param.increment is None:
                self.diagnostics.append(diag("px4-annotation", f"parameter '{f.name}': px4.increment = "
                                             f"{one_line(step.text)!r} is not a positive number", src, step.span))
        enum = enum_of(f.type)
        if enum is not None:
            param.values = [(v.value, humanize(v.name)) for v in enum.values]
        return param

    def _param_type(self, f: m.Field) -> str | None:
        src = self.iface.source
        t = resolve_typedefs(f.type)
        if isinstance(t, m.NamedType) and isinstance(t.target, m.Enum):
            return "enum"
        if isinstance(t, m.BaseType) and t.bound is None:
            if t.name == "bool":
                return "boolean"
            if t.name in _INT32_SOURCES:
                return "int32"
            if t.name == "float32":
                return "float"
            if t.name == "float64":
                self.diagnostics.append(diag("px4-param-precision", f"parameter '{f.name}' is {type_text(f.type)}: "
                                             "PX4 stores it as FLOAT (32-bit)", src, f.type.span))
                return "float"
        self.diagnostics.append(diag("px4-param-type", f"parameter '{f.name}' is {type_text(f.type)}: PX4 "
                                     "parameters are INT32 or FLOAT (bool, integers up to 16 bits and i32, "
                                     "float, double, enums)", src, f.type.span))
        return None

    def _param_default(self, f: m.Field, param: Param) -> bool:
        if f.default is None:
            param.default = {"boolean": "false", "float": "0.0"}.get(param.type, "0")
            return True
        value = literal(self.owners.root, f.default)
        if param.type == "boolean" and isinstance(value, (bool, int)):
            param.default = "true" if value else "false"
            return True
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if param.type == "float":
                param.default = number(float(value))
                return True
            if isinstance(value, int) and -(2**31) <= value < 2**31:
                param.default = str(value)
                return True
        self.diagnostics.append(diag("px4-param-default", f"parameter '{f.name}': the default "
                                     f"{f.default.text or f.default.value!r} cannot be a PX4 {param.type} value",
                                     self.iface.source, f.default.span))
        return False


def _bound(value: float, ptype: str) -> str:
    return number(value) if ptype == "float" else compact_number(value)


def _increment(text: str) -> str | None:
    """A GCS step size as module.yaml writes it, None unless a positive finite number."""
    try:
        value = float(text)
    except ValueError:
        return None
    return number(value) if 0 < value < float("inf") else None
