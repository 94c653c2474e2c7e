"""A system of components: who publishes, subscribes, provides and calls what, and
whether a component's endpoint fits its peers'. Used by ``compat --system``,
``graph`` and ``impact``."""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field

from ..model import nodes as m
from ..model.diagnostics import Severity
from ..semantics.compile import Compilation
from .context import Context
from .defs import compare_definition
from .findings import Finding
from .qos import mismatches
from .side import RECEIVE, SEND, Side
from .view import ENDPOINT_SETS, endpoint_qos, endpoint_type

#: role -> the roles of its peers
PEER_ROLE = {"publishes": "subscribes", "subscribes": "publishes", "provides": "calls", "calls": "provides"}
_FLOW = {"publishes": SEND, "subscribes": RECEIVE, "provides": RECEIVE, "calls": SEND}


@dataclass(eq=False)
class Component:
    """One component of the system."""

    comp: Compilation
    side: Side
    #: The instance of a system file this is ('' for a component named on its own).
    instance: str = ""

    @property
    def name(self) -> str:
        """The instance's name, else the component's (its ``component`` declaration, else the file stem)."""
        return self.instance or self.side.name


@dataclass(frozen=True, eq=False)
class Port:
    """An endpoint of a component: (component, kind, endpoint); ``delta`` for its diagnostics services (Δ).

    A Δ service is served like any service, so a monitor's ``calls`` reaches it under the
    same key, but it belongs to Δ, not to the component's services S.
    """

    component: Component
    kind: str
    endpoint: m.Endpoint
    delta: bool = False

    @property
    def set(self) -> str:
        """The set the endpoint belongs to: M, N, S, A or Δ."""
        if self.delta:
            return "Δ"
        return {"subscribes": "M", "publishes": "N"}.get(self.role, "S" if self.kind == "service" else "A")

    @property
    def key(self) -> str:
        """``topic:/x``, ``service:/s`` or ``action:/a``."""
        return f"{self.kind}:{self.endpoint.name}"

    @property
    def role(self) -> str:
        """publishes, subscribes, provides or calls."""
        return self.endpoint.role


def ports(c: Component) -> Iterator[Port]:
    """Every endpoint of a component, in set order, Δ last."""
    for _, kind, attr in ENDPOINT_SETS:
        for ep in getattr(c.side.iface, attr):
            yield Port(c, kind, ep)
    for ep in c.side.iface.diagnostics_endpoints:
        yield Port(c, "service", ep, delta=True)


@dataclass
class System:
    """Components and their ports by usage key."""

    components: list[Component] = field(default_factory=list)
    by_key: dict[str, list[Port]] = field(default_factory=dict)

    @classmethod
    def of(cls, comps: list[Compilation], exclude: tuple[Compilation, ...] = ()) -> System:
        """The system of ``comps`` minus the files of ``exclude`` (the component being replaced)."""
        skip = {os.path.abspath(c.path) for c in exclude}
        names = {c.interface.name for c in exclude}
        sys_ = cls()
        seen: set[str] = set()
        for comp in comps:
            path = os.path.abspath(comp.path)
            if path in skip or path in seen or comp.interface.name in names:
                continue
            seen.add(path)
            c = Component(comp, Side(comp))
            sys_.components.append(c)
            for p in ports(c):
                sys_.by_key.setdefault(p.key, []).append(p)
        return sys_

    @classmethod
    def of_instances(cls, instances: list[tuple[str, Compilation]]) -> System:
        """The system of a system file: one component per (instance name, its component's compilation)."""
        sys_ = cls()
        sides: dict[str, Side] = {}
        for name, comp in instances:
            side = sides.setdefault(os.path.abspath(comp.path), Side(comp))
            c = Component(comp, side, name)
            sys_.components.append(c)
            for p in ports(c):
                sys_.by_key.setdefault(p.key, []).append(p)
        return sys_

    def peers(self, key: str, role: str) -> list[Port]:
        """The ports on ``key`` that talk to a port of ``role``."""
        want = PEER_ROLE[role]
        return [p for p in self.by_key.get(key, []) if p.role == want]

    def referencing(self, qualname: str) -> list[Component]:
        """Components that define or include a type of this (local) name."""
        local = qualname.rpartition(".")[2]
        return [c for c in self.components if any(q.rpartition(".")[2] == local for q in c.side.defs)]


def qos_problems(a: Port, b: Port) -> list[str]:
    """QoS mismatches between two topic ports of which one publishes and one subscribes."""
    if a.kind != "topic":
        return []
    pub, sub = (a, b) if a.role == "publishes" else (b, a)
    return mismatches(endpoint_qos(pub.endpoint), endpoint_qos(sub.endpoint))


def fit(peer: Port, own: Port) -> list[Finding]:
    """The errors that stop ``own`` from working with ``peer``: ``peer`` plays OLD, ``own`` NEW."""
    ctx = Context(peer.component.side, own.component.side)
    po, pn = peer.endpoint, own.endpoint
    tp, tn = endpoint_type(ctx.old, po), endpoint_type(ctx.new, pn)
    oloc = ctx.old.loc(po.wiring.span if po.wiring else None)
    nloc = ctx.new.loc(pn.wiring.span if pn.wiring else None)
    usage = {own.key}
    if tp != tn:
        ctx.add("topic-type-changed" if own.kind == "topic" else f"{own.kind}-type-changed", f"{own.kind} {pn.name}",
                f"'{pn.name}' carries {tn} here and {tp} at {peer.component.name}", oloc, nloc, usage=usage)
        return ctx.findings
    problems = qos_problems(peer, own)
    if problems:
        ctx.add("qos-incompatible", f"{own.kind} {pn.name}", "; ".join(problems), oloc, nloc, usage=usage)
    if po.definition is not None and pn.definition is not None:
        for od, nd, dirs in _pairs(ctx, po.definition, pn.definition, _FLOW[own.role]):
            compare_definition(ctx, ctx.new.qualname(nd), od, ctx.old.where(od), nd, ctx.new.where(nd), dirs, usage)
    return [f for f in ctx.findings if f.severity == Severity.ERROR]


def _pairs(ctx: Context, od: m.Definition, nd: m.Definition, direction: str
           ) -> Iterator[tuple[m.Definition, m.Definition, set[str]]]:
    """Definitions reachable from an endpoint on both sides, matched by local name, with their direction."""
    seen: set[int] = set()
    stack: list[tuple[m.Definition, m.Definition, frozenset[str]]] = [(od, nd, frozenset({direction}))]
    by_local = {q.rpartition(".")[2]: d for q, (d, _) in ctx.old.defs.items()}
    while stack:
        a, b, ds = stack.pop()
        if id(b) in seen:
            continue
        seen.add(id(b))
        yield a, b, set(ds)
        for child, cds in ctx.new._children(b, ds):
            other = by_local.get(child.name)
            if other is not None:
                stack.append((other, child, cds))


def apply(findings: list[Finding], old_side: Side, new_side: Side, system: System) -> list[Finding]:
    """Fill ``components`` / ``satisfied_by`` of the findings; return extra findings (conflicts)."""
    new_ports = {(p.key, p.role): p for p in ports(Component(new_side.comp, new_side))}
    old_ports = {(p.key, p.role): p for p in ports(Component(old_side.comp, old_side))}
    fits: dict[tuple[str, str], dict[str, list[Finding]]] = {}

    def fits_of(key: str, role: str) -> dict[str, list[Finding]]:
        if (key, role) not in fits:
            own = new_ports.get((key, role))
            fits[(key, role)] = {p.component.name: (fit(p, own) if own is not None else [])
                                 for p in system.peers(key, role)}
        return fits[(key, role)]

    for f in findings:
        if f.severity != Severity.ERROR:
            continue
        hit: set[str] = set()
        for key in f.usage:
            kind = key.split(":", 1)[0]
            if kind == "type":
                hit |= {c.name for c in system.referencing(key.split(":", 1)[1])}
                continue
            if kind not in ("topic", "service", "action"):
                continue
            roles = {r for (k, r) in (*old_ports, *new_ports) if k == key}
            for role in sorted(roles):
                peers = fits_of(key, role)
                if f.requires:
                    f.satisfied_by.extend(sorted(n for n, errs in peers.items() if not errs))
                    continue
                own = new_ports.get((key, role))
                for name, errs in peers.items():
                    if own is None or _concerns(f, errs):
                        hit.add(name)
        f.components = sorted(hit)
        f.satisfied_by = sorted(set(f.satisfied_by))
        if f.requires and not f.satisfied_by:
            f.breaks = "no component of the system provides it with a fitting type"
    return _conflicts(old_side, new_side, new_ports, old_ports, system)


def _concerns(f: Finding, errs: list[Finding]) -> bool:
    """True when a peer's fit errors include this finding."""
    return any(e.rule == f.rule and e.subject == f.subject for e in errs)


def _conflicts(old_side: Side, new_side: Side, new_ports: dict[tuple[str, str], Port], old_ports: dict[tuple[str, str], Port],
               system: System) -> list[Finding]:
    """Elements NEW adds that clash with the system: a second server, or a topic of another type."""
    out: list[Finding] = []
    ctx = Context(old_side, new_side)
    for (key, role), p in sorted(new_ports.items(), key=lambda kv: kv[0]):
        if (key, role) in old_ports:
            continue
        others = system.by_key.get(key, [])
        mine = endpoint_type(new_side, p.endpoint)
        clash: list[str] = []
        involved: set[str] = set()
        for q in others:
            theirs = endpoint_type(q.component.side, q.endpoint)
            if role == "provides" and q.role == "provides":
                clash.append(f"{q.component.name} already provides it")
            elif theirs != mine:
                clash.append(f"{q.component.name} {q.role} it as {theirs}")
            else:
                continue
            involved.add(q.component.name)
        if clash:
            loc = ctx.new.loc(p.endpoint.wiring.span if p.endpoint.wiring else None)
            f = ctx.add("system-conflict", f"{p.kind} {p.endpoint.name}",
                        f"NEW {role} '{p.endpoint.name}', but " + "; ".join(clash), ctx.old.anchor(), loc,
                        breaks="two components disagree on one name")
            f.components = sorted(involved)
            out.append(f)
    return out

