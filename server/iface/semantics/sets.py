"""Derive the seven sets I = M ∪ N ∪ S ∪ A ∪ P ∪ Σ ∪ Δ from a resolved interface."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ..model import nodes as m
from ..model.diagnostics import Diagnostic, Related, make
from ..model.walk import resolve_typedefs


def fill_sets(iface: m.Interface) -> None:
    """Fill the seven sets of ``iface`` (its findings are ``SetFindings``')."""
    iface.subscribed, iface.published = [], []
    iface.services, iface.actions = [], []
    iface.parameters, iface.state, iface.diagnostics = [], [], []
    iface.diagnostics_endpoints = []
    wired_calls = False
    called: set[int] = set()
    for w in iface.wirings:
        target = wiring_target(w)
        if w.direction in ("publishes", "subscribes"):
            if target is None or isinstance(target, m.Struct):
                ep = m.Endpoint(w.direction, w.topic, target, w)
                (iface.published if w.direction == "publishes" else iface.subscribed).append(ep)
            continue
        wired_calls = True
        if isinstance(target, m.Service) and target.is_diagnostics:
            if w.direction == "provides":  # the component's own Δ, under the wired name: not in S
                _add_delta(iface, m.Endpoint("provides", w.topic, target, w))
                continue
            called.add(id(target))  # another component's Δ, called: a service this one needs (S)
        if target is None and w.direction == "provides" and _marked(w, "diagnostics"):
            _add_delta(iface, m.Endpoint("provides", w.topic, None, w))  # an external diagnostics service
            continue
        if isinstance(target, m.Action) or (target is None and _marked(w, "action")):
            iface.actions.append(m.Endpoint(w.direction, w.topic, target, w))
        elif isinstance(target, m.Service) or target is None:
            iface.services.append(m.Endpoint(w.direction, w.topic, target, w))
    for d in iface.definitions:
        if isinstance(d, m.Struct):
            if d.kind == "configuration":
                iface.parameters.extend(d.fields)
            elif d.kind == "state":
                iface.state.extend(d.fields)
        elif isinstance(d, m.Service) and d.is_diagnostics:
            if id(d) not in called and all(e.definition is not d for e in iface.diagnostics_endpoints):
                _add_delta(iface, m.Endpoint("provides", d.name, d, None))
        elif not wired_calls and iface.component is None and isinstance(d, (m.Service, m.Action)):
            ep = m.Endpoint("provides", d.name, d, None)
            (iface.actions if isinstance(d, m.Action) else iface.services).append(ep)


def _marked(w: m.Wiring, key: str) -> bool:
    """True when a wiring of an external type says what it is: ``(action)``, ``(diagnostics)``."""
    return any(a.key == key for a in w.annotations)


def interface_package(iface: m.Interface) -> bool:
    """A declared component that wires nothing: a package of types (as ``import --from ros2`` writes one).

    Its messages, services and actions are definitions only; nothing is read into M, N, S or A.
    """
    return iface.component is not None and not iface.wirings


def _add_delta(iface: m.Interface, ep: m.Endpoint) -> None:
    """Put a diagnostics service into Δ (once as a set member, once per name it is served under)."""
    iface.diagnostics_endpoints.append(ep)
    if ep.definition is None:  # of an external type: served, but no definition to hold in Δ
        return
    assert isinstance(ep.definition, m.Service)
    if all(d is not ep.definition for d in iface.diagnostics):
        iface.diagnostics.append(ep.definition)


def _unwired_delta(iface: m.Interface, d: m.Service) -> Diagnostic:
    """What an unwired diagnostics service is: Δ, served by the component under its own name."""
    why = "it is named 'diagnostics'" if d.name == "diagnostics" else "it is annotated (diagnostics)"
    return make("diagnostics-service",
                f"service '{d.name}' is the component's diagnostics and control service (the set Δ, kept apart "
                f"from its services S) because {why}: monitors call it to read the component's health and send "
                f"it commands. No `provides` names it, so it is served as '{d.name}' (add `provides {d.name} on "
                f"\"/name\"` to choose the name)", iface.source, d.name_span, name=d.name)


# ---------------------------------------------------------------------------
# the findings of the seven sets, kept per item


def wiring_target(w: m.Wiring) -> m.Definition | None:
    """What a wiring's type stands for, through typedefs."""
    target = w.type.target
    if isinstance(target, m.Typedef):
        real = resolve_typedefs(w.type)
        target = real.target if isinstance(real, m.NamedType) else target
    return target


def _wrong_kind(src: m.Source, w: m.Wiring, target: m.Definition | None) -> Diagnostic | None:
    """The ``wrong-kind`` finding of one wiring, if its type is the wrong kind of definition."""
    if w.direction in ("publishes", "subscribes"):
        if target is not None and not isinstance(target, m.Struct):
            done = "published" if w.direction == "publishes" else "subscribed to"
            return make("wrong-kind", f"'{w.type.name}' is a {target.kind}, not a message: "
                        f"only messages are {done} on topics", src, w.type.span)
        return None
    if target is None or isinstance(target, (m.Service, m.Action)):
        return None
    done = "provided" if w.direction == "provides" else "called"
    return make("wrong-kind", f"'{w.type.name}' is a {getattr(target, 'kind', 'definition')}, "
                f"not a service or action: only those are {done}", src, w.type.span)


def _count(counts: dict[m.Item, int], key: m.Item, by: int, touched: set[m.Item]) -> None:
    n = counts.get(key, 0) + by
    if n:
        counts[key] = n
    else:
        counts.pop(key, None)
    touched.add(key)


class SetFindings:
    """The findings of the seven sets (wiring of the wrong kind, wiring stated twice, a topic used with two
    types, a message not wired, Δ not wired, services provided implicitly), kept from small per-item facts so that an edit updates it in time that
    follows the edit (the seven sets themselves are made when first read: ``Interface.published`` …)."""

    def __init__(self) -> None:
        #: wiring -> what it stands for (model nodes hash by identity)
        self.facts: dict[m.Wiring, m.Definition | None] = {}
        #: wiring -> its wrong-kind finding
        self.wrong: dict[m.Wiring, Diagnostic] = {}
        #: The wirings on one topic name (its statements and its channels are among them), in the order of
        #: the text once the topic's findings are made.
        self.by_topic: dict[str, list[m.Wiring]] = {}
        #: topic name -> ``duplicate-wiring`` findings of its statements, ``topic-type-conflict`` of its channels
        self.statement_found: dict[str, list[Diagnostic]] = {}
        self.channel_found: dict[str, list[Diagnostic]] = {}
        # keyed by the definitions themselves (model nodes hash by identity)
        self.wired: dict[m.Item, int] = {}  # message -> publishes/subscribes naming it
        self.delta: dict[m.Item, int] = {}  # Δ service -> provides/calls naming it
        self.calls = 0  # provides and calls statements
        self.messages: dict[m.Struct, None] = {}  # a dict: smaller than a set of as many
        self.deltas: dict[m.Service, None] = {}
        self.implicit_kinds = 0  # services and actions, not Δ
        self.message_found: dict[m.Item, Diagnostic] = {}
        self.delta_found: dict[m.Item, Diagnostic] = {}
        self.implicit: Diagnostic | None = None
        self.flags: tuple[bool, bool] | None = None

    def update(self, iface: m.Interface, gone: Sequence[m.Item], new: Sequence[m.Item],
               again: Sequence[m.Wiring]) -> None:
        """Items ``gone`` and ``new`` (definitions and wirings), and wirings resolved ``again``."""
        src = iface.source
        touched: set[m.Item] = set()
        topics: set[str] = set()
        services_changed = False
        for x in [*gone, *again]:
            if isinstance(x, m.Wiring):
                target = self.facts.pop(x)
                self.wrong.pop(x, None)
                self._wiring(x, target, -1, touched)
                if x in gone:  # noqa: SIM102  (a wiring resolved again keeps its place)
                    _regroup(self.by_topic, x.topic, x, -1)
                topics.add(x.topic)
            else:
                services_changed |= self._definition(x, -1)
        for x in [*new, *again]:
            if isinstance(x, m.Wiring):
                target = wiring_target(x)
                self.facts[x] = target
                wrong = _wrong_kind(src, x, target)
                if wrong is not None:
                    self.wrong[x] = wrong
                self._wiring(x, target, 1, touched)
                if x not in again:
                    _regroup(self.by_topic, x.topic, x, 1)
                topics.add(x.topic)
            else:
                services_changed |= self._definition(x, 1)
                touched.add(x)
        for topic in [*self.statement_found, *self.channel_found]:  # a topic with findings: in order again
            if topic not in topics:
                on = self.by_topic[topic]
                if on != sorted(on, key=_start):
                    topics.add(topic)
        for topic in topics:
            self._topic(src, topic)
        robot_file = src.path.endswith(".iface")
        flags = (robot_file and not interface_package(iface), robot_file and not self.calls and iface.component is None)
        every = flags != self.flags
        self.flags = flags
        for d in (self.message_found.keys() | self.messages.keys()) if every else touched:
            if isinstance(d, m.Struct) and d in self.messages and flags[0] and not self.wired.get(d):
                self.message_found[d] = make("message-no-direction",
                                             f"message '{d.name}' is neither published nor subscribed: it is a type "
                                             f"definition (add `publishes {d.name} on \"/topic\"` to wire it)",
                                             src, d.name_span, name=d.name)
            else:
                self.message_found.pop(d, None)
        for s in (self.delta_found.keys() | self.deltas.keys()) if every else touched:
            if isinstance(s, m.Service) and s in self.deltas and not self.delta.get(s):
                self.delta_found[s] = _unwired_delta(iface, s)
            else:
                self.delta_found.pop(s, None)
        if every or services_changed:
            self.implicit = None
            if flags[1] and self.implicit_kinds:
                implicit = [d for d in iface.definitions if isinstance(d, m.Action) or
                            (isinstance(d, m.Service) and not d.is_diagnostics)]
                names = ", ".join(d.name for d in implicit)
                self.implicit = make("implicit-provides",
                                     f"nothing is wired with provides/calls, so the component provides {names} "
                                     "under their own names", src, implicit[0].name_span)

    def findings(self) -> list[Diagnostic]:
        """Every finding, grouped by kind."""
        out = list(self.wrong.values())
        for found in self.statement_found.values():
            out.extend(found)
        for found in self.channel_found.values():
            out.extend(found)
        out.extend(self.message_found.values())
        out.extend(self.delta_found.values())
        if self.implicit is not None:
            out.append(self.implicit)
        return out

    def rehome(self, move: Callable[[Diagnostic], Diagnostic]) -> None:
        """Attach every kept finding to the newest version of the file (``move``)."""
        self.wrong = {k: move(f) for k, f in self.wrong.items()}
        self.statement_found = {k: [move(f) for f in v] for k, v in self.statement_found.items()}
        self.channel_found = {k: [move(f) for f in v] for k, v in self.channel_found.items()}
        self.message_found = {k: move(f) for k, f in self.message_found.items()}
        self.delta_found = {k: move(f) for k, f in self.delta_found.items()}
        self.implicit = move(self.implicit) if self.implicit is not None else None

    def _wiring(self, w: m.Wiring, target: m.Definition | None, by: int, touched: set[m.Item]) -> None:
        if w.direction in ("publishes", "subscribes"):
            if target is not None and isinstance(target, m.Struct):
                _count(self.wired, target, by, touched)
            return
        self.calls += by
        if isinstance(target, m.Service) and target.is_diagnostics:
            _count(self.delta, target, by, touched)

    def _definition(self, d: m.Item, by: int) -> bool:
        """Count a definition in or out; True when it is a service or action that is not Δ."""
        if isinstance(d, m.Struct) and d.kind == "message":
            if by > 0:
                self.messages[d] = None
            else:
                self.messages.pop(d, None)
                self.message_found.pop(d, None)
        elif isinstance(d, m.Service) and d.is_diagnostics:
            if by > 0:
                self.deltas[d] = None
            else:
                self.deltas.pop(d, None)
                self.delta_found.pop(d, None)
        elif isinstance(d, (m.Service, m.Action)):
            self.implicit_kinds += by
            return True
        return False

    def _topic(self, src: m.Source, topic: str) -> None:
        """The findings of the wirings on ``topic``: statements made twice, channels used with two types."""
        on = self.by_topic.get(topic, [])
        if len(on) < 2:  # nothing to compare
            self.statement_found.pop(topic, None)
            self.channel_found.pop(topic, None)
            return
        on.sort(key=_start)
        stated: dict[tuple[str, str], m.Wiring] = {}  # (direction, type name) -> the first statement
        firsts: dict[str, m.Wiring] = {}  # channel -> the first wiring on it (not one stated twice)
        twice: list[Diagnostic] = []
        found: list[Diagnostic] = []
        for w in on:
            first = stated.setdefault((w.direction, w.type.name), w)
            if first is not w:
                twice.append(make("duplicate-wiring", f"'{w.direction} {w.type.name} on \"{w.topic}\"' is stated twice",
                                  src, w.span, related=[Related(src, first.span, "first stated here")]))
                continue  # stated twice: reported as such
            ch = _channel(w)
            first = firsts.setdefault(ch, w)
            if first is w:
                continue
            a, b = first.type, w.type
            if not ((a.target is not None and a.target is b.target) or a.name == b.name):
                found.append(make("topic-type-conflict",
                                  f"{ch} '{w.topic}' is used with '{b.name}' here and with '{a.name}' elsewhere",
                                  src, w.topic_span,
                                  related=[Related(src, first.topic_span, f"'{w.topic}' used with '{a.name}'")]))
        for kept, new in ((self.statement_found, twice), (self.channel_found, found)):
            if new:
                kept[topic] = new
            else:
                kept.pop(topic, None)


def _regroup(groups: dict[str, list[m.Wiring]], k: str, w: m.Wiring, by: int) -> None:
    """Put ``w`` in the group ``k`` (``by`` > 0) or take it out."""
    if by > 0:
        groups.setdefault(k, []).append(w)
        return
    group = groups[k]
    group.remove(w)
    if not group:
        del groups[k]


def _channel(w: m.Wiring) -> str:
    """Where a wiring's name lives: among topics, or among services (and actions)."""
    return "topic" if w.direction in ("publishes", "subscribes") else "service"


def _start(w: m.Wiring) -> int:
    return w.span.start
