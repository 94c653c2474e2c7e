"""The Python runtime (``iface_runtime_py``) imported as the module it is, without ROS.

Its ROS-free modules (``state``, ``params``, ``gate``, ``handlers``, ``describe``) are tested here
everywhere; the node (``runtime``, rclpy) runs in the ROS tests (test_rclpy_e2e.py and others).
"""

from __future__ import annotations

import json
import re
import threading
import time
from pathlib import Path

import pytest
from iface_runtime_py import describe, gate, handlers, params, state

from iface.emit import generate
from iface.nodes import protocol
from iface.semantics.compile import Workspace

from ..ros_harness.ros import ROOT


class Msg:
    """A message stand-in: attributes."""

    def __init__(self, **values: object) -> None:
        self.__dict__.update(values)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Msg) and self.__dict__ == other.__dict__


TYPES = {"p/Point": {"x": "float64", "name": "string<=4"}}
SCHEMA = {"count": "uint32", "label": "string<=8", "where": "p/Point", "path": "p/Point[<=3]", "gain": "float32",
          "raw": "byte[]", "flag": "bool"}


def _codec(schema: dict[str, str] = SCHEMA, hash_: str = "sha256:a"):
    return state.StateCodec("c", "1.0.0", hash_, schema, lambda t: TYPES[t], lambda t: Msg(x=0.0, name=""))


def _state() -> Msg:
    return Msg(count=7, label="abc", where=Msg(x=1.5, name="home"), path=[Msg(x=1.0, name="a")],
               gain=float("nan"), raw=b"\x01\x02", flag=True)


def test_the_state_document_round_trips() -> None:
    codec = _codec()
    text = codec.save(_state())
    doc = json.loads(text)
    assert text == json.dumps(doc, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    assert doc["format"] == protocol.STATE_FORMAT and doc["interface_hash"] == "sha256:a"
    assert doc["types"] == TYPES and doc["schema"] == SCHEMA
    assert doc["values"]["gain"] == "nan" and doc["values"]["raw"] == [1, 2]
    target = Msg(count=0, label="", where=Msg(x=0.0, name=""), path=[], gain=0.0, raw=b"", flag=False)
    report = codec.restore(target, text)
    assert report.same_interface and report.restored == sorted(SCHEMA) and report.kept == []
    assert target.count == 7 and target.where == Msg(x=1.5, name="home") and target.raw == b"\x01\x02"


def test_a_wider_type_takes_the_state_a_narrower_or_other_one_refuses_it() -> None:
    text = _codec().save(_state())
    wider = dict(SCHEMA, count="uint64", label="string", gain="float64", extra="int8")
    report = _codec(wider, "sha256:b").restore(Msg(), text)
    assert not report.same_interface and report.kept == ["extra"]
    for name, other in (("count", "uint16"), ("label", "string<=2"), ("gain", "int32"), ("count", "string")):
        with pytest.raises(state.StateError, match=f"state '{name}' is .* in c 1.0.0 but {re.escape(other)}"):
            _codec(dict(SCHEMA, **{name: other})).read(text)
    smaller = {k: v for k, v in SCHEMA.items() if k != "flag"}
    with pytest.raises(state.StateError, match="state 'flag' of c 1.0.0 has no place in c"):
        _codec(smaller).read(text)


def test_values_that_do_not_fit_are_refused_and_nothing_is_restored() -> None:
    doc = json.loads(_codec().save(_state()))
    for name, value, reason in (("count", -1, "does not fit uint32"), ("label", "123456789", "do not fit"),
                                ("path", [{"x": 1.0}] * 4, "at most 3"), ("flag", 1, "true or false"),
                                ("where", {"x": 1.0, "z": 2}, "no field z")):
        bad = json.loads(json.dumps(doc))
        bad["values"][name] = value
        target = Msg(count=0)
        with pytest.raises(state.StateError, match=reason):
            _codec().restore(target, json.dumps(bad))
        assert target.count == 0
    with pytest.raises(state.StateError, match="format"):
        _codec().read(json.dumps(dict(doc, format="other/2")))
    with pytest.raises(state.StateError, match="not JSON"):
        _codec().read("{")


def test_parameter_checks() -> None:
    spec = params.ParamSpec("gain", "double", low=0.0, high=10.0, unit="1/s")
    assert spec.problem(5.0) is None
    assert spec.problem(11.0) == "gain=11.0 1/s is above the maximum 10.0 1/s"
    mode = params.ParamSpec("mode", "integer", choices=(("IDLE", 0), ("RUN", 1)))
    assert mode.problem(1) is None and "not one of IDLE (0), RUN (1)" in mode.problem(3)
    label = params.ParamSpec("label", "string", max_length=3)
    assert "at most 3" in label.problem("abcd")
    fixed = params.ParamSpec("v", "double_array", size=2, size_kind="fixed", low=0.0)
    assert "exactly 2" in fixed.problem([1.0]) and "v[1]=-1.0 is below" in fixed.problem([1.0, -1.0])
    bounded = params.ParamSpec("ids", "integer_array", size=2, size_kind="bounded")
    assert bounded.problem([1, 2]) is None and "at most 2" in bounded.problem([1, 2, 3])


def test_pause_waits_for_the_transaction_in_progress_or_leaves_the_gate_as_it_was() -> None:
    g = gate.Gate()
    assert g.enter()
    ok, message = g.pause(0.05)
    assert not ok and "still running" in message and not g.paused
    threading.Timer(0.1, g.leave).start()
    start = time.monotonic()
    ok, message = g.pause(5.0)
    assert ok and g.paused and time.monotonic() - start >= 0.09
    assert message == "paused after 1 work transaction(s) in progress ended"
    assert not g.enter() and g.refused == 1
    with pytest.raises(gate.Paused), g.transaction():
        pass
    assert g.resume() == (True, "resumed") and g.enter()
    g.leave()
    with g.quiet(1.0):
        assert not g.paused and g.holds == 1
    assert not g.paused and g.holds == 0
    g.pause(1.0)
    with g.quiet(1.0):  # a paused gate needs no hold
        assert g.paused and g.holds == 0
    assert g.paused


def _enter_in_thread(g: gate.Gate) -> tuple[threading.Thread, list[bool]]:
    entered: list[bool] = []
    thread = threading.Thread(target=lambda: entered.append(g.enter()), daemon=True)
    thread.start()
    return thread, entered


def test_a_snapshot_holds_new_work_and_refuses_none() -> None:
    """Work that arrives during a save waits for it: a subscriber's message is handled after the snapshot, not
    dropped (a tally in a container missed a count at each save)."""
    g = gate.Gate()
    with g.quiet(1.0):
        assert not g.paused and g.holds == 1
        thread, entered = _enter_in_thread(g)
        thread.join(0.2)
        assert thread.is_alive() and entered == [] and g.in_flight == 0, "work ran during the snapshot"
    thread.join(5.0)
    assert entered == [True] and g.refused == 0 and g.holds == 0
    g.leave()


def test_a_snapshot_waits_for_the_work_in_progress_and_a_pause_refuses_the_work_it_held() -> None:
    g = gate.Gate()
    assert g.enter()
    with pytest.raises(TimeoutError, match="1 work transaction"), g.quiet(0.05):
        pass
    assert g.holds == 0 and g.enter()
    g.leave()
    g.leave()
    with g.quiet(1.0):
        thread, entered = _enter_in_thread(g)
        thread.join(0.1)
        assert g.pause(1.0) == (True, "paused")
        thread.join(5.0)
        assert entered == [False] and g.refused == 1



def test_closing_waits_for_the_work_in_progress_and_lets_none_in_until_opened() -> None:
    """Cleanup and shutdown close the gate before they destroy the members: a tick that began before a SIGTERM's
    shutdown ends first, and one that comes after is turned away (not counted as refused, as a pause's is)."""
    g = gate.Gate()
    assert g.enter()
    assert g.close(0.05) == (False, "1 work transaction(s) still running after 0.05 s")
    assert g.closed and not g.enter() and g.refused == 0
    threading.Timer(0.1, g.leave).start()
    start = time.monotonic()
    assert g.close(5.0) == (True, "closed") and time.monotonic() - start >= 0.09 and g.in_flight == 0
    g.open()
    with g.quiet(1.0):
        thread, entered = _enter_in_thread(g)  # held by the snapshot
        thread.join(0.1)
        assert g.close(1.0) == (True, "closed")  # turns the held work away
        thread.join(5.0)
        assert entered == [False] and g.refused == 0
    g.open()
    assert g.enter() and not g.closed
    g.leave()

def test_the_handler_check_names_missing_mismatched_and_stale_handlers() -> None:
    class Base:
        def on_x(self, msg):
            raise NotImplementedError

        def accept_g_goal(self, goal):
            return True

    specs = {"on_x": handlers.HandlerSpec(("msg",), "subscribes M on /x"),
                "handle_s": handlers.HandlerSpec(("request", "response"), "provides S on /s"),
                "accept_g_goal": handlers.HandlerSpec(("goal",), "provides G on /g", required=False)}

    class User(Base):
        NOT_HANDLERS = ("on_tick",)

        def on_x(self, msg, extra):
            pass

        def on_old(self, msg):
            pass

        def on_tick(self):
            pass

    problems = handlers.handler_problems(User, Base, specs, ("on_", "handle_"), "c.iface")
    assert problems == [
        "User.on_x cannot be called with (msg), as 'subscribes M on /x' calls it",
        "User has no handle_s(self, request, response), which handles 'provides S on /s' of c.iface",
        ("User.on_old handles nothing in c.iface (was its member renamed or removed? list helper methods with such "
        "names in NOT_HANDLERS)"),
    ]


def test_the_state_document_says_its_protocol_and_an_older_document_still_restores() -> None:
    codec = _codec()
    doc = json.loads(codec.save(_state(), {"tick": 1_700_000_000_000_000_000}))
    assert doc["protocol_version"] == protocol.PROTOCOL_VERSION and doc["schedule"] == {"tick": 1700000000000000000}
    assert codec.read(json.dumps(doc))[1].schedule == {"tick": 1700000000000000000}
    del doc["protocol_version"], doc["schedule"]  # as iface-state/1 was written before both existed
    target = Msg(count=0, label="", where=Msg(x=0.0, name=""), path=[], gain=0.0, raw=b"", flag=False)
    report = codec.restore(target, json.dumps(doc))
    assert report.restored == sorted(SCHEMA) and report.schedule == {} and target.count == 7


def test_a_newer_state_format_is_refused_with_the_reason() -> None:
    doc = dict(json.loads(_codec().save(_state())), format="iface-state/2", protocol_version="2")
    with pytest.raises(state.StateError, match=r"format 'iface-state/2' \(protocol 2\) is newer than this "
                                                  r"runtime's 'iface-state/1' \(protocol 1\): update iface_runtime_py"):
        _codec().read(json.dumps(doc))
    with pytest.raises(state.StateError, match="format is 'other', not 'iface-state/1'"):
        _codec().read(json.dumps(dict(doc, format="other")))




# ---- what ~/describe answers ----------------------------------------------------------------------------


def test_describe_answers_the_installed_file_else_the_older_compact_form(tmp_path: Path) -> None:
    """A package generated now installs the json target's file; one generated before runtime 1.2 carries the form
    compact in base.py: answered as the json target writes it, indented and stamped."""
    comp = Workspace().compile_path(str(ROOT / "examples" / "robot_arm.iface"))
    (wanted,) = generate(comp, "json").files
    from iface.emit.write import stamp

    written = stamp(wanted.text)
    compact = json.dumps(json.loads(wanted.text), ensure_ascii=False, separators=(",", ":"))
    assert describe.from_compact(compact) == written
    assert describe.interface_json("robot_arm", "robot_arm.json", compact) == written  # nothing installed here
    assert describe.installed_interface("no_such_package", "robot_arm.json") == ""
    assert describe.interface_json("no_such_package", "", "") == ""


def test_describe_reads_the_file_from_the_package_share_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    share = tmp_path / "share" / "arm"
    share.mkdir(parents=True)
    (share / "arm.json").write_text('{"generated": "x"}\n', encoding="utf-8")
    monkeypatch.setattr(describe, "share_directory", lambda package: str(share) if package == "arm" else None)
    assert describe.interface_json("arm", "arm.json", '{"old": 1}') == '{"generated": "x"}\n'
    assert describe.interface_json("arm", "missing.json", "") == ""


# ---- the package itself -----------------------------------------------------------------------------


def test_the_version_is_package_xmls_and_older_base_classes_still_import() -> None:
    import iface_runtime_py
    from iface_runtime_py import contract

    from iface.nodes.shared import source_version

    assert iface_runtime_py.__version__ == source_version("iface_runtime_py") == iface_runtime_py.package_version()
    # what a base.py generated by runtime 1.1 imports
    assert contract.HandlerSpec is handlers.HandlerSpec and contract.ParamSpec is params.ParamSpec
