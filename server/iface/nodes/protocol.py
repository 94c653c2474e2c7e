"""The protocol every generated component speaks, whatever its language (docs/runtime.md).

The protocol's types live in one ROS 2 interface package, ``iface_msgs`` (``PACKAGE``), written
from ``MESSAGES`` and ``SERVICES`` below by ``iface.nodes.shared`` beside the components, so
every component speaks it through the same types (``iface_msgs/srv/SaveState``…) and a tool that
talks to many components needs one type per service. Add a message or a service by adding it to
``MESSAGES`` or ``SERVICES`` and raising ``PACKAGE_VERSION``'s minor number; a change that old
nodes cannot answer raises ``PROTOCOL_VERSION`` (and the major number).

A component node serves four services beside its own members, under names relative to the
node (``~/save_state`` is ``/robot_arm/save_state`` for a node ``robot_arm``), so that two
instances of one component run side by side:

- ``~/save_state`` (``SaveState``): the state Σ as a *state document*, taken between work
  transactions;
- ``~/restore_state`` (``RestoreState``): put a state document into the node, or refuse it
  with the reason;
- ``~/control`` (``ComponentControl``): status, pause after the current work transaction,
  resume, save;
- ``~/describe`` (``Describe``): the component's name, version, interface hash, runtime and
  protocol versions and its whole interface (the ``json`` target's form), so a tool learns a
  running component's interface without its file.

They are answered from the control thread, also while the main callbacks are busy.

The state document is JSON (UTF-8, keys sorted, no spaces)::

    {"format": "iface-state/1", "protocol_version": "1", "component": "robot_arm", "version": "1.2.0",
     "interface_hash": "sha256:…", "schema": {"mode": "int32", …},
     "types": {"robot_arm_msgs/JointLimits": {"lower": "float64", …}},
     "values": {"mode": 0, …}}

``schema`` gives each state variable's ROS type (``.msg`` spelling, message types qualified by
their package), ``types`` the fields of the message types the schema uses, ``values`` the
values: numbers, strings, booleans, lists, and objects for messages; a float that JSON cannot
hold is the string ``"nan"``, ``"inf"`` or ``"-inf"``. A node takes a document when every
variable of the document has a place in it of the same type or a wider one (the rule of
``compat``'s ``state-type-widened``), and refuses it otherwise, naming the variable.
"""

from __future__ import annotations

from dataclasses import dataclass

#: The version of the protocol: in the state document, ``ComponentControl`` and ``Describe`` answers.
PROTOCOL_VERSION = "1"
#: The interface package of the protocol, and its version (major: PROTOCOL_VERSION; minor: raised when a
#: message or service is added).
PACKAGE = "iface_msgs"
PACKAGE_VERSION = f"{PROTOCOL_VERSION}.2.0"
#: The version tag of the state document.
STATE_FORMAT = "iface-state/1"
#: The runtimes a component may run on (``Describe.runtime``).
RUNTIMES = ("rclpy", "rclcpp")
#: Node-relative service names.
SAVE_STATE = "~/save_state"
RESTORE_STATE = "~/restore_state"
CONTROL = "~/control"
DESCRIBE = "~/describe"
#: Served by a component container (iface_runtime_cpp's iface_container), not by a component.
HAND_OVER = "~/handover"
#: Where every component publishes diagnostic_msgs/DiagnosticArray.
DIAGNOSTICS_TOPIC = "/diagnostics"
#: Diagnostics rate when the file gives none (diagnostic_updater's default).
DEFAULT_DIAGNOSTICS_RATE = 1.0
#: How long PAUSE, SAVE and RESTORE wait for a work transaction to end when the request says 0.
DEFAULT_TIMEOUT_SEC = 10.0
#: PAUSE first lets the next tick of a work timer run when it is due within this many seconds, so that
#: a hand-over's silence on the timer's topic holds the critical section only, not also part of a period.
ALIGN_SEC = 0.1

#: ComponentControl commands.
STATUS, PAUSE, RESUME, SAVE = 0, 1, 2, 3
COMMANDS = {"status": STATUS, "pause": PAUSE, "resume": RESUME, "save": SAVE}


@dataclass(frozen=True, slots=True)
class SrvField:
    """A field of a protocol service: ROS type, name, comment."""

    type: str
    name: str
    comment: str = ""


@dataclass(frozen=True, slots=True)
class SrvConst:
    """A constant of a protocol service."""

    type: str
    name: str
    value: int
    comment: str = ""


@dataclass(frozen=True, slots=True)
class ProtocolMessage:
    """One protocol message type: its name in ``iface_msgs``, doc lines, fields, constants."""

    type_name: str
    doc: tuple[str, ...]
    fields: tuple[SrvField, ...]
    consts: tuple[SrvConst, ...] = ()


@dataclass(frozen=True, slots=True)
class ProtocolService:
    """One protocol service type: its name in ``iface_msgs``, the node-relative name it is served under."""

    type_name: str
    served_as: str
    doc: tuple[str, ...]
    request: tuple[SrvField, ...]
    response: tuple[SrvField, ...]
    consts: tuple[SrvConst, ...] = ()


_TIMEOUT = SrvField("float64", "timeout_sec", "how long to wait for the current work transaction to end "
                    f"(0: {DEFAULT_TIMEOUT_SEC:g} s)")
_HASH = SrvField("string", "interface_hash", "the interface hash of this node (sha256:…)")
_PROTOCOL = SrvField("string", "protocol_version", f"the protocol version the node speaks ({PROTOCOL_VERSION})")

#: The messages of ``iface_msgs``: the component manager's (docs/system.md).
MESSAGES: tuple[ProtocolMessage, ...] = (
    ProtocolMessage(
        "InstanceStatus", ("One instance of a managed system, as the component manager sees it.",),
        (SrvField("string", "name", "the instance name in the system file"),
         SrvField("string", "node", "its node's fully qualified name"),
         SrvField("string", "component", "the component it runs (after a replacement: NEW's)"),
         SrvField("string", "state", "down, starting, inactive, active, stopped (not restarted by its policy) "
                  "or failed (past the restart limit)"),
         SrvField("int32", "pid", "its process id (0 while down)"),
         SrvField("uint32", "restarts", "restarts by the manager since it started"),
         SrvField("string", "interface_hash", "the interface hash of what runs (sha256:…)"),
         SrvField("string", "last_snapshot", "time of its last snapshot, ISO 8601 UTC (empty: none)"),
         SrvField("string[]", "findings", "what went wrong, oldest first"),
         SrvField("string", "container", "the component container it is loaded into (empty: a process of its own; "
                  "pid is the container's)"))),
)

#: The services of ``iface_msgs``; the first three are the ones every component served before ``Describe``.
SERVICES: tuple[ProtocolService, ...] = (
    ProtocolService(
        "SaveState", SAVE_STATE,
        ("Save the state of the component (Σ) as a state document (JSON, format iface-state/1).",
         "The node waits for the current work transaction to end, so the state is consistent."),
        (_TIMEOUT,),
        (SrvField("bool", "success"), SrvField("string", "message", "why it failed, or what was saved"),
         SrvField("string", "state", "the state document"), _HASH)),
    ProtocolService(
        "RestoreState", RESTORE_STATE,
        ("Restore a state document saved by this component or by one it may replace.",
         "Refused, with the reason, when a variable has no place here or a type this node cannot hold."),
        (SrvField("string", "state", "the state document"), _TIMEOUT),
        (SrvField("bool", "success"), SrvField("string", "message", "why it was refused, or what was restored"),
         SrvField("string[]", "restored", "variables set from the document"),
         SrvField("string[]", "kept", "variables of this node the document does not have: they keep their values"),
         _HASH)),
    ProtocolService(
        "ComponentControl", CONTROL,
        ("Control of a running component: answered from the control thread, also while work is in progress.",
         "PAUSE returns once the current work transaction has ended (and the next tick of a work timer due within",
         f"{ALIGN_SEC:g} s has run); new work is then refused until RESUME, and the answer carries the state."),
        (SrvField("uint8", "command"), _TIMEOUT),
        (SrvField("bool", "success"), SrvField("string", "message"),
         SrvField("bool", "paused", "true while work is refused"),
         SrvField("uint8", "lifecycle_state", "lifecycle_msgs/State id"),
         SrvField("uint32", "in_flight", "work transactions running now"),
         SrvField("uint64", "transactions", "work transactions done since the start"),
         SrvField("string", "component"), SrvField("string", "version"), _HASH,
         SrvField("string", "state", "SAVE, PAUSE: the state document (PAUSE: as it was at the pause)"), _PROTOCOL,
         SrvField("uint32", "pid", "the process the node runs in"),
         SrvField("string[]", "publisher_topics", "the topic of each of the node's publishers (while configured)"),
         SrvField("uint32[]", "publisher_matched", "how many subscriptions each of them has matched")),
        (SrvConst("uint8", "STATUS", STATUS, "read the status"),
         SrvConst("uint8", "PAUSE", PAUSE, "pause after the current work transaction"),
         SrvConst("uint8", "RESUME", RESUME, "accept work again"),
         SrvConst("uint8", "SAVE", SAVE, "save the state (as SaveState)"))),
    ProtocolService(
        "Describe", DESCRIBE,
        ("What a running component is: its name, version, interface hash, runtime, protocol version,",
         "and its whole interface in the JSON form (`iface-lsp generate --target json`)."),
        (),
        (SrvField("string", "node_name", "the node's fully qualified name"),
         SrvField("string", "component", "the component's name in its .iface file"),
         SrvField("string", "version", "the component's version"), _HASH,
         SrvField("string", "runtime", "rclpy or rclcpp"),
         SrvField("string", "runtime_version", "the version of the iface runtime package the node runs on"),
         _PROTOCOL,
         SrvField("string", "interface_json", "the interface as `iface-lsp generate --target json` writes it"))),
    ProtocolService(
        "SystemStatus", "/iface_manager/status", ("The status of every instance of a managed system.",),
        (), (SrvField("string", "system", "the system's name"),
             SrvField("InstanceStatus[]", "instances", "in start order"))),
    ProtocolService(
        "Snapshot", "/iface_manager/snapshot", ("Save the state of running instances to the state folder now.",),
        (SrvField("string", "instance", "one instance (empty: every one)"),),
        (SrvField("bool", "success", "every chosen instance was saved"), SrvField("string", "message"),
         SrvField("string[]", "files", "the snapshot files written"))),
    ProtocolService(
        "Replace", "/iface_manager/replace",
        ("Replace an instance by a new package and interface: compat against the rest of the system, trust,",
         "the hand-over, then a grace period; rolled back (OLD active again with its state) when NEW fails."),
        (SrvField("string", "instance"), SrvField("string", "new_iface", "the .iface file of NEW"),
         SrvField("string", "package", "NEW's install folder (ws/install/<package>)"), _TIMEOUT),
        (SrvField("bool", "success", "NEW took over"),
         SrvField("string", "result", "replaced, refused or rolled_back"),
         SrvField("string", "record", "the hand-over record (JSON, as `iface-lsp handover` prints)"))),
    ProtocolService(
        "HandOver", HAND_OVER,
        ("Hand over inside a component container (iface_runtime_cpp's iface_container), from one component node it",
         "holds (OLD, active) to another (NEW, configured), with no DDS round trip in the critical section: right",
         "after a tick of OLD's work timer (when one is due within the alignment time), OLD pauses, its state",
         "document is restored into NEW, NEW is activated on OLD's schedule, OLD is deactivated and resumed."),
        (SrvField("string", "old_node", "OLD's fully qualified node name"),
         SrvField("string", "new_node", "NEW's fully qualified node name"), _TIMEOUT),
        (SrvField("bool", "success", "NEW took over; otherwise OLD is as it was (active, not paused)"),
         SrvField("string", "message", "why it failed, or what was done"),
         SrvField("string", "state", "OLD's state document at the pause (what NEW restored)"),
         SrvField("string[]", "restored", "variables NEW set from the document"),
         SrvField("string[]", "kept", "variables of NEW the document does not have"),
         SrvField("float64", "pause_ms", "from the request to OLD paused: its next tick and its work in progress"),
         SrvField("float64", "critical_ms", "from OLD paused to NEW active"),
         SrvField("string", "after_tick", "the work timer of OLD whose tick the switch followed (empty: none was "
                  "due, the switch came between transactions)"))),
)
SERVICE_TYPES = tuple(s.type_name for s in SERVICES)
#: The services every component node serves whose types its generated code names (beside ``Describe``).
COMPONENT_SERVICES = tuple(s for s in SERVICES if s.type_name in ("SaveState", "RestoreState", "ComponentControl"))
