"""The system graph of a system file: one node per instance, and its conflicts located on the instances.

``check``, the language server and ``graph`` read a system file (docs/language.md, Systems) through
this module: the graph's checks that concern a running system — two types on one topic or service, QoS
that cannot match, a subscribed topic nobody publishes — are reported on the instances they concern,
with the component file's statement as related information.
"""

from __future__ import annotations

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, Severity
from ..semantics.compile import Compilation
from .graph import Graph, build

#: The graph checks a system file reports (the others — a topic nobody subscribes, a service nobody
#: provides or provided twice — are the graph's own information).
SYSTEM_CHECKS = ("graph-topic-type-conflict", "graph-service-type-conflict", "graph-qos-mismatch",
                 "graph-unpublished-topic")


def is_system(comp: Compilation) -> bool:
    """True when the file declares a system."""
    return comp.interface.system is not None


def instance_compilations(comp: Compilation) -> list[tuple[m.Instance, Compilation]]:
    """Each instance with the compilation of its component (instances of an unknown component are left out)."""
    by_component: dict[str, Compilation] = {}
    for inc in comp.includes.values():
        by_component.setdefault(inc.interface.name, inc)
    seen: set[str] = set()
    out: list[tuple[m.Instance, Compilation]] = []
    for inst in comp.interface.instances:
        found = by_component.get(inst.component)
        if found is not None and inst.name not in seen:
            seen.add(inst.name)
            out.append((inst, found))
    return out


def system_graph(comp: Compilation) -> Graph:
    """The graph of the system's instances whose component files have no errors."""
    pairs = [(inst.name, c) for inst, c in instance_compilations(comp)
             if not any(d.severity == Severity.ERROR for d in c.all_diagnostics())]
    return build([], pairs)


def system_findings(comp: Compilation) -> list[Diagnostic]:
    """The system graph's conflicts, each on the instance it concerns (nothing for a file that is no system)."""
    if not is_system(comp):
        return []
    instances = {inst.name: inst for inst, _ in instance_compilations(comp)}
    g = system_graph(comp)
    out: list[Diagnostic] = []
    seen: set[tuple[str, str, str]] = set()
    for d in g.checks:
        inst = instances.get(d.data.get("instance", ""))
        if d.code not in SYSTEM_CHECKS or inst is None or (inst.name, d.code, d.message) in seen:
            continue
        seen.add((inst.name, d.code, d.message))
        out.append(Diagnostic(d.code, d.message, comp.source, inst.name_span, d.severity,
                              [Related(d.source, d.span, f"{inst.name} is a {inst.component}: stated here")]))
    out.sort(key=lambda d: (d.span.start, d.code, d.message))
    return out

