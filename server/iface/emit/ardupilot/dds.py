"""The component's AP_DDS entries: topic table, service table and XRCE-DDS profiles.

Followed as ArduPilot writes them at commit 003e46bb (``libraries/AP_DDS/AP_DDS_Client.h``:
``struct Topic_table`` and ``struct Service_table``; ``AP_DDS_Topic_Table.h``) and 6195046f
(``dds_xrce_profile.xml``): a topic is ``rt/<ROS name>`` of type ``<pkg>::msg::dds_::<Name>_``; a
service ``rs/<name>Service`` with request ``rq/<name>Request`` and reply ``rr/<name>Reply``.
QoS comes from the ``qos.*`` annotations of the wiring statement, ROS 2's defaults
(reliable, volatile, keep_last, depth 10) for the rest; ``uxrQoS_t`` holds those four only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...model import nodes as m
from ...model import qos as rules
from ...model.diagnostics import Diagnostic
from ...model.naming import ros_field_name, ros_type_name, words
from ...semantics.compile import Compilation
from ..ros2.names import Namer
from ..support import component_span
from .codes import diag

#: ``uxrQoS_t`` of Micro-XRCE-DDS-Client: what each ROS 2 policy value becomes.
_DURABILITY = {"volatile": "VOLATILE", "transient_local": "TRANSIENT_LOCAL", "transient": "TRANSIENT",
               "persistent": "PERSISTENT"}
_RELIABILITY = {"reliable": "RELIABLE", "best_effort": "BEST_EFFORT"}
_HISTORY = {"keep_last": "KEEP_LAST", "keep_all": "KEEP_ALL"}
_DEFAULTS = {"durability": "volatile", "reliability": "reliable", "history": "keep_last", "depth": "10"}
MAX_DEPTH = 65535  # uxrQoS_t.depth is a uint16_t
MAX_ENTRIES = 256  # the table indices are uint8_t


@dataclass(frozen=True, slots=True)
class DdsQos:
    """A ``uxrQoS_t``: the suffixes of the UXR_* enumerators and the depth."""

    durability: str
    reliability: str
    history: str
    depth: int


@dataclass(frozen=True, slots=True)
class DdsTopic:
    """One ``Topic_table`` entry and its XRCE profiles."""

    index: str
    label: str
    writer: bool
    topic_name: str
    type_name: str
    qos: DdsQos
    what: str

    @property
    def feature(self) -> str:
        """The build switch of the entry, as AP_DDS_config.h names ArduPilot's (``AP_DDS_TIME_PUB_ENABLED``)."""
        return f"AP_DDS_{self.index}_ENABLED"


@dataclass(frozen=True, slots=True)
class DdsService:
    """One ``Service_table`` entry and its XRCE profile."""

    index: str
    label: str
    replier: bool
    service_name: str
    request_type: str
    reply_type: str
    request_topic_name: str
    reply_topic_name: str
    qos: DdsQos
    what: str

    @property
    def feature(self) -> str:
        """The build switch of the entry, as AP_DDS_config.h names ArduPilot's (``AP_DDS_ARM_SERVER_ENABLED``)."""
        return f"AP_DDS_{self.index}_{'SERVER' if self.replier else 'CLIENT'}_ENABLED"


@dataclass(slots=True)
class DdsTables:
    """What the component adds to AP_DDS."""

    topics: list[DdsTopic] = field(default_factory=list)
    services: list[DdsService] = field(default_factory=list)

    @property
    def type_headers(self) -> list[str]:
        """The C headers of the topic types (``pkg/msg/Name.h``), as AP_DDS_Topic_Table.h includes them."""
        found = {"/".join(t.type_name.replace("::dds_::", "::").rstrip("_").split("::")) + ".h" for t in self.topics}
        return sorted(found)


class DdsBuilder:
    """Reads the wiring statements of a component into AP_DDS entries."""

    def __init__(self, comp: Compilation) -> None:
        self.iface = comp.interface
        self.src = comp.interface.source
        self.names = Namer(comp)
        self.diagnostics: list[Diagnostic] = []
        self._indices: set[str] = set()
        self._labels: set[str] = set()

    def build(self) -> DdsTables:
        """The topic and service entries, in the order of the wiring statements' kinds."""
        tables = DdsTables()
        for ep, writer in [*((e, True) for e in self.iface.published), *((e, False) for e in self.iface.subscribed)]:
            topic = self._topic(ep, writer)
            if topic is not None:
                tables.topics.append(topic)
        for ep in self.iface.services:
            tables.services.extend(self._services(ep))
        for d in self.iface.diagnostics:
            # the diagnostics service Δ: served under its wired name, else ~/<name> as the ROS 2 node does
            w = next((w for w in self.iface.wirings if w.direction == "provides" and w.type.target is d), None)
            name = w.topic if w is not None else f"~/{ros_field_name(d.name) or d.name}"
            tables.services.extend(self._services(m.Endpoint("provides", name, d, w)))
        for what, count in (("topics", len(tables.topics)), ("services", len(tables.services))):
            if count > MAX_ENTRIES:
                self.diagnostics.append(diag("ap-dds-too-many", f"{count} {what}: AP_DDS numbers its {what} with "
                                             f"uint8_t, at most {MAX_ENTRIES}", self.src,
                                             component_span(self.iface)))
        return tables

    def _topic(self, ep: m.Endpoint, writer: bool) -> DdsTopic | None:
        d = ep.definition
        if isinstance(d, m.Struct):
            type_name = self._type(d, "msg")
        else:
            type_name = _external(ep, "msg")
        if type_name is None:
            return None
        ros = self._ros_name(ep.name)
        slug = _slug(ros)
        index = self._unique(f"{slug.upper()}_{'PUB' if writer else 'SUB'}", self._indices)
        label = self._unique(slug, self._labels)
        return DdsTopic(index, label, writer, f"rt/{ros}", type_name, self._qos(ep.wiring),
                        f"{ep.role} {_wired(ep)} on {ep.name}")

    def _services(self, ep: m.Endpoint) -> list[DdsService]:
        d = ep.definition
        if d is not None and not isinstance(d, m.Service):
            return []
        replier = ep.role == "provides"
        parts: list[tuple[str, str | None]] = [(ep.name, "")]
        if d is not None and d.form == "functions":
            parts = [(ep.name.rstrip("/") + "/" + (ros_field_name(fn.name) or fn.name), ros_type_name(fn.name))
                     for fn in d.functions]
        out = []
        for name, suffix in parts:
            if d is None:
                type_name = _external(ep, "srv")
            else:
                type_name = self._type(d, "srv", suffix or "") if suffix is not None else None
            if type_name is None:
                continue
            ros = self._ros_name(name)
            slug = _slug(ros)
            index = self._unique(slug.upper(), self._indices)
            label = self._unique(slug, self._labels)
            out.append(DdsService(index, label, replier, f"rs/{ros}Service", f"{type_name}Request_",
                                  f"{type_name}Response_", f"rq/{ros}Request", f"rr/{ros}Reply",
                                  self._qos(ep.wiring), f"{ep.role} {_wired(ep)} on {name}"))
        return out

    def _type(self, d: m.Definition, kind: str, suffix: str = "") -> str | None:
        """``pkg::kind::dds_::Name_`` (services: without the trailing ``_``, for Request_/Response_)."""
        package = self.names.package_of(self.names.owners.of(d))
        name = self.names.type_name(d, suffix=suffix)
        if package is None or name is None:
            return None
        return f"{package}::{kind}::dds_::{name}_"

    def _ros_name(self, name: str) -> str:
        """The fully qualified ROS name without its leading slash; ``~/x`` is the component's ``x``."""
        if name.startswith("~"):
            name = f"{self.iface.name}/{name[1:].lstrip('/')}"
        return name.strip("/")

    def _qos(self, w: m.Wiring | None) -> DdsQos:
        values = dict(_DEFAULTS)
        if w is not None:
            for a in w.annotations:
                if not a.key.startswith("qos."):
                    continue
                key = rules.ALIASES.get(a.key[4:], a.key[4:])
                value = a.text.strip().lower()
                if key in values:
                    if value != "system_default":
                        values[key] = value
                elif key in rules.KEYS:
                    self.diagnostics.append(diag("ap-dds-qos-unsupported", f"qos.{key} is not carried to AP_DDS: "
                                                 "its uxrQoS_t holds durability, reliability, history and depth "
                                                 "only", self.src, a.span))
        depth = int(values["depth"]) if values["depth"].isdigit() else 10
        if depth > MAX_DEPTH:
            span = next(a.span for a in (w.annotations if w else []) if a.key == "qos.depth")
            self.diagnostics.append(diag("ap-dds-qos-depth", f"qos.depth = {depth}: AP_DDS keeps the depth in a "
                                         f"uint16_t, at most {MAX_DEPTH}", self.src, span))
            depth = MAX_DEPTH
        return DdsQos(_DURABILITY.get(values["durability"], "VOLATILE"),
                      _RELIABILITY.get(values["reliability"], "RELIABLE"),
                      _HISTORY.get(values["history"], "KEEP_LAST"), depth)

    @staticmethod
    def _unique(name: str, seen: set[str]) -> str:
        out, n = name, 2
        while out in seen:
            out, n = f"{name}_{n}", n + 1
        seen.add(out)
        return out


def _external(ep: m.Endpoint, kind: str) -> str | None:
    """The DDS type of a wired type of an ``external`` package (``geometry_msgs.Twist``)."""
    if ep.wiring is None or "." not in ep.wiring.type.name:
        return None
    package, _, name = ep.wiring.type.name.rpartition(".")
    return f"{package.replace('.', '::')}::{kind}::dds_::{name}_"


def _wired(ep: m.Endpoint) -> str:
    """The wired type as written."""
    if ep.definition is not None:
        return ep.definition.name
    return ep.wiring.type.name if ep.wiring is not None else "?"


def _slug(ros: str) -> str:
    """``a/report`` → ``a_report``: an identifier from a ROS name."""
    return "_".join(w.lower() for w in words(ros.replace("/", "_"))) or "root"
