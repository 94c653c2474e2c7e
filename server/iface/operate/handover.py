"""Replace a running component by another on a live system: the paper's hand-over, with trust.

"Stop a component, save its state, load another component in its place and switch them"
(docs/runtime.md has the sequence as a diagram). ``decide`` is the offline half: ``compat`` must
find that NEW may replace OLD, and its verdict fixes the interface hash that NEW must have.
``HandOver.run`` is the live half, over the component protocol (``iface.nodes.protocol``) and
the standard lifecycle services, with rclpy:

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
   state document carries when each last ran).

Any refusal before step 4 leaves OLD untouched; a failure after OLD paused reactivates and resumes
it, so OLD goes on as before. The result is a JSON-able record of every step, the state before and
after, and how long the critical section took.
"""

from __future__ import annotations

import importlib
import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..compat import Report, compare
from ..semantics.compile import Compilation
from ..nodes import protocol
from .trust import TrustError, verify

#: Verdicts under which a hand-over may go on.
ACCEPTED = ("equivalent", "replaceable")
#: lifecycle_msgs/State ids and Transition ids.
UNCONFIGURED, INACTIVE, ACTIVE = 1, 2, 3
STATE_LABELS = {0: "unknown", 1: "unconfigured", 2: "inactive", 3: "active", 4: "finalized"}
CONFIGURE, ACTIVATE, DEACTIVATE = 1, 3, 4
#: The state each transition ends in.
GOAL = {CONFIGURE: INACTIVE, ACTIVATE: ACTIVE, DEACTIVATE: INACTIVE}
#: Seconds before an unanswered idempotent request is sent again.
RESEND = 2.0
#: At most this many seconds (and the timeout) for NEW's publishers to match the subscriptions OLD's have.
MATCH_WAIT = 5.0


class Refused(Exception):
    """The hand-over stops here: the message says why."""


def decide(old: Compilation, new: Compilation, system: list[Compilation] | None) -> Report:
    """What ``compat`` says of NEW replacing OLD (``report.new_hash`` is the hash NEW must show)."""
    return compare(old, new, system)


def fully_qualified(name: str) -> str:
    """``/name`` for a node name given with or without its leading slash."""
    return name if name.startswith("/") else "/" + name


@dataclass
class Step:
    """One thing the hand-over did or found."""

    step: str
    ok: bool
    detail: str = ""


@dataclass
class HandOver:
    """A hand-over from the node ``old`` to the node ``new``, approved for ``approved_hash``."""

    old: str
    new: str
    approved_hash: str
    timeout: float = 10.0
    trust_store: Path | None = None
    new_package: Path | None = None
    steps: list[Step] = field(default_factory=list)
    state_before: dict[str, Any] | None = None
    state_after: dict[str, Any] | None = None
    #: Milliseconds from OLD's answer to the pause (OLD paused) to NEW's answer to its activation; None before.
    critical_ms: float | None = None
    #: Milliseconds the pause took: OLD's current work transaction (and a fast timer's next tick) ending.
    pause_ms: float | None = None

    def __post_init__(self) -> None:
        self.old, self.new = fully_qualified(self.old), fully_qualified(self.new)

    # ---- talking to the nodes ---------------------------------------------------------------
    def _open(self) -> None:
        import rclpy
        from rclpy.node import Node

        self._rclpy = rclpy
        self._own_context = not rclpy.ok()
        if self._own_context:
            rclpy.init()
        self._node = Node(f"iface_handover_{int(time.monotonic() * 1000) % 100000}")
        self._clients: dict[str, Any] = {}
        self._types: dict[str, Any] = {}

    def _close(self) -> None:
        self._node.destroy_node()
        if self._own_context:
            self._rclpy.shutdown()

    def _service_type(self, service: str) -> Any:
        """The type of a service as the graph shows it, imported (once); waits at most the timeout."""
        if service in self._types:
            return self._types[service]
        deadline = time.monotonic() + self.timeout
        while True:
            for name, types in self._node.get_service_names_and_types():
                if name == service and types:
                    package, kind, type_name = types[0].split("/")
                    found = getattr(importlib.import_module(f"{package}.{kind}"), type_name)
                    self._types[service] = found
                    return found
            if time.monotonic() > deadline:
                raise Refused(f"{service} does not exist (no answer within {self.timeout:g} s)")
            self._rclpy.spin_once(self._node, timeout_sec=0.1)

    def _call(self, service: str, fill: dict[str, Any], timeout: float | None = None,
              idempotent: bool = True) -> Any:
        """Call ``service``: the first answer counts; an unanswered idempotent request is sent again
        every :data:`RESEND` seconds.

        A server just seen in the graph may not yet have matched this client's reply reader; DDS
        then drops the reply (rmw_fastrtps: "client will not receive response"). Sending again is
        safe for every request here but a lifecycle transition (see :meth:`_transition`).
        """
        srv = self._service_type(service)
        client = self._clients.get(service)
        if client is None:
            client = self._clients[service] = self._node.create_client(srv, service)
        limit = timeout if timeout is not None else self.timeout
        if not client.wait_for_service(timeout_sec=limit):
            raise Refused(f"{service} does not answer within {limit:g} s")
        request = srv.Request()
        for key, value in fill.items():
            setattr(request, key, value)
        deadline = time.monotonic() + limit
        futures: list[Any] = []
        send_at = time.monotonic()
        while True:
            now = time.monotonic()
            if now >= deadline:
                raise Refused(f"{service} does not answer within {limit:g} s")
            if not futures or (idempotent and now >= send_at):
                futures.append(client.call_async(request))
                send_at = now + RESEND
            self._rclpy.spin_once(self._node, timeout_sec=min(0.1, max(0.0, deadline - now)))
            answer = next((f.result() for f in futures if f.done() and f.result() is not None), None)
            if answer is not None:
                return answer

    def _control(self, node: str, command: int) -> Any:
        return self._call(f"{node}/control", {"command": command, "timeout_sec": self.timeout},
                          self.timeout + 5)

    def _lifecycle_state(self, node: str) -> int:
        return int(self._call(f"{node}/get_state", {}).current_state.id)

    def _transition(self, node: str, transition: int, label: str) -> None:
        """Ask ``node`` for a transition, sent once; without an answer, its state tells whether it happened."""
        try:
            answer = self._call(f"{node}/change_state", {"transition": _transition_msg(transition)},
                                idempotent=False)
        except Refused:
            if self._lifecycle_state(node) == GOAL[transition]:
                return
            raise
        if not answer.success:
            raise Refused(f"{node} refused to {label}")

    def _note(self, step: str, detail: str = "", ok: bool = True) -> None:
        self.steps.append(Step(step, ok, detail))

    # ---- the sequence --------------------------------------------------------------------------
    def run(self) -> bool:
        """Carry out the hand-over; True when NEW took over, False when it was refused (``steps`` say why)."""
        self._open()
        paused = deactivated = False
        try:
            old_status = self._status(self.old, "OLD")
            new_status = self._status(self.new, "NEW")
            if old_status.lifecycle_state != ACTIVE:
                raise Refused(f"OLD {self.old} is {STATE_LABELS.get(old_status.lifecycle_state, '?')}, not active")
            if new_status.lifecycle_state == ACTIVE:
                raise Refused(f"NEW {self.new} is active already")
            if new_status.interface_hash != self.approved_hash:
                raise Refused(f"NEW {self.new} has interface hash {new_status.interface_hash}, not the one compat "
                              f"approved ({self.approved_hash})")
            self._note("hash", f"NEW has the approved interface hash {self.approved_hash}")
            self._check_trust()
            if new_status.lifecycle_state == UNCONFIGURED:
                self._transition(self.new, CONFIGURE, "configure")
                self._note("configure NEW", f"{self.new} configured")
            self._prepare()
            asked = time.perf_counter()
            pause = self._control(self.old, protocol.PAUSE)
            start = time.perf_counter()
            self.pause_ms = (start - asked) * 1000
            if not pause.success:
                raise Refused(f"OLD {self.old} did not pause: {pause.message}")
            paused = True
            state, saved_note = pause.state, "saved with the pause"
            if not state:  # a runtime before 1.1 answers PAUSE without the state
                saved = self._call(f"{self.old}/save_state", {"timeout_sec": self.timeout}, self.timeout + 5)
                if not saved.success:
                    raise Refused(f"OLD {self.old} could not save its state: {saved.message}")
                state, saved_note = saved.state, saved.message
            restored = self._call(f"{self.new}/restore_state", {"state": state, "timeout_sec": self.timeout},
                                  self.timeout + 5)
            if not restored.success:
                raise Refused(f"NEW {self.new} refused the state: {restored.message}")
            self._transition(self.old, DEACTIVATE, "deactivate")
            deactivated = True
            self._transition(self.new, ACTIVATE, "activate")
            self.critical_ms = (time.perf_counter() - start) * 1000
            self._note("pause OLD", f"{self.old} paused after its current work transaction "
                       f"({pause.transactions} done) in {self.pause_ms:.1f} ms")
            self.state_before = json.loads(state)
            self._note("save OLD", saved_note)
            self._note("restore NEW", f"restored {', '.join(restored.restored) or 'nothing'}"
                       + (f"; kept {', '.join(restored.kept)}" if restored.kept else ""))
            self._note("deactivate OLD", f"{self.old} inactive")
            self._note("activate NEW", f"{self.new} active; pause to activation {self.critical_ms:.1f} ms")
            self._control(self.old, protocol.RESUME)
            paused = False
            after = self._call(f"{self.new}/save_state", {"timeout_sec": self.timeout}, self.timeout + 5)
            self.state_after = json.loads(after.state) if after.success else None
            return True
        except Refused as e:
            self._note("refused", str(e), ok=False)
            if paused:
                if deactivated:
                    self._reactivate_old()
                self._resume_old()
            return False
        finally:
            self._close()

    def _prepare(self) -> None:
        """Before OLD pauses: every service of the switch found, its client made and answered once.

        OLD's current state is restored into NEW (NEW is not active, and the restore of the critical
        section replaces it), so a state NEW refuses stops the hand-over while OLD still works.
        """
        for node in (self.old, self.new):
            self._lifecycle_state(node)
            self._service_type(f"{node}/change_state")
        current = self._call(f"{self.old}/save_state", {"timeout_sec": self.timeout}, self.timeout + 5)
        if not current.success:
            raise Refused(f"OLD {self.old} could not save its state: {current.message}")
        rehearsal = self._call(f"{self.new}/restore_state", {"state": current.state, "timeout_sec": self.timeout},
                               self.timeout + 5)
        if not rehearsal.success:
            raise Refused(f"NEW {self.new} refused the state: {rehearsal.message}")
        for node in (self.old, self.new):
            client = self._clients.get(f"{node}/change_state")
            if client is None:
                srv = self._service_type(f"{node}/change_state")
                client = self._clients[f"{node}/change_state"] = self._node.create_client(srv, f"{node}/change_state")
            if not client.wait_for_service(timeout_sec=self.timeout):
                raise Refused(f"{node}/change_state does not answer within {self.timeout:g} s")
        self._note("prepare", "every service of the switch answered; NEW took OLD's current state in a rehearsal")
        self._await_matches()

    def _matched(self, node: str) -> dict[str, int]:
        """Each publisher topic of ``node`` and the subscriptions it has matched."""
        status = self._control(node, protocol.STATUS)
        return dict(zip(status.publisher_topics, status.publisher_matched, strict=True))

    def _await_matches(self) -> None:
        """Before OLD pauses: NEW's publishers matched by as many subscriptions as OLD's on the same topic.

        A NEW started a moment ago may not be discovered yet by every subscriber; what it published
        before they match it would be lost, and the silence would last until discovery ends. Waited
        for at most ``MATCH_WAIT`` s (and the timeout); then the hand-over goes on and says so.
        """
        limit = min(self.timeout, MATCH_WAIT)
        start = time.monotonic()
        while True:
            old, new = self._matched(self.old), self._matched(self.new)
            short = {t: (new[t], n) for t, n in old.items() if t in new and new[t] < n}
            waited = time.monotonic() - start
            if not short:
                shared = sorted(t for t in old if t in new)
                self._note("match", f"NEW's publishers on {', '.join(shared)} matched as OLD's are "
                           f"({waited * 1000:.0f} ms)" if shared else "no topic published by both")
                return
            if waited >= limit:
                self._note("match", "after {:g} s NEW's publishers still match fewer subscriptions than OLD's: {}; "
                           "going on".format(limit, ", ".join(f"{t} {a} of {b}" for t, (a, b) in sorted(short.items()))))
                return
            time.sleep(0.05)

    def _reactivate_old(self) -> None:
        try:
            self._transition(self.old, ACTIVATE, "activate")
            self._note("reactivate OLD", f"{self.old} active again")
        except Refused as e:
            self._note("reactivate OLD", f"{self.old} could not be activated again: {e}", ok=False)

    def _status(self, node: str, role: str) -> Any:
        try:
            status = self._control(node, protocol.STATUS)
        except Refused as e:
            raise Refused(f"{role} {node} does not answer: {e}") from e
        self._note(f"status {role}", f"{node}: {status.component} {status.version}, "
                   f"{STATE_LABELS.get(status.lifecycle_state, '?')}, {status.interface_hash}")
        return status

    def _check_trust(self) -> None:
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
        self._note("trust", f"{self.new_package} is signed by a key of {self.trust_store}")

    def _resume_old(self) -> None:
        try:
            answer = self._control(self.old, protocol.RESUME)
            self._note("resume OLD", f"{self.old} resumed: {answer.message}", ok=bool(answer.success))
        except Refused as e:
            self._note("resume OLD", f"{self.old} could not be resumed: {e}", ok=False)

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


def _transition_msg(transition: int) -> Any:
    from lifecycle_msgs.msg import Transition

    return Transition(id=transition)
