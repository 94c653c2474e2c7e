"""What the ROS 2 graph tells of one running node, as plain data (nothing here imports ROS)."""

from __future__ import annotations

from dataclasses import dataclass, field

#: Node-relative services every rclpy/rclcpp node serves (parameters, type description).
PARAMETER_SERVICES = ("describe_parameters", "get_parameter_types", "get_parameters", "get_type_description",
                      "list_parameters", "set_parameters", "set_parameters_atomically")
#: Node-relative services of a lifecycle node.
LIFECYCLE_SERVICES = ("change_state", "get_available_states", "get_available_transitions", "get_state",
                      "get_transition_graph")
#: Topics every node (or every lifecycle node) has.
OWN_TOPICS = ("/rosout", "/parameter_events")
LIFECYCLE_TOPIC = "transition_event"
#: The node-relative service of iface's Describe (issue 26's runtime).
DESCRIBE_SERVICE = "describe"
DESCRIBE_TYPE = "iface_msgs/srv/Describe"


@dataclass(frozen=True, slots=True)
class Qos:
    """The QoS of one endpoint as the graph tells it; durations in seconds, None when infinite/default."""

    reliability: str
    durability: str
    liveliness: str
    deadline: float | None = None
    lifespan: float | None = None
    lease_duration: float | None = None
    #: From the node's ``qos_overrides.<topic>.<publisher|subscription>.*`` parameters, when it declares them.
    history: str | None = None
    depth: int | None = None


@dataclass(frozen=True, slots=True)
class TopicEndpoint:
    """A publisher or subscription of the node: role (``publishes``/``subscribes``), topic, type, QoS."""

    role: str
    topic: str
    type: str
    qos: Qos


@dataclass(frozen=True, slots=True)
class NamedEndpoint:
    """A service or action the node provides or calls: role (``provides``/``calls``), kind, name, type."""

    role: str
    kind: str
    name: str
    type: str


@dataclass(frozen=True, slots=True)
class Param:
    """A parameter with its descriptor: kind (``bool``, ``integer``, ``double``, ``string`` and ``*_array``)."""

    name: str
    kind: str
    value: bool | int | float | str | tuple[bool | int | float | str, ...] | None
    description: str = ""
    read_only: bool = False
    low: float | int | None = None
    high: float | int | None = None
    constraints: str = ""


@dataclass(slots=True)
class NodeReading:
    """One running node: its full name and what the graph tells of it."""

    name: str
    topics: list[TopicEndpoint] = field(default_factory=list)
    endpoints: list[NamedEndpoint] = field(default_factory=list)
    params: list[Param] = field(default_factory=list)
    lifecycle: bool = False
    #: The JSON form of its interface when it answers Describe, with the answer's hash.
    describe_json: str = ""
    describe_hash: str = ""
    #: What could not be read (a parameter service that did not answer…).
    notes: list[str] = field(default_factory=list)
    #: Its services inside the node (``get_state`` for ``/talker/get_state``) and their types.
    own_services: dict[str, str] = field(default_factory=dict)

    @property
    def base(self) -> str:
        """The node's name without its namespace."""
        return self.name.rsplit("/", 1)[-1]

    def relative(self, name: str) -> str | None:
        """``name`` relative to the node (``/talker/get_state`` → ``get_state``), or None when outside it."""
        prefix = self.name.rstrip("/") + "/"
        return name[len(prefix):] if name.startswith(prefix) else None

    def is_ros_own(self, name: str, kind: str) -> bool:
        """True for ROS 2's own endpoints: parameter and type-description services, /rosout, lifecycle's."""
        if kind == "topic":
            rel = self.relative(name)
            return name in OWN_TOPICS or (self.lifecycle and rel == LIFECYCLE_TOPIC)
        rel = self.relative(name)
        if rel is None:
            return False
        return rel in PARAMETER_SERVICES or (self.lifecycle and rel in LIFECYCLE_SERVICES) or rel == DESCRIBE_SERVICE
