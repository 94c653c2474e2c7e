"""The hand-over's service calls survive a lost reply (no ROS needed: a fake client drops replies).

A server just seen in the graph may not yet have matched the caller's reply reader, and DDS then
drops the reply. Idempotent requests are sent again; a lifecycle transition is sent once and,
without an answer, the node's state tells whether it happened.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import pytest

from iface.operate import handover
from iface.operate.handover import ACTIVATE, ACTIVE, INACTIVE, HandOver, Refused


class Future:
    def __init__(self, answer: Any) -> None:
        self.answer = answer

    def done(self) -> bool:
        return self.answer is not None

    def result(self) -> Any:
        return self.answer


class Client:
    """Drops the replies to the first ``lose`` requests, answers the others at once."""

    def __init__(self, answer: Any, lose: int) -> None:
        self.answer, self.lose, self.sent = answer, lose, 0

    def wait_for_service(self, timeout_sec: float) -> bool:
        return True

    def call_async(self, request: Any) -> Future:
        self.sent += 1
        return Future(None if self.sent <= self.lose else self.answer)


def make(monkeypatch: pytest.MonkeyPatch, clients: dict[str, Client]) -> HandOver:
    monkeypatch.setattr(handover, "RESEND", 0.05)
    h = HandOver("old", "new", "hash", timeout=1.0)
    h._rclpy = SimpleNamespace(spin_once=lambda node, timeout_sec: None)
    h._node = SimpleNamespace(create_client=lambda srv, name: clients[name])
    h._clients = {}
    monkeypatch.setattr(h, "_service_type", lambda service: SimpleNamespace(Request=SimpleNamespace))
    monkeypatch.setattr(handover, "_transition_msg", lambda transition: transition)
    return h


def test_an_idempotent_request_is_sent_again_after_a_lost_reply(monkeypatch: pytest.MonkeyPatch) -> None:
    client = Client(SimpleNamespace(success=True, state="{}"), lose=2)
    h = make(monkeypatch, {"/old/save_state": client})
    assert h._call("/old/save_state", {"timeout_sec": 1.0}).success
    assert client.sent == 3


def test_no_answer_at_all_is_refused_within_the_timeout(monkeypatch: pytest.MonkeyPatch) -> None:
    client = Client(None, lose=10**6)
    h = make(monkeypatch, {"/old/control": client})
    with pytest.raises(Refused, match="does not answer within 0.3 s"):
        h._call("/old/control", {}, timeout=0.3)
    assert client.sent > 1


@pytest.mark.parametrize(("state", "taken"), [(ACTIVE, True), (INACTIVE, False)])
def test_a_transition_is_sent_once_and_judged_by_the_state(monkeypatch: pytest.MonkeyPatch, state: int,
                                                            taken: bool) -> None:
    change = Client(SimpleNamespace(success=True), lose=10**6)
    get_state = Client(SimpleNamespace(current_state=SimpleNamespace(id=state)), lose=1)
    h = make(monkeypatch, {"/new/change_state": change, "/new/get_state": get_state})
    h.timeout = 0.3
    if taken:
        h._transition("/new", ACTIVATE, "activate")
    else:
        with pytest.raises(Refused, match="change_state does not answer"):
            h._transition("/new", ACTIVATE, "activate")
    assert change.sent == 1
    assert get_state.sent == 2
