"""The protocol every generated component speaks, whatever its language (docs/runtime.md).

A component node serves three services beside its own members, under names relative to the
node (``~/save_state`` is ``/robot_arm/save_state`` for a node ``robot_arm``), so that two
instances of one component run side by side:

- ``~/save_state`` (``SaveState``): the state Σ as a *state document*, taken between work
  transactions;
- ``~/restore_state`` (``RestoreState``): put a state document into the node, or refuse it
  with the reason;
- ``~/control`` (``ComponentControl``): status, pause after the current work transaction,
  resume, save.

Their types are written into the component's interface package (``<pkg>/srv/SaveState.srv``…),
so a node needs nothing but that package. They are answered from the control thread, also
while the main callbacks are busy.

The state document is JSON (UTF-8, keys sorted, no spaces)::

    {"format": "iface-state/1", "component": "robot_arm", "version": "1.2.0",
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

#: The version tag of the state document.
STATE_FORMAT = "iface-state/1"
#: Node-relative service names.
SAVE_STATE = "~/save_state"
RESTORE_STATE = "~/restore_state"
CONTROL = "~/control"
#: Where every component publishes diagnostic_msgs/DiagnosticArray.
DIAGNOSTICS_TOPIC = "/diagnostics"
#: Diagnostics rate when the file gives none (diagnostic_updater's default).
DEFAULT_DIAGNOSTICS_RATE = 1.0
#: How long PAUSE, SAVE and RESTORE wait for a work transaction to end when the request says 0.
DEFAULT_TIMEOUT_SEC = 10.0

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
class ProtocolService:
    """One protocol service type: its name in the interface package, the node-relative name it is served under."""

    type_name: str
    served_as: str
    doc: tuple[str, ...]
    request: tuple[SrvField, ...]
    response: tuple[SrvField, ...]
    consts: tuple[SrvConst, ...] = ()


_TIMEOUT = SrvField("float64", "timeout_sec", "how long to wait for the current work transaction to end "
                    f"(0: {DEFAULT_TIMEOUT_SEC:g} s)")
_HASH = SrvField("string", "interface_hash", "the interface hash of this node (sha256:…)")

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
         "PAUSE returns once the current work transaction has ended; new work is then refused until RESUME."),
        (SrvField("uint8", "command"), _TIMEOUT),
        (SrvField("bool", "success"), SrvField("string", "message"),
         SrvField("bool", "paused", "true while work is refused"),
         SrvField("uint8", "lifecycle_state", "lifecycle_msgs/State id"),
         SrvField("uint32", "in_flight", "work transactions running now"),
         SrvField("uint64", "transactions", "work transactions done since the start"),
         SrvField("string", "component"), SrvField("string", "version"), _HASH,
         SrvField("string", "state", "SAVE: the state document")),
        (SrvConst("uint8", "STATUS", STATUS, "read the status"),
         SrvConst("uint8", "PAUSE", PAUSE, "pause after the current work transaction"),
         SrvConst("uint8", "RESUME", RESUME, "accept work again"),
         SrvConst("uint8", "SAVE", SAVE, "save the state (as SaveState)"))),
)
SERVICE_TYPES = tuple(s.type_name for s in SERVICES)
