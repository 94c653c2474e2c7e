"""A node reading as an ``.iface`` file: what the graph tells, the types' packages as ``external``.

The text is laid out as ``iface-lsp fmt`` lays it out and passes ``check``. QoS policies are written
where they differ from ROS 2's defaults (reliable, volatile, automatic, infinite durations, keep_last
of depth 10); history and depth only where the node's ``qos_overrides.*`` parameters tell them, a
comment says so where they do not. Names inside the node (``/ns/node/x``) are written ``~/x``.
"""

from __future__ import annotations

import keyword
import math
import re
from dataclasses import dataclass

from ..text.formatter import format_text
from ..text.printer import quote
from .filters import own_endpoints, own_params, own_topics, serves_protocol
from .reading import NodeReading, Param, Qos

_PARAM_TYPES = {"bool": "bool", "integer": "i64", "double": "float64", "string": "string", "byte_array": "octet[]",
                "bool_array": "bool[]", "integer_array": "i64[]", "double_array": "float64[]",
                "string_array": "string[]"}
_INT64 = (-(2 ** 63), 2 ** 63 - 1)
_IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
#: History and depth of a QoS profile the graph does not tell: the comment above such a wiring.
UNKNOWN_DEPTH = "// qos.history and qos.depth: the graph does not tell them (no qos_overrides parameters)"


@dataclass(frozen=True, slots=True)
class Imported:
    """One imported node: the file name, its text, the component name."""

    path: str
    text: str
    component: str


def component_name(node: str) -> str:
    """An ``.iface`` identifier for a node's base name."""
    base = re.sub(r"\W", "_", node.rsplit("/", 1)[-1]) or "node"
    if base[0].isdigit() or keyword.iskeyword(base):
        base = "n_" + base
    return base


def iface_type(ros_type: str) -> tuple[str, str]:
    """``pkg/msg/Name`` → (``pkg.Name``, ``pkg``)."""
    parts = ros_type.split("/")
    return f"{parts[0]}.{parts[-1]}", parts[0]


def shown_name(snap: NodeReading, name: str) -> str:
    """A graph name as the file writes it: ``~/x`` inside the node."""
    rel = snap.relative(name)
    return "~/" + rel if rel else name


def duration_text(seconds: float) -> str:
    """Seconds as a QoS duration (``2s``, ``0.25s``)."""
    return f"{seconds:g}s"


def qos_annotations(q: Qos) -> list[str]:
    """The non-default QoS policies of one endpoint as annotations."""
    out = []
    if q.reliability not in ("reliable", "unknown", "system_default"):
        out.append(f'qos.reliability = "{q.reliability}"')
    if q.durability not in ("volatile", "unknown", "system_default"):
        out.append(f'qos.durability = "{q.durability}"')
    if q.history is not None and q.history != "keep_last":
        out.append(f'qos.history = "{q.history}"')
    if q.depth is not None and q.depth != 10 and q.history != "keep_all":
        out.append(f"qos.depth = {q.depth}")
    if q.deadline is not None:
        out.append(f'qos.deadline = "{duration_text(q.deadline)}"')
    if q.lifespan is not None:
        out.append(f'qos.lifespan = "{duration_text(q.lifespan)}"')
    if q.liveliness not in ("automatic", "unknown", "system_default"):
        out.append(f'qos.liveliness = "{q.liveliness}"')
    if q.lease_duration is not None:
        out.append(f'qos.liveliness_lease_duration = "{duration_text(q.lease_duration)}"')
    return out


def _number(v: float | int, integer: bool) -> str:
    if integer:
        return str(int(v))
    f = float(v)
    return repr(f) if math.isfinite(f) else "0.0"


def value_text(p: Param) -> str | None:
    """A parameter's current value as an ``.iface`` default (None when it has none)."""
    v = p.value
    if v is None:
        return None
    if isinstance(v, tuple):
        element = Param(p.name, p.kind.removesuffix("_array"), None)
        items = [value_text(Param(p.name, element.kind if p.kind != "byte_array" else "integer", x)) for x in v]
        return "[" + ", ".join(i for i in items if i is not None) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return _number(v, p.kind == "integer")
    return quote(str(v))


def _constraint(p: Param, key: str) -> str:
    for part in p.constraints.split(";"):
        k, _, v = part.partition(":")
        if k.strip() == key:
            return v.strip()
    return ""


def param_lines(p: Param) -> list[str]:
    """A parameter as a field of the ``configuration`` body (with its doc), or a comment when it has no iface name."""
    t = _PARAM_TYPES.get(p.kind, "string")
    if not _IDENT.match(p.name) or keyword.iskeyword(p.name):
        return [f"// parameter '{p.name}' ({p.kind}) has no .iface name: not imported"]
    out = []
    if p.description and p.description != p.name:
        out.append(f"/** {p.description.replace('*/', '* /')} */")
    notes = []
    unit = _constraint(p, "unit")
    if unit:
        notes.append(f"unit = {quote(unit)}")
    if p.low is not None or p.high is not None:
        integer = p.kind == "integer"
        low = "" if p.low is None or (integer and p.low == _INT64[0]) else format(p.low, "g") if not integer \
            else str(int(p.low))
        high = "" if p.high is None or (integer and p.high == _INT64[1]) else format(p.high, "g") if not integer \
            else str(int(p.high))
        if low or high:
            notes.append(f'range = "{low}..{high}"')
    if p.read_only:
        notes.append("read_only")
    default = value_text(p)
    line = f"{t} {p.name}" + (f" = {default}" if default is not None else "")
    if notes:
        line += " (" + ", ".join(notes) + ")"
    out.append(line + ",")
    return out


def node_iface(snap: NodeReading, everything: bool = False) -> Imported:
    """The ``.iface`` file of one node."""
    name = component_name(snap.name)
    annotations = [f"ros2.node = {quote(snap.name)}"]
    if snap.lifecycle:
        annotations.append("ros2.lifecycle")
    lines = [f"/** Imported from the running node {snap.name} (iface-lsp import --from node). */",
             f"component {name} (" + ", ".join(annotations) + ")", ""]
    topics = own_topics(snap, everything)
    endpoints = own_endpoints(snap, everything)
    params = own_params(snap, everything)
    packages = sorted({iface_type(t.type)[1] for t in topics} | {iface_type(e.type)[1] for e in endpoints})
    if packages:
        lines += [f"external {p}" for p in packages] + [""]
    if params:
        lines.append(f"/** Parameters of {snap.name}, their current values as defaults. */")
        lines.append("configuration parameters {")
        for p in params:
            lines += ["    " + x for x in param_lines(p)]
        lines += ["}", ""]
    if serves_protocol(snap) and not everything:
        lines.append("// it serves iface's component protocol (~/save_state, ~/restore_state, ~/control, /diagnostics)")
    for t in topics:
        notes = qos_annotations(t.qos)
        if t.qos.depth is None and t.qos.history is None:
            lines.append(UNKNOWN_DEPTH)
        line = f"{t.role} {iface_type(t.type)[0]} on {quote(shown_name(snap, t.topic))}"
        lines.append(line + (" (" + ", ".join(notes) + ")" if notes else ""))
    for e in endpoints:
        notes = []
        if e.kind == "action":
            notes.append("action")
        elif e.role == "provides" and e.name.rsplit("/", 1)[-1] == "diagnostics":
            notes.append("diagnostics")
        line = f"{e.role} {iface_type(e.type)[0]} on {quote(shown_name(snap, e.name))}"
        lines.append(line + (" (" + ", ".join(notes) + ")" if notes else ""))
    for note in snap.notes:
        lines.append(f"// {note}")
    text = "\n".join(lines).rstrip() + "\n"
    return Imported(f"{name}.iface", format_text(text), name)
