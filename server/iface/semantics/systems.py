"""System files: the instances a ``system`` declares, their annotations, their start order, and the checks.

A system file (docs/language.md, Systems) includes component files and declares ``instance NAME :
COMPONENT (annotations)``; COMPONENT is the component an included file declares. What is checked here
reads the file and its includes only; the conflicts of the running graph (types, QoS) are the system
graph's (``compat.systemfile``).
"""

from __future__ import annotations

import difflib
import os
import re
from collections.abc import Iterator

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, Severity, make
from ..model.source import Span
from .validate import rule

#: The annotations an instance takes, with what each says (hover and completion show it).
ANNOTATIONS: dict[str, str] = {
    "package": "the ROS 2 package the instance runs from (default: the package `generate --target rclpy` "
               "writes for its component)",
    "executable": "the executable of that package (default: the package's entry point, named as the package)",
    "node": "the ROS 2 node name (default: the instance name)",
    "restart": 'what the manager does when the instance fails: "never", "on-failure" (default) or "always"',
    "snapshot": 'how often the manager saves its state, a period like "1s" or "500ms" '
                "(default: only on deactivate and on request)",
    "after": "an instance this one starts after (default: declaration order); may be given more than once",
    "parameters": "a YAML parameter file, relative to the system file",
    "container": "the component container (an rclcpp process, named by its node name) the instance is loaded "
                 "into; instances naming one container share its process and fail together (default: a process "
                 "of its own)",
    "runtime": 'which of its component\'s generated packages the instance runs: "rclpy" (`generate --target '
               'rclpy`) or "rclcpp" (`--target rclcpp`); default "rclcpp" in a container, else "rclpy"',
    "plugin": "the rclcpp component class a container loads (default: `<package>::<Class>`, the class "
              "`generate --target rclcpp` registers)",
    "intra_process": 'in a container: "true" (default) or "false", whether its publishers and subscriptions '
                     "reach the container's other instances in-process where their QoS allows it (volatile, "
                     "keep_last)",
    "standby": '"true": the manager keeps a spare process of the instance (in a container: of its container) started '
               "ahead, ROS up and no node yet, which becomes the instance (the container) when its process fails: a "
               'restart without a process start or a new participant to discover; "false" (default) saves that '
               "process's memory",
}
RESTART = ("never", "on-failure", "always")
DEFAULT_RESTART = "on-failure"
RUNTIMES = ("rclpy", "rclcpp")
BOOLEANS = ("true", "false")
#: The component manager's own node: no instance or container may take its name.
MANAGER_NODE = "iface_manager"
#: Annotations that only an instance in a container uses, and one it does not.
CONTAINER_ONLY = ("plugin", "intra_process")
NOT_IN_CONTAINER = ("executable",)
_PERIOD = re.compile(r"^\s*([0-9]+(?:\.[0-9]*)?|\.[0-9]+)\s*(ms|s|min)\s*$")
_UNITS = {"ms": 1e-3, "s": 1.0, "min": 60.0}
_NODE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_NAMES = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")
_PLUGIN = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(::[A-Za-z_][A-Za-z0-9_]*)+$")


def period(text: str) -> float | None:
    """Seconds from ``"1s"``, ``"500ms"`` or ``"2min"``; None when it is no positive period."""
    found = _PERIOD.match(text)
    if found is None:
        return None
    value = float(found.group(1)) * _UNITS[found.group(2)]
    return value if value > 0 else None


def is_node_name(text: str) -> bool:
    """True for a name ROS 2 takes as a node name (letters, digits and underscores, not a digit first)."""
    return _NODE.match(text) is not None


def runtime(inst: m.Instance) -> str:
    """The instance's runtime: its ``runtime`` annotation, else rclcpp in a container and rclpy outside one."""
    given = inst.value("runtime")
    if given in RUNTIMES:
        return given
    return "rclcpp" if inst.value("container") else "rclpy"


def intra_process(inst: m.Instance) -> bool:
    """Whether an instance in a container uses intra-process communication (the default), per ``intra_process``."""
    return inst.value("container") is not None and inst.value("intra_process") != "false"


def standby(inst: m.Instance) -> bool:
    """Whether the manager keeps a spare process for the instance, or for its container (``standby = "true"``)."""
    return inst.value("standby") == "true"


def containers(instances: list[m.Instance]) -> list[str]:
    """The containers the instances name, in the order of their first instance."""
    return list(dict.fromkeys(c for c in (i.value("container") for i in instances) if c))


def components(iface: m.Interface) -> dict[str, m.Interface]:
    """The components a system file can instantiate: each included file's interface by its component name."""
    out: dict[str, m.Interface] = {}
    for inc in iface.included.values():
        out.setdefault(inc.name, inc)
    return out


def by_name(iface: m.Interface) -> dict[str, m.Instance]:
    """The instances of a system file by name (the first of a duplicate)."""
    out: dict[str, m.Instance] = {}
    for inst in iface.instances:
        out.setdefault(inst.name, inst)
    return out


def start_order(instances: list[m.Instance]) -> list[m.Instance]:
    """The instances in the order they start: each after those its ``after`` names, declaration order otherwise.

    Among the instances whose predecessors have all started, the first declared goes first. Instances on a
    cycle (an error) and an ``after`` naming no instance are left to declaration order.
    """
    names = {i.name for i in instances}
    waits = {id(i): {a.text for a in i.after if a.text in names and a.text != i.name} for i in instances}
    started: set[str] = set()
    order: list[m.Instance] = []
    left = list(instances)
    while left:
        ready = next((i for i in left if waits[id(i)] <= started), left[0])
        left.remove(ready)
        order.append(ready)
        started.add(ready.name)
    return order


def cycle(iface: m.Interface) -> list[m.Instance]:
    """Instances whose ``after`` annotations lead back to themselves ([] when none do), in the cycle's order."""
    table = by_name(iface)
    state: dict[str, int] = {}  # 1 on the path, 2 done
    for first in iface.instances:
        if state.get(first.name):
            continue
        path: list[m.Instance] = [first]
        state[first.name] = 1
        todo: list[Iterator[m.Instance]] = [iter(_afters(first, table))]
        while todo:
            nxt = next(todo[-1], None)
            if nxt is None:
                state[path.pop().name] = 2
                todo.pop()
                continue
            if state.get(nxt.name) == 1:
                return path[path.index(nxt):]
            if not state.get(nxt.name):
                state[nxt.name] = 1
                path.append(nxt)
                todo.append(iter(_afters(nxt, table)))
    return []


def _afters(inst: m.Instance, table: dict[str, m.Instance]) -> list[m.Instance]:
    """The instances ``inst`` starts after (itself left out: ``after`` naming itself is reported alone)."""
    return [table[a.text] for a in inst.after if a.text in table and a.text != inst.name]


@rule()
def system_file(iface: m.Interface) -> Iterator[Diagnostic]:
    """A system file's declarations, instances and their annotations."""
    src = iface.source
    decls = iface.system_decls
    for extra in decls[1:]:
        yield make("duplicate-system", "the file already declares its system", src, extra.span,
                   related=[Related(src, decls[0].span, "system declared here")])
    if not decls:
        for inst in iface.instances:
            yield make("instance-outside-system", f"instance '{inst.name}' in a file that declares no system: "
                       "start the file with `system NAME`", src, inst.span)
        return
    extra_items = [*iface.component_decls, *iface.wirings, *iface.definitions]
    for item in sorted(extra_items, key=lambda x: x.span.start)[:1]:
        yield make("system-content", "a system file holds includes and instances only: put components, "
                   "definitions and wiring in the component files it includes", src, item.span,
                   related=[Related(src, decls[0].span, "system declared here")])
    known = components(iface)
    names: dict[str, m.Instance] = {}
    nodes: dict[str, m.Instance] = {}
    table = by_name(iface)
    for inst in iface.instances:
        if inst.name in names:
            yield make("duplicate-instance", f"instance '{inst.name}' is declared twice", src, inst.name_span,
                       related=[Related(src, names[inst.name].name_span, "first declared here")])
        else:
            names[inst.name] = inst
        if inst.component not in known:
            close = difflib.get_close_matches(inst.component, list(known), n=1)
            hint = (f"; did you mean '{close[0]}'?" if close else
                    f"; the included files declare: {', '.join(sorted(known))}" if known else
                    "; include the component's file first (include \"room_sensor.iface\")")
            yield make("unknown-component", f"no included file declares component '{inst.component}'{hint}",
                       src, inst.component_span, suggestions=close)
        yield from _annotations(iface, inst, table)
        node = inst.node
        if is_node_name(node) and inst.name in names and names[inst.name] is inst:
            if node in nodes:
                where = annotation_span(inst, "node")
                yield make("duplicate-node-name", f"instances '{nodes[node].name}' and '{inst.name}' would both "
                           f"run as node '/{node}': give one a `node` of its own", src, where,
                           related=[Related(src, annotation_span(nodes[node], "node"), "the other node")])
            else:
                nodes[node] = inst
    yield from _containers(iface, nodes)
    loop = cycle(iface)
    if loop:
        chain = " → ".join(i.name for i in [*loop, loop[0]])
        for inst in loop:
            a = next(a for a in inst.after if a.text != inst.name and a.text in table and table[a.text] in loop)
            yield make("instance-cycle", f"instances start after each other: {chain}", src,
                       a.value.span if a.value is not None else a.span)


def _containers(iface: m.Interface, nodes: dict[str, m.Instance]) -> Iterator[Diagnostic]:
    """A container holds rclcpp components only, and its node name is no instance's (nor the manager's)."""
    src = iface.source
    for inst in iface.instances:
        name = inst.value("container")
        if name is None:
            if inst.value("standby") == "true" and inst.value("restart") == "never":
                yield make("invalid-instance-annotation", "standby = \"true\" keeps a spare process for a restart, "
                           "and restart = \"never\" never restarts the instance: the spare would only take memory",
                           src, annotation_span(inst, "standby"), severity=Severity.WARNING)
            for key in CONTAINER_ONLY:
                if inst.value(key) is not None:
                    yield make("invalid-instance-annotation", f"'{key}' is for an instance in a container: add "
                               f"container = \"…\" or leave it out", src, annotation_span(inst, key),
                               severity=Severity.WARNING)
            continue
        if not is_node_name(name):
            continue  # invalid-instance-annotation says so
        if inst.value("runtime") == "rclpy":
            yield make("container-needs-rclcpp", f"instance '{inst.name}' runs its rclpy package (runtime = "
                       f"\"rclpy\"), but container '{name}' loads rclcpp components: generate the component with "
                       "--target rclcpp and leave runtime out (or say \"rclcpp\"), or run it in a process of its own",
                       src, annotation_span(inst, "container"),
                       related=[Related(src, annotation_span(inst, "runtime"), "the runtime")])
        for key in NOT_IN_CONTAINER:
            if inst.value(key) is not None:
                yield make("invalid-instance-annotation", f"'{key}' is not used for an instance in a container: "
                           "the container loads its component library, no executable runs", src,
                           annotation_span(inst, key), severity=Severity.WARNING)
        other = nodes.get(name)
        if other is not None:
            yield make("container-name-clash", f"container '{name}' would run as node '/{name}', the node of "
                       f"instance '{other.name}': give the container another name", src,
                       annotation_span(inst, "container"),
                       related=[Related(src, annotation_span(other, "node"), f"instance '{other.name}'s node")])
        elif name == MANAGER_NODE:
            yield make("container-name-clash", f"container '{name}' would run as node '/{name}', the component "
                       "manager's node: give the container another name", src, annotation_span(inst, "container"))


def annotation_span(inst: m.Instance, key: str) -> Span:
    """Where the instance sets ``key``, else its name."""
    a = m.annotation(inst.annotations, key)
    if a is not None and a.value is not None:
        return a.value.span
    return inst.name_span


def _annotations(iface: m.Interface, inst: m.Instance, table: dict[str, m.Instance]) -> Iterator[Diagnostic]:
    src = iface.source
    seen: set[str] = set()
    for a in inst.annotations:
        where = a.value.span if a.value is not None else a.span
        if a.key not in ANNOTATIONS:
            close = difflib.get_close_matches(a.key, list(ANNOTATIONS), n=1)
            hint = f"; did you mean '{close[0]}'?" if close else f"; known: {', '.join(ANNOTATIONS)}"
            yield make("unknown-instance-annotation", f"an instance takes no annotation '{a.key}'{hint}",
                       src, a.span, suggestions=close)
            continue
        if a.key != "after" and a.key in seen:
            yield make("invalid-instance-annotation", f"'{a.key}' is given twice: the last one counts", src,
                       a.span, severity=Severity.WARNING)
        seen.add(a.key)
        if a.value is None or a.value.kind != "string":
            yield make("invalid-instance-annotation", f"'{a.key}' takes a string: {a.key} = \"…\"", src, where)
            continue
        text = a.text
        problem = _value_problem(iface, inst, a.key, text, table)
        if problem is not None:
            code, message = problem
            yield make(code, message, src, where)


def _value_problem(iface: m.Interface, inst: m.Instance, key: str, text: str,
                   table: dict[str, m.Instance]) -> tuple[str, str] | None:
    """(code, message) when ``key = text`` is not a value an instance can take."""
    bad = "invalid-instance-annotation"
    if key == "restart" and text not in RESTART:
        return bad, f"restart must be one of {', '.join(repr(r) for r in RESTART)}, not '{text}'"
    if key == "snapshot" and period(text) is None:
        return bad, f"snapshot must be a period like \"1s\" or \"500ms\", not '{text}'"
    if key == "node" and not is_node_name(text):
        return bad, f"'{text}' is no ROS 2 node name: letters, digits and underscores, not a digit first"
    if key in ("package", "executable") and not is_node_name(text):
        return bad, f"'{text}' is no ROS 2 {key} name: letters, digits and underscores, not a digit first"
    if key == "container" and not is_node_name(text):
        return bad, (f"'{text}' is no container name: a container runs as a ROS 2 node, its name letters, digits "
                     "and underscores, not a digit first")
    if key == "runtime" and text not in RUNTIMES:
        return bad, f"runtime must be one of {', '.join(repr(r) for r in RUNTIMES)}, not '{text}'"
    if key in ("intra_process", "standby") and text not in BOOLEANS:
        return bad, f"{key} must be \"true\" or \"false\", not '{text}'"
    if key == "plugin" and not _PLUGIN.match(text):
        return bad, f"'{text}' is no C++ class name with its namespace, like \"counter::Counter\""
    if key == "after":
        if text == inst.name:
            return "instance-cycle", f"instance '{inst.name}' cannot start after itself"
        if text not in table:
            close = difflib.get_close_matches(text, list(table), n=1)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            return "unknown-instance", f"no instance '{text}' in this system{hint}"
    if key == "parameters":
        if not text.endswith((".yaml", ".yml")):
            return bad, f"parameters names a YAML file (.yaml or .yml), not '{text}'"
        path = os.path.join(os.path.dirname(iface.source.path), text)
        if not os.path.isfile(path):
            return bad, f"cannot find the parameter file '{text}' (read relative to the system file)"
    return None
