"""PX4's own uORB messages and topics: a component's message or topic of the same name is a collision.

Generated into a PX4 tree, ``msg/VehicleStatus.msg`` would replace PX4's own message, and a
topic ``vehicle_status`` carrying another type would clash with the one PX4 publishes. The names
are data (``upstream.json``), taken from a PX4 release by ``scripts/px4_upstream_names.py``; the
warning names the release. A file that is PX4's message set itself (named or namespaced
``px4_msgs``, as ``import --from px4`` writes it) is not checked.
"""

from __future__ import annotations

import functools
import json
from dataclasses import dataclass
from importlib.resources import files

from ...model import nodes as m
from ...model.diagnostics import Diagnostic
from .codes import diag
from .messages import PX4_PACKAGES, MessageBuilder


@dataclass(frozen=True)
class Upstream:
    """PX4's message names with their topics, and the release they come from."""

    version: str
    messages: dict[str, tuple[str, ...]]

    @functools.cached_property
    def topics(self) -> dict[str, str]:
        """uORB topic → the PX4 message it carries."""
        return {t: name for name, topics in self.messages.items() for t in topics}


@functools.cache
def upstream() -> Upstream:
    """The shipped list (``upstream.json``)."""
    data = json.loads(files(__package__ or "iface.emit.px4").joinpath("upstream.json").read_text(encoding="utf-8"))
    return Upstream(str(data["px4_version"]), {k: tuple(v) for k, v in data["messages"].items()})


def is_px4_own(iface: m.Interface) -> bool:
    """True for PX4's message set itself (``px4_msgs.iface``, or a px4/ros2 namespace px4_msgs)."""
    names = {iface.source.path.replace("\\", "/").rsplit("/", 1)[-1].rsplit(".", 1)[0],
             iface.namespace("px4") or "", iface.namespace("ros2") or ""}
    return bool(names & PX4_PACKAGES)


def collisions(iface: m.Interface, builder: MessageBuilder) -> list[Diagnostic]:
    """A warning for each generated message or topic that has the name of one of PX4's own."""
    if is_px4_own(iface):
        return []
    up = upstream()
    out: list[Diagnostic] = []
    for name in sorted(builder.messages):
        msg = builder.messages[name]
        if name in up.messages:
            out.append(diag("px4-upstream-name", f"message '{msg.struct.name}' becomes msg/{name}.msg, the name of "
                            f"PX4's own uORB message {name} (PX4 {up.version}): in a PX4 tree it would replace it; "
                            f"rename it, or use px4_msgs.{name} if it is meant to be PX4's",
                            builder.owners.source(msg.struct), msg.struct.name_span))
    seen: set[str] = set()
    for w in iface.wirings:
        topic = builder.wired.get(id(w))
        if topic is not None and topic not in seen:
            seen.add(topic)
            _topic(out, topic, builder, iface.source, w.topic_span)
    for name in sorted(builder.messages):
        msg = builder.messages[name]
        a = m.annotation(msg.struct.annotations, "px4.topics")
        for topic in msg.topics:
            if a is not None and topic not in seen:
                seen.add(topic)
                _topic(out, topic, builder, builder.owners.source(msg.struct), a.span)
    return out


def _topic(out: list[Diagnostic], topic: str, builder: MessageBuilder, src: m.Source, span: m.Span) -> None:
    up = upstream()
    owner = up.topics.get(topic)
    msg = builder.topics.get(topic, (None, ""))[0]
    if owner is None or msg is None or msg.name == owner:
        return  # not PX4's topic; PX4's own message on it; or the message name was reported already
    out.append(diag("px4-upstream-name", f"uORB topic '{topic}' is PX4's own topic of {owner} (PX4 {up.version}); "
                    f"here it would carry {msg.name}, and a uORB topic has one message type: choose another "
                    "topic name", src, span))
