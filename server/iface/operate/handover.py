"""Replace a running component by another on a live system: the paper's hand-over, with trust.

"Stop a component, save its state, load another component in its place and switch them"
(docs/runtime.md has the sequence as a diagram). ``decide`` is the offline half: ``compat`` must
find that NEW may replace OLD, and its verdict fixes the interface hash that NEW must have.
``HandOver`` is the live half, over the component protocol (``iface.nodes.protocol``) and the
standard lifecycle services, through the one client (``iface.live.link``). Its steps are public and
named, in order: ``check_compat``, ``check_trust``, ``check_nodes``, ``prepare``, ``switch``, then
``roll_back`` after a failure and ``record``; ``run`` carries out the live ones as ``iface-lsp
handover`` does, and the component manager calls them itself (it starts NEW between the trust
check and the nodes' check, and keeps a grace period after the switch):

1. both nodes answer ``~/control`` STATUS within the timeout; OLD is active, NEW is not;
2. NEW reports the approved interface hash; where a trust store is given, NEW's package carries a
   valid signature (``iface.operate.trust``);
3. NEW is configured if it is not yet; every service the switch needs is found, its client made and
   answered once (OLD's current state is restored into NEW as a rehearsal: a state NEW refuses is
   found before OLD pauses); NEW's publishers are matched by the subscriptions OLD's have (a NEW
   started a moment ago is not yet known to every subscriber);
4. the critical section, kept to a few round trips: OLD pauses after its current work transaction
   (right after a tick of a fast work timer) and answers with its state, which is restored into NEW; OLD is deactivated, then NEW activated (never both
   active), and OLD's gate opened again after it. NEW's work timers continue OLD's schedule (the
   state document carries when each last ran). When OLD and NEW are loaded into one component container
   (iface_runtime_cpp's ``iface_container``), ``switch_in`` has the container do step 4 in its process,
   between two of OLD's ticks, with no round trip in it (the manager's replacement inside a container).

Any refusal before step 4 leaves OLD untouched; a failure after OLD paused reactivates and resumes
it (``roll_back``), so OLD goes on as before; after a switch (NEW failed later: the manager's grace
period), ``roll_back`` also restores into OLD the state it had at the pause. The result is a JSON-able record of every step, the state before and
after, and how long the critical section took.
"""

from __future__ import annotations

import functools
import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from ..compat import Report, compare
from ..live.link import Link, LinkError
from ..nodes import protocol
from ..semantics.compile import Compilation
from .trust import TrustError, verify

#: Verdicts under which a hand-over may go on.
ACCEPTED = ("equivalent", "replaceable")
#: lifecycle_msgs/State ids and Transition ids.
UNCONFIGURED, INACTIVE, ACTIVE, FINALIZED = 1, 2, 3, 4
STATE_LABELS = {0: "unknown", 1: "unconfigured", 2: "inactive", 3: "active", 4: "finalized"}
CONFIGURE, ACTIVATE, DEACTIVATE = 1, 3, 4

_Step = TypeVar("_Step", bound=Callable[..., Any])


class Refused(Exception):
    """The hand-over stops here: the message says why."""


def decide(old: Compilation, new: Compilation, system: list[Compilation] | None) -> Report:
    """What ``compat`` says of NEW replacing OLD (``report.new_hash`` is the hash NEW must show)."""
    return compare(old, new, system)


def fully_qualified(name: str) -> str:
    """``/name`` for a node name given with or without its leading slash."""
    return name if name.startswith("/") else "/" + name


def _refusing(step: _Step) -> _Step:
    """A step whose calls that fail refuse the hand-over (LinkError → Refused, the same message)."""
    @functools.wraps(step)
    def wrapped(self: HandOver, *args: Any, **kwargs: Any) -> Any:
        try:
            return step(self, *args, **kwargs)
        except LinkError as e:
            raise Refused(str(e)) from e
    return wrapped  # type: ignore[return-value]


@dataclass
class Step:
    """One thing the hand-over did or found."""

    step: str
    ok: bool
    detail: str = ""


@dataclass
class HandOver:
    """A hand-over from the node ``old`` to the node ``new``, approved for ``approved_hash``.

    ``link``: the client to call the nodes with (the manager's); None: ``run`` opens one of its own.
    """

    old: str
    new: str
    approved_hash: str
    timeout: float = 10.0
    trust_store: Path | None = None
    new_package: Path | None = None
    link: Link | None = field(default=None, repr=False)
    steps: list[Step] = field(default_factory=list)
    state_before: dict[str, Any] | None = None
    state_after: dict[str, Any] | None = None
    #: Milliseconds from OLD's answer to the pause (OLD paused) to NEW's answer to its activation; None before.
    critical_ms: float | None = None
    #: Milliseconds the pause took: OLD's current work transaction (and a fast timer's next tick) ending.
    pause_ms: float | None = None
    #: What the hand-over did to OLD so far (``roll_back`` undoes it): paused it (at all; and not resumed
    #: yet), deactivated it; and whether NEW was activated in its place.
    touched_old: bool = False
    paused: bool = False
    deactivated: bool = False
    switched: bool = False
    _new_state: int = field(default=0, repr=False)

    def __post_init__(self) -> None:
        self.old, self.new = fully_qualified(self.old), fully_qualified(self.new)

    @property
    def calls(self) -> Link:
        """The client the steps call with."""
        if self.link is None:
            raise RuntimeError("HandOver: no link (run() opens one; the manager gives its own)")
        return self.link

    def note(self, step: str, detail: str = "", ok: bool = True) -> None:
        """Add a step to the record."""
        self.steps.append(Step(step, ok, detail))

    # ---- the steps, in order -------------------------------------------------------------------
    def check_compat(self, report: Report, new_name: str, old_name: str) -> bool:
        """Whether compat's verdict lets NEW (``new_name``) replace OLD (``old_name``); noted either way."""
        accepted = report.exit_code == 0
        self.note("compat", f"{report.verdict}: {new_name} {'may' if accepted else 'may not'} replace {old_name}",
                  ok=accepted)
        return accepted

    def check_trust(self) -> None:
        """With a trust store: NEW's package carries a valid signature of one of its keys (else Refused)."""
        if self.trust_store is None:
            return
        if self.new_package is None:
            raise Refused("a trust store is configured: name NEW's package folder (--new-package) to check its "
                          "signature")
        try:
            problems = verify(self.new_package, self.trust_store)
        except TrustError as e:
            raise Refused(str(e)) from e
        if problems:
            raise Refused("NEW is not trusted: " + "; ".join(problems[:5])
                          + (f" (and {len(problems) - 5} more)" if len(problems) > 5 else ""))
        self.note("trust", f"{self.new_package} is signed by a key of {self.trust_store}")

    def check_nodes(self) -> None:
        """Both nodes answer; OLD is active, NEW is not and has the approved interface hash (else Refused)."""
        old_status = self._status(self.old, "OLD")
        new_status = self._status(self.new, "NEW")
        if old_status.lifecycle_state != ACTIVE:
            raise Refused(f"OLD {self.old} is {STATE_LABELS.get(old_status.lifecycle_state, '?')}, not active")
        if new_status.lifecycle_state == ACTIVE:
            raise Refused(f"NEW {self.new} is active already")
        if new_status.interface_hash != self.approved_hash:
            raise Refused(f"NEW {self.new} has interface hash {new_status.interface_hash}, not the one compat "
                          f"approved ({self.approved_hash})")
        self._new_state = int(new_status.lifecycle_state)
        self.note("hash", f"NEW has the approved interface hash {self.approved_hash}")

    @_refusing
    def prepare(self) -> None:
        """Before OLD pauses: NEW configured, every service of the switch found, its client made and answered once.

        OLD's current state is restored into NEW (NEW is not active, and the restore of the critical
        section replaces it), so a state NEW refuses stops the hand-over while OLD still works. Then
        NEW's publishers are awaited (``_await_matches``).
        """
        if self._new_state == UNCONFIGURED:
            self._transition(self.new, CONFIGURE, "configure")
            self.note("configure NEW", f"{self.new} configured")
        for node in (self.old, self.new):
            self.calls.lifecycle_state(node, self.timeout)
        current = self._save(self.old)
        self._restore(self.new, current.state)
        for node in (self.old, self.new):
            self.calls.ready(f"{node}/change_state", self.timeout)
        self.note("prepare", "every service of the switch answered; NEW took OLD's current state in a rehearsal")
        self._await_matches()

    @_refusing
    def switch(self) -> None:
        """The critical section: OLD paused (its state with the answer), restored into NEW, OLD deactivated, NEW
        activated; then OLD resumed (inactive) and NEW's state read back for the record."""
        self.touched_old = True  # from here on OLD may be paused: a failure rolls back
        asked = time.perf_counter()
        pause = self._control(self.old, protocol.PAUSE)
        start = time.perf_counter()
        self.pause_ms = (start - asked) * 1000
        if not pause.success:
            raise Refused(f"OLD {self.old} did not pause: {pause.message}")
        self.paused = True
        state, saved_note = pause.state, "saved with the pause"
        if not state:  # a runtime before 1.1 answers PAUSE without the state
            saved = self._save(self.old)
            state, saved_note = saved.state, saved.message
        restored = self._restore(self.new, state)
        self._transition(self.old, DEACTIVATE, "deactivate")
        self.deactivated = True
        self._transition(self.new, ACTIVATE, "activate")
        self.switched = True
        self.critical_ms = (time.perf_counter() - start) * 1000
        self.state_before = json.loads(state)
        self.note("pause OLD", f"{self.old} paused after its current work transaction "
                  f"({pause.transactions} done) in {self.pause_ms:.1f} ms")
        self.note("save OLD", saved_note)
        self.note("restore NEW", f"restored {', '.join(restored.restored) or 'nothing'}"
                  + (f"; kept {', '.join(restored.kept)}" if restored.kept else ""))
        self.note("deactivate OLD", f"{self.old} inactive")
        self.note("activate NEW", f"{self.new} active; pause to activation {self.critical_ms:.1f} ms")
        try:  # NEW has taken over: what fails from here on is said, not rolled back
            self._control(self.old, protocol.RESUME)
            self.paused = False
        except LinkError as e:
            self.note("resume OLD", f"{self.old} (inactive) stays paused: {e}")
        try:
            after = self.calls.save(self.new, self.timeout, wait=self.timeout + 5)
            self.state_after = json.loads(after.state)
        except LinkError:
            self.state_after = None

    @_refusing
    def switch_in(self, container: Any, name: str) -> None:
        """The critical section run by the container both nodes are loaded into: its ``~/handover``
        (``in_container.ContainerCalls.hand_over``: pause OLD between two of its ticks, restore its state into NEW,
        activate NEW, deactivate OLD, in the process); then NEW's state read back for the record. Refused when
        the container did not switch (OLD as it was; when it did not answer at all, a rollback looks)."""
        self.touched_old = True  # no answer: OLD may be paused or switched
        try:
            done = container.hand_over(self.old, self.new, self.timeout)
        except LinkError as e:
            self.paused = True
            raise Refused(f"container {name}'s hand-over did not answer: {e}") from e
        if not done.success:
            self.touched_old = False  # the container leaves OLD active and resumed
            raise Refused(f"container {name} did not switch: {done.message}")
        self.paused = False
        self.deactivated = self.switched = True
        self.state_before = done.state
        self.pause_ms, self.critical_ms = done.pause_ms, done.critical_ms
        self.note("switch in container", f"{name} switched {self.old} to {self.new} in its process"
                  + (f" after a tick of '{done.after_tick}'" if done.after_tick else "")
                  + f": pause {done.pause_ms:.2f} ms, OLD paused to NEW active {done.critical_ms:.3f} ms; restored "
                  + (", ".join(done.restored) or "nothing") + (f"; kept {', '.join(done.kept)}" if done.kept else ""))
        try:
            after = self.calls.save(self.new, self.timeout, wait=self.timeout + 5)
            self.state_after = json.loads(after.state)
        except LinkError:
            self.state_after = None

    def roll_back(self) -> bool:
        """OLD as it was before the hand-over: after NEW took over (and failed), OLD's state at the pause
        restored into it; reactivated if deactivated, resumed if paused. Whether it all worked (noted)."""
        ok = True
        if self.switched and self.state_before is not None:
            document = json.dumps(self.state_before, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
            try:
                self._restore(self.old, document)
                self.note("restore OLD", f"{self.old} has its state of the pause again")
            except (LinkError, Refused) as e:
                ok = False
                self.note("restore OLD", f"{self.old} did not take its state back: {e}", ok=False)
        if self.deactivated:
            try:
                self._transition(self.old, ACTIVATE, "activate")
                self.deactivated = False
                self.note("reactivate OLD", f"{self.old} active again")
            except (LinkError, Refused) as e:
                ok = False
                self.note("reactivate OLD", f"{self.old} could not be activated again: {e}", ok=False)
        if self.paused or self._still_paused():
            try:
                answer = self._control(self.old, protocol.RESUME)
                self.paused = False
                self.note("resume OLD", f"{self.old} resumed: {answer.message}", ok=bool(answer.success))
                ok = ok and bool(answer.success)
            except LinkError as e:
                ok = False
                self.note("resume OLD", f"{self.old} could not be resumed: {e}", ok=False)
        return ok

    def run(self) -> bool:
        """The live steps as ``iface-lsp handover`` takes them: True when NEW took over, False when refused (OLD
        as it was; ``steps`` say why)."""
        own = self.link is None
        if own:
            self.link = Link.own(Link.unique("iface_handover"))
        try:
            self.check_nodes()
            self.check_trust()
            self.prepare()
            self.switch()
            return True
        except Refused as e:
            self.note("refused", str(e), ok=False)
            if self.touched_old:
                self.roll_back()
            return False
        finally:
            if own:
                self.calls.close()
                self.link = None

    def record(self, report: Report | None) -> dict[str, Any]:
        """What was done, as JSON data."""
        done = bool(self.steps) and all(s.ok for s in self.steps)
        out: dict[str, Any] = {
            "result": "replaced" if done and self.state_after is not None else "refused",
            "old": self.old, "new": self.new, "approved_hash": self.approved_hash,
            "steps": [{"step": s.step, "ok": s.ok, "detail": s.detail} for s in self.steps],
            "state_before": (self.state_before or {}).get("values"),
            "state_after": (self.state_after or {}).get("values"),
            "critical_section_ms": None if self.critical_ms is None else round(self.critical_ms, 2),
            "pause_ms": None if self.pause_ms is None else round(self.pause_ms, 2),
        }
        if report is not None:
            out["verdict"] = report.verdict
        return out

    # ---- calls ---------------------------------------------------------------------------------
    def _control(self, node: str, command: int) -> Any:
        return self.calls.control(node, command, self.timeout, wait=self.timeout + 5)

    def _save(self, node: str) -> Any:
        try:
            return self.calls.save(node, self.timeout, wait=self.timeout + 5)
        except LinkError as e:
            raise Refused(f"OLD {e}" if node == self.old else str(e)) from e

    def _restore(self, node: str, document: str) -> Any:
        try:
            return self.calls.restore(node, document, self.timeout, wait=self.timeout + 5)
        except LinkError as e:
            raise Refused(f"NEW {e}" if node == self.new else str(e)) from e

    def _transition(self, node: str, transition: int, label: str) -> None:
        try:
            self.calls.transition(node, transition, self.timeout)
        except LinkError as e:
            if "refused the transition" in str(e):
                raise Refused(f"{node} refused to {label}") from e
            raise Refused(str(e)) from e

    def _status(self, node: str, role: str) -> Any:
        try:
            status = self._control(node, protocol.STATUS)
        except LinkError as e:
            raise Refused(f"{role} {node} does not answer: {e}") from e
        self.note(f"status {role}", f"{node}: {status.component} {status.version}, "
                  f"{STATE_LABELS.get(status.lifecycle_state, '?')}, {status.interface_hash}")
        return status

    def _still_paused(self) -> bool:
        """After the pause was asked but its answer lost: whether OLD says it is paused."""
        if not self.touched_old:
            return False
        try:
            return bool(self._control(self.old, protocol.STATUS).paused)
        except LinkError:
            return False

    def _matched(self, node: str) -> dict[str, int]:
        """Each publisher topic of ``node`` and the subscriptions it has matched."""
        status = self._control(node, protocol.STATUS)
        return dict(zip(status.publisher_topics, status.publisher_matched, strict=True))

    def _await_matches(self) -> None:
        """Before OLD pauses: NEW's publishers matched by as many subscriptions as OLD's on the same topic.

        A NEW started a moment ago may not be discovered yet by every subscriber; what it published
        before they match it would be lost, and the silence would last until discovery ends. Compat
        has approved NEW's QoS (a publisher that may match fewer peers is ``qos-incompatible``), so
        only discovery stands between: a lost announcement is sent again seconds later. Waited for at
        most the timeout; then the hand-over goes on and says so.
        """
        limit = self.timeout
        start = time.monotonic()
        while True:
            old, new = self._matched(self.old), self._matched(self.new)
            short = {t: (new[t], n) for t, n in old.items() if t in new and new[t] < n}
            waited = time.monotonic() - start
            if not short:
                shared = sorted(t for t in old if t in new)
                self.note("match", f"NEW's publishers on {', '.join(shared)} matched as OLD's are "
                          f"({waited * 1000:.0f} ms)" if shared else "no topic published by both")
                return
            if waited >= limit:
                self.note("match", "after {:g} s NEW's publishers still match fewer subscriptions than OLD's: {}; "
                          "going on".format(limit, ", ".join(f"{t} {a} of {b}" for t, (a, b) in sorted(short.items()))))
                return
            self.calls.pause(0.05)
