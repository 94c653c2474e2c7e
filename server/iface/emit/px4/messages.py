"""uORB messages from the interface: types, fields, constants and topics, checked against uORB's rules."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from ...model.naming import ros_constant_name, ros_field_name
from ...model.walk import resolve_typedefs, type_text
from ...semantics.compile import Compilation
from ..keywords import c_family_keyword
from ..support import Owners, camel, enum_of, literal, member_order, snake, upper
from ..text import comment_lines, number, one_line
from ..types import container, px4_base
from .codes import diag

#: External packages whose types are uORB messages that PX4 already has.
PX4_PACKAGES = frozenset({"px4_msgs", "px4"})
_UORB_TOPIC = re.compile(r"^[a-z][a-z0-9]*(_[a-z0-9]+)*$")
#: The ROS 2 name the uXRCE-DDS bridge gives a uORB topic: ``[/<vehicle namespace>]/fmu/(in|out)/<topic>``.
_BRIDGE_NAME = re.compile(r"^/?(?:[A-Za-z][A-Za-z0-9_]*/)?fmu/(?:in|out)/(?P<topic>[^/]+)$")
_NUMERIC = frozenset({"bool", "char", "int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
                      "float32", "float64"})
#: Why uORB cannot hold a base type, and what to write instead.
_REASONS = {"string": "uORB has no unbounded strings: write string<=N, which becomes char[N] (text in uORB is a "
                      "char array, as in PX4's log_message)",
            "wstring": "uORB has no wide strings: uORB text is 8-bit, write string<=N (char[N])",
            "binary": "uORB has no binary type: use a fixed uint8[N] array"}
TIMESTAMP_DOC = "time since system start (microseconds)"
#: uORB's node path is ``/obj/<topic><instance>`` within ``orb_maxpath`` (64 bytes with the NUL, uORBCommon.hpp),
#: the instance one digit (ORB_MULTI_MAX_INSTANCES): 57 characters are left for the topic.
MAX_TOPIC = 64 - len("/obj/") - 1 - 1
#: uORB rounds a queue length up to a power of two, at most 128 (round_pow_of_two_8 in uORBDeviceNode.cpp).
QUEUE_LENGTHS = (1, 2, 4, 8, 16, 32, 64, 128)


def queue_depth(declared: int) -> int:
    """The queue uORB keeps for an ORB_QUEUE_LENGTH: the value as a uint8, rounded up to a power of two <= 128."""
    n = declared % 256
    return next((q for q in QUEUE_LENGTHS if q >= n), 128)
_INT_TYPES = (("uint8", 0, 2**8 - 1), ("int8", -(2**7), 2**7 - 1), ("uint16", 0, 2**16 - 1),
              ("int16", -(2**15), 2**15 - 1), ("uint32", 0, 2**32 - 1), ("int32", -(2**31), 2**31 - 1))


class Unsupported(Exception):
    """A type uORB cannot hold: the code and the reason, in words."""

    def __init__(self, code: str, reason: str) -> None:
        super().__init__(reason)
        self.code = code
        self.reason = reason


@dataclass(slots=True)
class Line:
    """One field or constant line of a .msg file."""

    type: str
    name: str
    value: str | None = None
    comment: str = ""


@dataclass(slots=True)
class UorbMessage:
    """One .msg file."""

    name: str
    struct: m.Struct
    doc: list[str]
    lines: list[Line] = field(default_factory=list)
    topics: list[str] = field(default_factory=list)

    @property
    def snake(self) -> str:
        """The header and struct stem PX4 derives from the file name (``SensorAccel`` → ``sensor_accel``)."""
        return snake(self.name)


def uorb_topic(name: str) -> str | None:
    """A ROS-style topic name as a uORB topic name (``/arm/jointState`` → ``arm_joint_state``)."""
    if name.startswith("~") or "{" in name:
        return None
    parts = name.strip("/").split("/")
    converted = [ros_field_name(p) for p in parts]
    if not parts or any(p is None for p in converted):
        return None
    topic = "_".join(converted)  # type: ignore[arg-type]
    return topic if _UORB_TOPIC.match(topic) else None


def bridge_topic(name: str) -> str | None:
    """The uORB topic in a uXRCE-DDS bridge name (``/fmu/out/vehicle_attitude`` → ``vehicle_attitude``), else None.

    The bridge publishes uORB topic ``t`` to ROS 2 as ``/fmu/out/t`` and subscribes
    ``/fmu/in/t``, behind a namespace such as ``/px4_1`` when several vehicles share
    a network. The part after ``/fmu/in|out/`` is returned as written, valid or not.
    """
    m = _BRIDGE_NAME.match(name)
    return m.group("topic") if m else None


class MessageBuilder:
    """Collects the messages a component needs and converts them, reporting what uORB cannot hold."""

    def __init__(self, comp: Compilation, owners: Owners) -> None:
        self.iface = comp.interface
        self.owners = owners
        self.diagnostics: list[Diagnostic] = []
        self.messages: dict[str, UorbMessage] = {}
        self.names: dict[int, str | None] = {}
        self._queue: list[m.Struct] = []
        self.topics: dict[str, tuple[UorbMessage | None, str]] = {}
        #: The uORB topic of each publishes/subscribes wiring, by ``id`` of the wiring.
        self.wired: dict[int, str] = {}

    # ---- collection ------------------------------------------------------------------
    def build(self) -> list[UorbMessage]:
        """Every message of the file and every message or struct they use, converted."""
        for d in self.iface.definitions:
            if isinstance(d, m.Struct) and d.kind == "message":
                self.require(d)
        for w in self.iface.wirings:
            if w.direction in ("publishes", "subscribes") and isinstance(w.type.target, m.Struct):
                self.require(w.type.target)
        while self._queue:
            self._convert(self._queue.pop(0))
        self._wired_topics()
        self._annotated_topics()
        self._default_topics()
        return [self.messages[k] for k in sorted(self.messages)]

    def require(self, struct: m.Struct) -> str | None:
        """The uORB name of ``struct``, queued for conversion the first time it is seen."""
        key = id(struct)
        if key in self.names:
            return self.names[key]
        name = camel(struct.name)
        src = self.owners.source(struct)
        if name is None:
            self.diagnostics.append(diag("px4-name-invalid", f"'{struct.name}' cannot be made a uORB message "
                                         "name (CamelCase)", src, struct.name_span))
        elif name in self.messages:
            other = self.messages[name].struct
            self.diagnostics.append(diag("px4-name-conflict", f"'{struct.name}' and '{other.name}' both become "
                                         f"the uORB message {name}", src, struct.name_span))
            name = None
        else:
            self.messages[name] = UorbMessage(name, struct, comment_lines(struct.doc))
            self._queue.append(struct)
        self.names[key] = name
        return name

    # ---- conversion ------------------------------------------------------------------
    def _convert(self, struct: m.Struct) -> None:
        name = self.names[id(struct)]
        assert name is not None
        msg = self.messages[name]
        src = self.owners.source(struct)
        owner = self.owners.of(struct)
        if struct.kind in ("union", "exception"):
            self.diagnostics.append(diag("px4-unsupported-type", f"'{struct.name}' is a {struct.kind}: uORB "
                                         "messages are plain structs", src, struct.name_span))
        msg.lines.append(self._timestamp(struct, src))
        enums_done: set[int] = set()
        for member in member_order(struct):
            if isinstance(member, m.Const):
                line = self._const(struct, member, owner)
                if line is not None:
                    msg.lines.append(line)
                continue
            if member.name == "timestamp":
                continue
            fname = ros_field_name(member.name)
            if fname is None:
                self.diagnostics.append(diag("px4-name-invalid", f"field '{member.name}' of message "
                                             f"'{struct.name}' cannot be made a uORB field name",
                                             src, member.name_span))
                continue
            if c_family_keyword(fname):
                self.diagnostics.append(diag("px4-reserved-name", f"field '{member.name}' of message "
                                             f"'{struct.name}' is a C++ keyword: PX4 generates a C++ struct member "
                                             f"'{fname}' from it, which does not compile; rename it",
                                             src, member.name_span))
                continue
            if member.default is not None:
                self.diagnostics.append(diag("px4-default", f"field '{member.name}' of message '{struct.name}' "
                                             f"has a default ({member.default.text or member.default.value}): "
                                             "uORB messages have no default values", src, member.default.span))
            try:
                ptype = self.field_type(member.type)
            except Unsupported as e:
                self.diagnostics.append(diag(e.code, f"field '{member.name}' of message '{struct.name}': "
                                             f"{e.reason}", src, member.type.span))
                continue
            msg.lines.append(Line(ptype, fname, None, _field_comment(member)))
            enum = enum_of(member.type if not isinstance(resolve_typedefs(member.type), m.ArrayType)
                           else resolve_typedefs(member.type).element)  # type: ignore[union-attr]
            if enum is not None and id(enum) not in enums_done:
                enums_done.add(id(enum))
                msg.lines.extend(_enum_constants(enum))

    def _timestamp(self, struct: m.Struct, src: m.Source) -> Line:
        found = next((f for f in struct.fields if f.name == "timestamp"), None)
        if found is None:
            self.diagnostics.append(diag("px4-timestamp-added", f"message '{struct.name}' has no timestamp: "
                                         "'uint64 timestamp' is added as its first field (uORB needs it)",
                                         src, struct.name_span))
            return Line("uint64", "timestamp", None, TIMESTAMP_DOC)
        t = resolve_typedefs(found.type)
        if not (isinstance(t, m.BaseType) and t.name == "u64"):
            self.diagnostics.append(diag("px4-timestamp-type", f"field 'timestamp' of message '{struct.name}' is "
                                         f"{type_text(found.type)}: uORB timestamps are u64 (microseconds)",
                                         src, found.type.span))
        return Line("uint64", "timestamp", None, _field_comment(found) or TIMESTAMP_DOC)

    def _const(self, struct: m.Struct, c: m.Const, owner: m.Interface) -> Line | None:
        src = self.owners.source(struct)
        name = ros_constant_name(c.name)
        t = resolve_typedefs(c.type)
        ptype = px4_base(t.name) if isinstance(t, m.BaseType) and t.bound is None else None
        if ptype not in _NUMERIC:
            self.diagnostics.append(diag("px4-unsupported-type", f"constant '{c.name}' of message '{struct.name}' "
                                         f"is {type_text(c.type)}: uORB constants are numbers or bool",
                                         src, c.type.span))
            return None
        if name is None:
            self.diagnostics.append(diag("px4-name-invalid", f"constant '{c.name}' cannot be made a uORB constant "
                                         "name", src, c.name_span))
            return None
        if c_family_keyword(name):
            self.diagnostics.append(diag("px4-reserved-name", f"constant '{c.name}' of message '{struct.name}' is a "
                                         "C++ keyword: PX4 generates a C++ constant of that name, which does not "
                                         "compile; rename it", src, c.name_span))
            return None
        value = literal(owner, c.value)
        if name == "ORB_QUEUE_LENGTH":
            self._queue_length(struct, c, ptype, value, src)
        if isinstance(value, bool) or ptype == "bool":
            text = "1" if value else "0"
        elif isinstance(value, (int, float)):
            if isinstance(value, float) and not value.is_integer():
                self.diagnostics.append(diag("px4-constant-fraction", f"constant '{c.name}' of message "
                                             f"'{struct.name}' is {value!r}: PX4's generator writes every constant "
                                             f"as int(value), so its C++ header says {int(value)} (the .msg keeps "
                                             f"{value!r})", src, c.value.span))
            text = number(value) if ptype in ("float32", "float64") else str(int(value))
        else:
            self.diagnostics.append(diag("px4-unsupported-type", f"constant '{c.name}' of message "
                                         f"'{struct.name}' has no numeric value", src, c.value.span))
            return None
        return Line(ptype, name, text, one_line(c.doc))

    def _queue_length(self, struct: m.Struct, c: m.Const, ptype: str | None, value: object, src: m.Source) -> None:
        """``ORB_QUEUE_LENGTH``: PX4 builds any numeric one and reads it as a uint8; warnings say what uORB keeps."""
        if not isinstance(value, (bool, int, float)):
            return
        if ptype != "uint8":
            self.diagnostics.append(diag("px4-queue-length", f"ORB_QUEUE_LENGTH of message '{struct.name}' is "
                                         f"{type_text(c.type)}: PX4 builds it and reads it as a uint8 (uORB's "
                                         "DefaultQueueSize); PX4's own messages declare 'uint8 ORB_QUEUE_LENGTH = "
                                         f"N' (const u8 ORB_QUEUE_LENGTH = {int(value)})", src, c.type.span))
        kept = queue_depth(int(value))
        if kept != value:
            self.diagnostics.append(diag("px4-queue-length-rounded", f"ORB_QUEUE_LENGTH of message "
                                         f"'{struct.name}' is {value!r}: uORB reads it as a uint8 and rounds it "
                                         f"up to a power of two from 1 to 128, so the queue holds {kept}; write "
                                         f"{kept}", src, c.value.span))

    def field_type(self, t: m.TypeRef) -> str:
        """The uORB spelling of a field type; Unsupported says why there is none."""
        r = resolve_typedefs(t)
        if isinstance(r, m.BaseType):
            if r.bound is not None:
                text = container("bounded_string", "px4", r.name, r.bound)
                if text is not None:
                    return text
            px = px4_base(r.name) if r.bound is None else None
            if px is None:
                raise Unsupported("px4-unsupported-type",
                                  _REASONS.get(r.name, f"uORB has no {r.spelling or r.name} type"))
            return px
        if isinstance(r, m.ArrayType):
            if r.array != "fixed":
                raise Unsupported("px4-variable-array", f"{type_text(r)} has a variable length: uORB arrays "
                                  "have a fixed size (T[N])")
            inner = self.field_type(r.element)
            if "[" in inner:
                raise Unsupported("px4-unsupported-type", f"uORB has no arrays of arrays ({type_text(r)})")
            return container("fixed", "px4", inner, r.size)  # type: ignore[return-value]
        if isinstance(r, m.SetType):
            raise Unsupported("px4-unsupported-type", f"uORB has no sets ({type_text(r)}): use a fixed array")
        if isinstance(r, m.MapType):
            raise Unsupported("px4-unsupported-type", f"uORB has no maps ({type_text(r)})")
        target = r.target
        if target is None:
            if r.external in PX4_PACKAGES:
                name = camel(r.local_name)
                if name is not None:
                    return name
            if r.external:
                raise Unsupported("px4-external-type", f"'{r.name}' comes from the package '{r.external}', which "
                                  "PX4 does not have (only px4_msgs types can be used)")
            raise Unsupported("px4-unsupported-type", f"unknown type '{r.name}'")
        if isinstance(target, m.Enum):
            return enum_int_type(target)
        if isinstance(target, m.Struct):
            if target.kind in ("union", "exception"):
                raise Unsupported("px4-unsupported-type", f"'{r.name}' is a {target.kind}: uORB has plain "
                                  "structs only")
            name = self.require(target)
            if name is None:
                raise Unsupported("px4-name-invalid", f"'{r.name}' has no uORB message name")
            return name
        raise Unsupported("px4-unsupported-type", f"'{r.name}' is a {target.kind}, not a type uORB can hold")

    # ---- topics ------------------------------------------------------------------
    def _wired_topics(self) -> None:
        src = self.iface.source
        for w in self.iface.wirings:
            if w.direction not in ("publishes", "subscribes"):
                continue
            topic = self._wired_topic(w)
            if topic is None:
                continue
            self.wired[id(w)] = topic
            target = w.type.target
            msg = self.messages.get(self.names.get(id(target)) or "") if isinstance(target, m.Struct) else None
            type_name = msg.name if msg else w.type.name
            self._claim(topic, msg, type_name, src, w.topic_span)

    def _wired_topic(self, w: m.Wiring) -> str | None:
        """The uORB topic of a wiring (reporting why there is none, or what is assumed).

        A bridge name ``[/ns]/fmu/in|out/<topic>`` names the uORB topic ``<topic>``.
        Any other name of a message PX4 already has (``px4_msgs.X``) cannot name a
        uORB topic, whose names PX4 fixes: the topic is taken to be the snake_case
        message name, with a warning unless the name says just that. The name of a
        topic of the component's own messages is made a uORB name
        (``/arm/jointState`` → ``arm_joint_state``).
        """
        src = self.iface.source
        bridged = bridge_topic(w.topic)
        if bridged is not None:
            if _UORB_TOPIC.match(bridged):
                return bridged
            self.diagnostics.append(diag("px4-topic-invalid", f"topic '{w.topic}': '{bridged}' is not a uORB topic "
                                         "name (snake_case)", src, w.topic_span))
            return None
        if w.type.target is None and w.type.external in PX4_PACKAGES:
            assumed = snake(w.type.local_name)
            if uorb_topic(w.topic) != assumed:
                self.diagnostics.append(diag("px4-topic-assumed", f"topic '{w.topic}' is not a uXRCE-DDS bridge name "
                                             f"(/fmu/out/<topic>, /fmu/in/<topic>): the uORB topic of {w.type.name} "
                                             f"is assumed to be '{assumed}', its snake_case name (write "
                                             "'/fmu/out/<topic>' or '/fmu/in/<topic>' to name another uORB topic)",
                                             src, w.topic_span))
            return assumed
        topic = uorb_topic(w.topic)
        if topic is None:
            self.diagnostics.append(diag("px4-topic-invalid", f"topic '{w.topic}' has no uORB name: uORB "
                                         "topics are snake_case names without namespaces or substitutions",
                                         src, w.topic_span))
        return topic

    def _annotated_topics(self) -> None:
        for name in sorted(self.messages):
            msg = self.messages[name]
            a = m.annotation(msg.struct.annotations, "px4.topics")
            if a is None:
                continue
            src = self.owners.source(msg.struct)
            for raw in re.split(r"[\s,]+", a.text.strip()):
                if not raw:
                    continue
                if not _UORB_TOPIC.match(raw):
                    self.diagnostics.append(diag("px4-topic-invalid", f"'{raw}' in px4.topics of '{msg.struct.name}' "
                                                 "is not a uORB topic name (snake_case)", src, a.span))
                    continue
                self._claim(raw, msg, msg.name, src, a.span)

    def _default_topics(self) -> None:
        """A message without a ``# TOPICS`` line gets the topic of its snake_case name: it must fit too."""
        for name in sorted(self.messages):
            msg = self.messages[name]
            if not msg.topics:
                self._too_long(msg.snake, self.owners.source(msg.struct), msg.struct.name_span,
                               f"the topic of message '{msg.struct.name}' (its snake_case name)")

    def _too_long(self, topic: str, src: m.Source, span: m.Span, what: str) -> None:
        if len(topic) > MAX_TOPIC:
            self.diagnostics.append(diag("px4-topic-too-long", f"{what}, '{topic}', has {len(topic)} characters: "
                                         f"PX4 builds it, but uORB cannot advertise a topic over {MAX_TOPIC} "
                                         "(its node path /obj/<topic><instance> must fit in 64 bytes, else "
                                         "node_mkpath fails with ENAMETOOLONG)", src, span))

    def _claim(self, topic: str, msg: UorbMessage | None, type_name: str, src: m.Source, span: m.Span) -> None:
        self._too_long(topic, src, span, "uORB topic")
        first = self.topics.get(topic)
        if first is not None and first[1] != type_name:
            self.diagnostics.append(diag("px4-topic-conflict", f"uORB topic '{topic}' would carry both {type_name} "
                                         f"and {first[1]}: a uORB topic has one message type", src, span))
            return
        self.topics[topic] = (msg, type_name)
        if msg is not None and topic not in msg.topics:
            msg.topics.append(topic)


def _field_comment(f: m.Field) -> str:
    unit = f"[{one_line(f.unit)}]" if f.unit else ""
    return " ".join(x for x in (unit, one_line(f.doc)) if x)


def _enum_constants(enum: m.Enum) -> list[Line]:
    ptype = enum_int_type(enum)
    prefix = upper(enum.name)
    out = []
    for v in enum.values:
        name = upper(v.name)
        if not name.startswith(prefix + "_"):
            name = f"{prefix}_{name}"
        out.append(Line(ptype, name, str(v.value), one_line(v.doc)))
    return out


def enum_int_type(enum: m.Enum) -> str:
    """The smallest integer type (uORB spelling) that holds every value of ``enum``."""
    values = [v.value for v in enum.values] or [0]
    for name, lo, hi in _INT_TYPES:
        if lo <= min(values) and max(values) <= hi:
            return name
    return "int64"
