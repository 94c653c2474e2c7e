"""The hand-over's service calls survive a lost reply (no ROS needed: a fake client drops replies).

A server just seen in the graph may not yet have matched the caller's reply reader, and DDS then
drops the reply. Idempotent requests are sent again; a lifecycle transition is judged by the node's
state: done when ``get_state`` shows its goal, waited for while it runs, sent again only while the
node is where the transition starts (the request was lost). The calls are the one client's
(``iface.live.link``), which the hand-over, the manager and the ``system`` commands share.

Discovery, too, takes its time: before OLD pauses, the hand-over waits (up to its timeout, on a fake
clock here) until NEW's publishers are matched by as many subscriptions as OLD's.
"""

from __future__ import annotations

import re
from types import SimpleNamespace
from typing import Any

import pytest

from iface.live import link as link_module
from iface.live.link import Link, LinkError
from iface.operate import handover as handover_module
from iface.operate.handover import ACTIVATE, ACTIVE, INACTIVE, HandOver, Refused

ACTIVATING = 13  # lifecycle_msgs/State TRANSITION_STATE_ACTIVATING


class Future:
    def __init__(self, answer: Any) -> None:
        self.answer = answer

    def done(self) -> bool:
        return self.answer is not None

    def result(self) -> Any:
        return self.answer

    def add_done_callback(self, fn: Any) -> None:
        if self.answer is not None:
            fn(self)


class Client:
    """Drops the replies to the first ``lose`` requests, answers the others at once (``answers`` in turn)."""

    def __init__(self, answer: Any, lose: int, answers: list[Any] | None = None) -> None:
        self.answers = answers or [answer]
        self.lose, self.sent = lose, 0

    def service_is_ready(self) -> bool:
        return True

    def call_async(self, request: Any) -> Future:
        self.sent += 1
        if self.sent <= self.lose:
            return Future(None)
        return Future(self.answers[min(self.sent - self.lose, len(self.answers)) - 1])

    def remove_pending_request(self, future: Future) -> None:
        pass


def make(monkeypatch: pytest.MonkeyPatch, clients: dict[str, Client], timeout: float = 1.0) -> HandOver:
    monkeypatch.setattr(link_module, "RESEND", 0.05)
    monkeypatch.setattr(link_module, "TRANSITION_WAIT", 0.05)
    monkeypatch.setattr(link_module, "_transition_msg", lambda transition: transition)
    node = SimpleNamespace(create_client=lambda srv, name, callback_group=None: clients[name])
    link = Link(node)
    for name in clients:
        link.know(name, SimpleNamespace(Request=SimpleNamespace))
    return HandOver("old", "new", "hash", timeout=timeout, link=link)


def status(state: int) -> Any:
    return SimpleNamespace(lifecycle_state=state, interface_hash="hash", component="c", version="1")


def test_an_idempotent_request_is_sent_again_after_a_lost_reply(monkeypatch: pytest.MonkeyPatch) -> None:
    old = Client(status(ACTIVE), lose=2)
    h = make(monkeypatch, {"/old/control": old, "/new/control": Client(status(1), lose=0)})
    h.check_nodes()
    assert old.sent == 3
    assert [s.step for s in h.steps] == ["status OLD", "status NEW", "hash"]


def test_no_answer_at_all_is_refused_within_the_timeout(monkeypatch: pytest.MonkeyPatch) -> None:
    client = Client(None, lose=10**6)
    h = make(monkeypatch, {"/old/control": client})
    with pytest.raises(LinkError, match="does not answer within 0.3 s"):
        h.calls.call("/old/control", {}, 0.3)
    assert client.sent > 1


@pytest.mark.parametrize(("states", "taken", "sent"), [
    ([ACTIVE], True, 1),                 # the reply was lost, the node is active: done, not sent again
    ([ACTIVATING, ACTIVE], True, 1),     # still activating: waited for, not sent again
    ([INACTIVE], False, 2),              # still where it starts: the request was lost, sent again
])
def test_a_transition_is_judged_by_the_state(monkeypatch: pytest.MonkeyPatch, states: list[int], taken: bool,
                                             sent: int) -> None:
    change = Client(SimpleNamespace(success=True), lose=10**6)
    get_state = Client(None, lose=1, answers=[SimpleNamespace(current_state=SimpleNamespace(id=s)) for s in states])
    h = make(monkeypatch, {"/new/change_state": change, "/new/get_state": get_state}, timeout=2.0)
    if taken:
        h._transition("/new", ACTIVATE, "activate")
        assert change.sent == sent
    else:
        with pytest.raises(Refused, match="change_state does not answer"):
            h._transition("/new", ACTIVATE, "activate")
        assert change.sent >= sent
    assert get_state.sent >= 2, "the lost get_state reply was not asked again"


def test_a_refused_transition_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    change = Client(SimpleNamespace(success=False), lose=0)
    get_state = Client(SimpleNamespace(current_state=SimpleNamespace(id=INACTIVE)), lose=0)
    h = make(monkeypatch, {"/new/change_state": change, "/new/get_state": get_state})
    with pytest.raises(Refused, match="refused to activate"):
        h._transition("/new", ACTIVATE, "activate")
    assert change.sent == 1


class Discovery:
    """OLD's publisher of /tick matched by 3 subscriptions; NEW's by 2 until ``after`` seconds of a fake clock."""

    def __init__(self, after: float) -> None:
        self.after, self.now = after, 0.0

    def monotonic(self) -> float:
        return self.now

    def pause(self, seconds: float, done: object = None) -> None:
        self.now += seconds

    def matched(self, node: str) -> dict[str, int]:
        return {"/tick": 3 if node == "/old" or self.now >= self.after else 2}


def awaited(monkeypatch: pytest.MonkeyPatch, after: float, timeout: float) -> HandOver:
    discovery = Discovery(after)
    h = make(monkeypatch, {}, timeout=timeout)
    monkeypatch.setattr(handover_module, "time", discovery)
    monkeypatch.setattr(h.calls, "pause", discovery.pause)
    monkeypatch.setattr(h, "_matched", discovery.matched)
    h._await_matches()
    return h


def test_a_subscriber_that_discovers_new_late_is_waited_for_within_the_timeout(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # a lost discovery announcement is sent again after seconds: 7 s is within the 10 s timeout
    h = awaited(monkeypatch, after=7.0, timeout=10.0)
    assert [(s.step, s.ok) for s in h.steps] == [("match", True)]
    waited = re.fullmatch(r"NEW's publishers on /tick matched as OLD's are \((\d+) ms\)", h.steps[0].detail)
    assert waited and 7000 <= int(waited.group(1)) <= 7100, h.steps[0].detail


def test_a_match_that_never_comes_ends_the_wait_at_the_timeout_and_says_so(monkeypatch: pytest.MonkeyPatch) -> None:
    h = awaited(monkeypatch, after=float("inf"), timeout=10.0)
    assert [s.step for s in h.steps] == ["match"]
    assert h.steps[0].detail == ("after 10 s NEW's publishers still match fewer subscriptions than OLD's: "
                                 "/tick 2 of 3; going on"), h.steps[0].detail
