"""What a replacement touches: the links of the system that change and the components behind them."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any, Callable

from ..model.diagnostics import Severity
from ..semantics.compile import Compilation
from . import compare
from .findings import Report
from .side import Side
from .system import Component, System, ports

Display = Callable[[str], str]
IMPACT_ID = "iface-impact/1"


@dataclass
class LinkImpact:
    """One link between the replaced component and a peer: what happens to it."""

    status: str  # broken, removed, changed, added, unchanged
    kind: str
    name: str
    role: str
    peer: str
    rules: list[str] = field(default_factory=list)


@dataclass
class Impact:
    """The links of the replaced component and the components they reach."""

    report: Report
    component: str
    links: list[LinkImpact]

    @property
    def affected(self) -> dict[str, str]:
        """Peer -> the worst status of its links (unchanged links excluded)."""
        rank = {"broken": 0, "removed": 1, "changed": 2, "added": 3}
        out: dict[str, str] = {}
        for lk in self.links:
            if lk.status == "unchanged":
                continue
            if lk.peer not in out or rank[lk.status] < rank[out[lk.peer]]:
                out[lk.peer] = lk.status
        return dict(sorted(out.items()))

    @property
    def breaks(self) -> bool:
        """True when a link breaks or a breaking change is usage-independent."""
        return self.report.verdict == "incompatible"


def impact(system: list[Compilation], old: Compilation, new: Compilation) -> Impact:
    """The impact of replacing OLD by NEW in ``system``."""
    report = compare(old, new, system)
    sys_ = System.of(system, exclude=(old, new))
    old_ports = {(p.key, p.role): p for p in ports(Component(old, Side(old)))}
    new_ports = {(p.key, p.role): p for p in ports(Component(new, Side(new)))}
    links: list[LinkImpact] = []
    for key, role in sorted(set(old_ports) | set(new_ports)):
        kind, name = key.split(":", 1)
        touching = [f for f in report.findings if key in f.usage]
        for peer in sys_.peers(key, role):
            p_name = peer.component.name
            if (key, role) not in new_ports:
                status = "removed"
            elif (key, role) not in old_ports:
                status = "added"
            else:
                status = "unchanged"
            rules = sorted({f.rule for f in touching if p_name in f.components})
            if rules:
                status = "broken"
            elif status == "unchanged" and touching:
                status = "changed"
                rules = sorted({f.rule for f in touching})
            links.append(LinkImpact(status, kind, name, role, p_name, rules))
    return Impact(report, new.interface.name, links)


def _arrow(lk: LinkImpact, me: str) -> str:
    return f"{me} -> {lk.peer}" if lk.role in ("publishes", "calls") else f"{lk.peer} -> {me}"


def render_text(imp: Impact, display: Display) -> str:
    """The impact as lines of text."""
    r = imp.report
    lines = [f"replacing {r.old.interface.name} ({display(r.old.path)}) by {r.new.interface.name} "
             f"({display(r.new.path)}): {r.verdict}"]
    lines.append("links:" if imp.links else "links: none (no component of the system talks to it)")
    for lk in imp.links:
        why = f": {', '.join(lk.rules)}" if lk.rules else ""
        lines.append(f"  {lk.status:<9} {lk.kind} {lk.name}  {_arrow(lk, imp.component)}{why}")
    affected = imp.affected
    lines.append("affected components: " + (", ".join(f"{c} ({s})" for c, s in affected.items()) or "none"))
    other = [f for f in r.findings if f.severity == Severity.ERROR and not f.usage_dependent]
    for f in other:
        lines.append(f"  also breaking, whoever uses it: {f.rule} {f.subject}")
    return "\n".join(lines) + "\n"


def impact_json(imp: Impact, display: Display) -> dict[str, Any]:
    """The impact as JSON data."""
    r = imp.report
    return {"schema": IMPACT_ID, "old": display(r.old.path), "new": display(r.new.path), "verdict": r.verdict,
            "links": [{"status": lk.status, "kind": lk.kind, "name": lk.name, "role": lk.role, "peer": lk.peer,
                       "rules": lk.rules} for lk in imp.links],
            "affected": [{"component": c, "status": s} for c, s in imp.affected.items()]}


def render_json(imp: Impact, display: Display) -> str:
    """The impact as indented JSON."""
    return json.dumps(impact_json(imp, display), indent=2, ensure_ascii=False) + "\n"


