"""The live import and verify without ROS 2: readings written as .iface, findings from a graph given as data.

The graph is read by rclpy in ``test_live.py``; here the two pure halves are checked on hand-made
readings, so they run everywhere, and the commands' answer when ROS 2 is not sourced.
"""

from __future__ import annotations

import functools
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from iface.live.reading import NamedEndpoint, NodeReading, Param, Qos, TopicEndpoint
from iface.live.to_iface import UNKNOWN_DEPTH, node_iface
from iface.live.verify import CODES, LiveGraph, Peer, declared, verify
from iface.semantics.compile import Workspace

ROOT = Path(__file__).resolve().parents[2]
DEFAULT = Qos("reliable", "volatile", "automatic")


def talker() -> NodeReading:
    """A node as the graph tells it, with ROS 2's own endpoints among its own."""
    snap = NodeReading("/live/talker")
    snap.topics = [
        TopicEndpoint("publishes", "/chatter", "std_msgs/msg/String",
                      Qos("best_effort", "transient_local", "automatic", deadline=2.0, history="keep_last", depth=5)),
        TopicEndpoint("subscribes", "/numbers", "std_msgs/msg/Int32",
                      Qos("reliable", "volatile", "manual_by_topic", lease_duration=3.0)),
        TopicEndpoint("publishes", "/rosout", "rcl_interfaces/msg/Log", DEFAULT),
        TopicEndpoint("publishes", "/parameter_events", "rcl_interfaces/msg/ParameterEvent", DEFAULT),
    ]
    snap.endpoints = [
        NamedEndpoint("provides", "service", "/live/talker/add", "diagnostic_msgs/srv/AddDiagnostics"),
        NamedEndpoint("provides", "service", "/live/talker/get_parameters", "rcl_interfaces/srv/GetParameters"),
        NamedEndpoint("calls", "service", "/arm/move_to_pose", "robot_arm_msgs/srv/MoveToPose"),
        NamedEndpoint("provides", "action", "/follow", "robot_arm_msgs/action/FollowTrajectory"),
    ]
    snap.params = [
        Param("rate", "double", 2.5, "Loop rate.", False, 0.5, 10.0, "unit: Hz"),
        Param("count", "integer", 50, "", False, 0, 100),
        Param("frame", "string", "base", "Frame.", True),
        Param("gains", "double_array", (1.0, 2.0)),
        Param("use_sim_time", "bool", False),
    ]
    return snap


def compiled(path: Path, text: str):
    path.write_text(text, encoding="utf-8")
    return Workspace().compile_path(str(path))


def test_a_reading_is_written_as_a_checked_file_naming_exactly_what_the_node_has(tmp_path: Path) -> None:
    out = node_iface(talker())
    assert out.path == "talker.iface"
    comp = compiled(tmp_path / out.path, out.text)
    assert [d.code for d in comp.diagnostics] == []
    iface = comp.interface
    assert [(e.role, e.name) for e in iface.published] == [("publishes", "/chatter")]
    assert [(e.role, e.name) for e in iface.subscribed] == [("subscribes", "/numbers")]
    assert [(e.role, e.name) for e in iface.services] == [("provides", "~/add"), ("calls", "/arm/move_to_pose")]
    assert [(e.role, e.name) for e in iface.actions] == [("provides", "/follow")]
    assert [f.name for f in iface.parameters] == ["rate", "count", "frame", "gains"]
    assert iface.published[0].wiring.qos == {"reliability": "best_effort", "durability": "transient_local",
                                             "depth": "5", "deadline": "2s"}
    assert iface.subscribed[0].wiring.qos == {"liveliness": "manual_by_topic", "liveliness_lease_duration": "3s"}
    assert 'float64 rate = 2.5 (unit = "Hz", range = "0.5..10")' in out.text
    assert 'string frame = "base" (read_only)' in out.text
    assert "/** Loop rate. */" in out.text
    assert out.text.count(UNKNOWN_DEPTH) == 1  # /numbers: no qos_overrides parameters tell its depth
    assert "rosout" not in out.text and "get_parameters" not in out.text and "use_sim_time" not in out.text
    everything = node_iface(talker(), everything=True).text
    assert "/rosout" in everything and "~/get_parameters" in everything and "use_sim_time" in everything


def test_a_lifecycle_node_is_marked_and_its_lifecycle_services_left_out() -> None:
    snap = NodeReading("/lifer", lifecycle=True)
    snap.endpoints = [NamedEndpoint("provides", "service", "/lifer/get_state", "lifecycle_msgs/srv/GetState")]
    snap.topics = [TopicEndpoint("publishes", "/lifer/transition_event", "lifecycle_msgs/msg/TransitionEvent",
                                 DEFAULT)]
    text = node_iface(snap).text
    assert 'component lifer (ros2.node = "/lifer", ros2.lifecycle)' in text
    assert "get_state" not in text and "transition_event" not in text


def declared_talker(tmp_path: Path, count_range: str = "0..100"):
    text = node_iface(talker()).text.replace('range = "0..100"', f'range = "{count_range}"')
    return declared(compiled(tmp_path / "talker.iface", text))


def test_a_node_that_matches_its_file_gives_no_finding(tmp_path: Path) -> None:
    live = LiveGraph(["/live/talker"], {"/live/talker": talker()})
    assert verify([declared_talker(tmp_path)], live) == []


def test_each_planted_fault_is_found_once_with_its_code(tmp_path: Path) -> None:
    d = declared_talker(tmp_path, "0..10")
    ghost = declared(compiled(tmp_path / "ghost.iface", "component ghost\n"))
    snap = talker()
    snap.topics[1] = TopicEndpoint("subscribes", "/numbers", "std_msgs/msg/Float64", snap.topics[1].qos)
    snap.topics.append(TopicEndpoint("publishes", "/extra", "std_msgs/msg/Int32", DEFAULT))
    peers = {"/chatter": [Peer("/live/talker", "publishes", "std_msgs/msg/String", snap.topics[0].qos),
                          Peer("/live/listener", "subscribes", "std_msgs/msg/String", DEFAULT)]}
    found = verify([d, ghost], LiveGraph(["/live/talker"], {"/live/talker": snap}, peers))
    assert sorted(f.code for f in found) == sorted(["live-param-out-of-range", "live-type-mismatch",
                                                    "live-endpoint-undeclared", "live-qos-incompatible",
                                                    "live-node-missing"])
    by = {f.code: f for f in found}
    assert "std_msgs/Int32" in by["live-type-mismatch"].message and "std_msgs/Float64" in by["live-type-mismatch"].message
    assert by["live-node-missing"].path.endswith("ghost.iface") and by["live-node-missing"].line == 1
    assert by["live-param-out-of-range"].node == "/live/talker"
    assert "reliability" in by["live-qos-incompatible"].message
    assert by["live-endpoint-undeclared"].severity == "warning"
    text = (tmp_path / "talker.iface").read_text().splitlines()
    assert "count" in text[by["live-param-out-of-range"].line - 1]
    assert set(CODES) >= set(by)


def test_parameter_missing_and_of_another_type(tmp_path: Path) -> None:
    d = declared_talker(tmp_path)
    snap = talker()
    snap.params = [p for p in snap.params if p.name != "frame"]
    snap.params[0] = Param("rate", "string", "fast")
    codes = sorted(f.code for f in verify([d], LiveGraph(["/live/talker"], {"/live/talker": snap})))
    assert codes == ["live-param-missing", "live-param-type"]


def test_a_describe_hash_that_differs_is_found(tmp_path: Path) -> None:
    d = declared_talker(tmp_path)
    snap = talker()
    snap.describe_hash = "sha256:0000"
    codes = [f.code for f in verify([d], LiveGraph(["/live/talker"], {"/live/talker": snap}))]
    assert codes == ["live-describe-hash"]


@functools.cache
def _without_ros() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "AMENT_PREFIX_PATH")}
    env["PYTHONPATH"] = str(ROOT / "server")
    probe = subprocess.run([sys.executable, "-c", "import rclpy"], env=env, capture_output=True, timeout=60)
    return env if probe.returncode != 0 else {}


@pytest.mark.parametrize("argv", [["import", "--from", "node", "/talker"],
                                  ["verify", str(ROOT / "examples" / "counter.iface")]])
def test_without_ros_the_commands_say_so_in_one_line_and_exit_2(argv: list[str]) -> None:
    env = _without_ros()
    if not env:
        pytest.skip("rclpy is importable without sourcing ROS 2 here")
    done = subprocess.run([sys.executable, "-m", "iface", *argv], env=env, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 2
    assert done.stdout == ""
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "ROS 2 is not sourced" in lines[0], done.stderr


def test_the_system_file_names_every_imported_node_and_verify_reads_its_instances(tmp_path: Path) -> None:
    from iface.commands.live import system_text
    from iface.live.verify import declared_all

    lifer = NodeReading("/lifer", lifecycle=True)
    for snap in (talker(), lifer):
        out = node_iface(snap)
        (tmp_path / out.path).write_text(out.text, encoding="utf-8")
    system = tmp_path / "room.iface"
    system.write_text(system_text("room", [("/live/talker", "talker", "talker.iface"),
                                           ("/lifer", "lifer", "lifer.iface")]), encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "iface", "check", str(system)], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT / "server")})
    assert done.returncode == 0, done.stdout + done.stderr
    decls = declared_all([Workspace().compile_path(str(system))])
    assert [(d.node, d.comp.interface.name) for d in decls] == [("/live/talker", "talker"), ("/lifer", "lifer")]
    found = verify(decls, LiveGraph(["/live/talker"], {"/live/talker": talker()}))
    assert [(f.code, Path(f.path).name, f.line) for f in found] == [("live-node-missing", "room.iface", 9)]


def test_a_describe_answer_gives_the_whole_interface_exactly(tmp_path: Path) -> None:
    """The interface_json of a Describe answer (the JSON form) is read back: compat finds it equivalent."""
    from iface.commands.live import described_files
    from iface.emit import generate

    source = ROOT / "tests" / "runtime" / "data" / "live" / "live_probe.iface"
    form = next(f.text for f in generate(Workspace().compile_path(str(source)), "json").files
                if f.path.endswith(".json"))
    files = described_files("live_probe", form)
    assert [f.path for f in files] == ["live_probe.iface"]
    (tmp_path / "live_probe.iface").write_text(files[0].text, encoding="utf-8")
    from iface.compat import compare

    report = compare(Workspace().compile_path(str(source)), Workspace().compile_path(str(tmp_path / "live_probe.iface")))
    assert report.verdict == "equivalent", [f.message for f in report.findings]


def test_declared_parameter_types_map_to_the_ros_2_types_nodes_hold(tmp_path: Path) -> None:
    from iface.live.verify import param_kind

    text = """component p
enum Mode { A = 0 }
typedef float64 Metres
configuration c {
    bool b, i32 i, u8 o, octet x, float32 f, Metres m, string s, Mode e, binary bin, uuid id,
    float64[] fs, list<i16> ls, string[<=3] ss, bool[2] bs
}
"""
    comp = compiled(tmp_path / "p.iface", text)
    kinds = {f.name: param_kind(f) for f in comp.interface.parameters}
    assert kinds == {"b": "bool", "i": "integer", "o": "integer", "x": "integer", "f": "double", "m": "double",
                     "s": "string", "e": "integer", "bin": "integer_array", "id": "integer_array",
                     "fs": "double_array", "ls": "integer_array", "ss": "string_array", "bs": "bool_array"}


def test_a_component_file_given_beside_the_system_that_runs_it_is_verified_once(tmp_path: Path) -> None:
    from iface.commands.live import system_text
    from iface.live.verify import declared_all

    out = node_iface(talker())
    (tmp_path / out.path).write_text(out.text, encoding="utf-8")
    (tmp_path / "room.iface").write_text(system_text("room", [("/live/talker", "talker", "talker.iface")]),
                                         encoding="utf-8")
    comps = [Workspace().compile_path(str(tmp_path / n)) for n in ("talker.iface", "room.iface")]
    assert [(d.node, d.instance is not None) for d in declared_all(comps)] == [("/live/talker", True)]


def test_findings_render_as_text_json_and_sarif(tmp_path: Path) -> None:
    import json

    from iface.live.report import render_json, render_sarif, render_text

    d = declared_talker(tmp_path, "0..10")
    found = verify([d], LiveGraph(["/live/talker"], {"/live/talker": talker()}))
    assert [f.code for f in found] == ["live-param-out-of-range"]
    text = render_text(found, str, 1).splitlines()
    assert text[0].startswith(f"{found[0].path}:{found[0].line}:{found[0].column}: error[live-param-out-of-range]: ")
    assert text[-1] == "verify: 1 node: 1 error, 0 warnings"
    doc = json.loads(render_json(found, str, 1))
    assert (doc["nodes"], doc["errors"], doc["warnings"]) == (1, 1, 0)
    assert doc["findings"][0]["node"] == "/live/talker"
    sarif = json.loads(render_sarif(found, str, "0"))
    result = sarif["runs"][0]["results"][0]
    assert sarif["version"] == "2.1.0" and result["ruleId"] == "live-param-out-of-range"
    assert result["locations"][0]["physicalLocation"]["region"]["startLine"] == found[0].line
    assert {r["id"] for r in sarif["runs"][0]["tool"]["driver"]["rules"]} == set(CODES)
    assert render_text([], str, 2) == "verify: 2 nodes conform to their interfaces\n"


class _ArrivingGraph:
    """A graph on which the node ``/live/listener`` shows at once with its parameter services, and its
    subscription ``/chatter`` only ``late`` seconds after (endpoints are discovered one by one)."""

    def __init__(self, late: float) -> None:
        self.start = time.monotonic()
        self.late = late

    def get_node_names_and_namespaces(self) -> list[tuple[str, str]]:
        return [("listener", "/live")]

    def get_publisher_names_and_types_by_node(self, name: str, ns: str) -> list[tuple[str, list[str]]]:
        return [("/rosout", ["rcl_interfaces/msg/Log"])]

    def get_subscriber_names_and_types_by_node(self, name: str, ns: str) -> list[tuple[str, list[str]]]:
        arrived = time.monotonic() - self.start >= self.late
        return [("/chatter", ["std_msgs/msg/String"])] if arrived else []

    def get_service_names_and_types_by_node(self, name: str, ns: str) -> list[tuple[str, list[str]]]:
        return [("/live/listener/list_parameters", ["rcl_interfaces/srv/ListParameters"])]

    def get_client_names_and_types_by_node(self, name: str, ns: str) -> list[tuple[str, list[str]]]:
        return []


def _graph_over(fake: _ArrivingGraph, timeout: float) -> Any:
    from iface.live.graph import Graph

    graph = object.__new__(Graph)  # the reading logic alone, over a stand-in for rclpy's node
    graph.timeout = timeout
    graph.node = fake
    return graph


def test_verify_waits_for_each_declared_endpoint_past_a_pause_in_discovery() -> None:
    """An endpoint the file declares, seen a second after its node, is waited for; one never seen costs the
    grace, not the whole timeout."""
    fake = _ArrivingGraph(late=1.0)
    graph = _graph_over(fake, timeout=30)
    assert graph.wait_for(["/live/listener"], expect={"/live/listener": {"/chatter"}}) == []
    assert ("/chatter", ["std_msgs/msg/String"]) in fake.get_subscriber_names_and_types_by_node("listener", "/live")
    never = _ArrivingGraph(late=1e9)
    graph = _graph_over(never, timeout=30)
    began = time.monotonic()
    assert graph.wait_for(["/live/listener"], expect={"/live/listener": {"/chatter"}}) == []
    assert time.monotonic() - began < 25, "a never-seen endpoint held the wait to the timeout"


def test_every_node_with_another_type_on_a_declared_topic_service_or_action_is_found(tmp_path: Path) -> None:
    """Issue 33: an undeclared node that publishes std_msgs/Int32 on /chatter, which the file publishes as
    std_msgs/String, is named with both types at the declared line; so are subscribers, servers and clients."""
    import json

    from iface.live.report import render_json, render_sarif, render_text
    from iface.live.verify import NamedPeer

    d = declared_talker(tmp_path)
    snap = talker()
    quiet = Qos("best_effort", "volatile", "automatic")
    peers = {
        "/chatter": [Peer("/live/talker", "publishes", "std_msgs/msg/String", snap.topics[0].qos),
                     Peer("/intruder", "publishes", "std_msgs/msg/Int32", quiet),
                     Peer("/live/listener", "subscribes", "std_msgs/msg/String", quiet)],
        "/numbers": [Peer("/live/talker", "subscribes", "std_msgs/msg/Int32", snap.topics[1].qos),
                     Peer("/counter", "publishes", "std_msgs/msg/Int64", snap.topics[1].qos)],
    }
    named = {"/arm/move_to_pose": [NamedPeer("/arm", "provides", "std_srvs/srv/Trigger")],
             "/follow": [NamedPeer("/boss", "calls", "other_msgs/action/Follow"),
                         NamedPeer("/live/talker", "provides", "robot_arm_msgs/action/FollowTrajectory")]}
    found = verify([d], LiveGraph(["/live/talker", "/intruder"], {"/live/talker": snap}, peers, named))
    assert [(f.code, f.node) for f in found] == [("live-type-mismatch", n) for n in
                                                  ("/intruder", "/counter", "/arm", "/boss")], found
    lines = (tmp_path / "talker.iface").read_text().splitlines()
    for f, name, want, got in zip(found, ("/chatter", "/numbers", "/arm/move_to_pose", "/follow"),
                                  ("std_msgs/String", "std_msgs/Int32", "robot_arm_msgs/MoveToPose",
                                   "robot_arm_msgs/FollowTrajectory"),
                                  ("std_msgs/Int32", "std_msgs/Int64", "std_srvs/Trigger", "other_msgs/Follow"),
                                  strict=True):
        assert f.message == f"'{name}': declared {want}, {f.node} {_verb(f.node)} {got}", f.message
        assert f"\"{name}\"" in lines[f.line - 1], (name, lines[f.line - 1])
    text = render_text(found, str, 1).splitlines()
    assert text[0] == (f"{found[0].path}:{found[0].line}:{found[0].column}: error[live-type-mismatch]: '/chatter': "
                       "declared std_msgs/String, /intruder publishes std_msgs/Int32 [/intruder]")
    assert text[-1] == "verify: 1 node: 4 errors, 0 warnings"
    doc = json.loads(render_json(found, str, 1))
    assert [(x["node"], x["line"]) for x in doc["findings"]] == [(f.node, f.line) for f in found]
    sarif = json.loads(render_sarif(found, str, "0"))["runs"][0]["results"]
    assert [r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in sarif] == [f.line for f in found]
    assert all("[/" in r["message"]["text"] for r in sarif)


def _verb(node: str) -> str:
    return {"/intruder": "publishes", "/counter": "publishes", "/arm": "serves", "/boss": "calls"}[node]


def test_a_declared_topic_of_a_node_that_is_not_running_is_still_checked(tmp_path: Path) -> None:
    ghost = declared(compiled(tmp_path / "ghost.iface", "component ghost\nexternal std_msgs\n"
                                                        'publishes std_msgs.String on "/ghost"\n'))
    peers = {"/ghost": [Peer("/other", "subscribes", "std_msgs/msg/Bool", DEFAULT)]}
    found = verify([ghost], LiveGraph(["/other"], {}, peers))
    assert [(f.code, f.node, f.line) for f in found] == [("live-node-missing", "/ghost", 1),
                                                         ("live-type-mismatch", "/other", 3)]


class _GraphOfPeers:
    """What read_live asks of the graph, answered from data; it records what is read node by node."""

    def __init__(self) -> None:
        self.asked: list[tuple[str, set[str]]] = []

    def wait_for(self, names: list[str], expect: dict[str, set[str]] | None = None, whole: bool = False) -> list[str]:
        assert whole, "verify waits for the whole graph to settle: other nodes come after the declared ones"
        return []

    def node_names(self) -> list[str]:
        return ["/live/talker", "/other"]

    def read_nodes(self, names: list[str]) -> dict[str, NodeReading]:
        return {"/live/talker": talker()}

    def peers(self, topic: str) -> list[tuple[str, str, str, Qos]]:
        return [("/other", "publishes", "std_msgs/msg/Int64", DEFAULT)] if topic == "/numbers" else []

    def names_and_types(self, kind: str) -> dict[str, tuple[str, ...]]:
        if kind == "service":
            return {"/arm/move_to_pose": ("robot_arm_msgs/srv/MoveToPose", "std_srvs/srv/Trigger"),
                    "/live/talker/add": ("diagnostic_msgs/srv/AddDiagnostics",)}
        return {"/follow": ("robot_arm_msgs/action/FollowTrajectory",)}

    def named_peers(self, kind: str, names: set[str]) -> dict[str, list[tuple[str, str, str]]]:
        self.asked.append((kind, names))
        if kind == "service" and names:
            return {"/arm/move_to_pose": [("/other", "provides", "std_srvs/srv/Trigger"),
                                          ("/live/talker", "calls", "robot_arm_msgs/srv/MoveToPose")]}
        return {}


def test_read_live_asks_node_by_node_only_for_a_name_the_graph_carries_with_another_type(tmp_path: Path) -> None:
    from iface.live.verify import read_live

    graph = _GraphOfPeers()
    live = read_live(graph, [declared_talker(tmp_path)])  # type: ignore[arg-type]
    assert graph.asked == [("service", {"/arm/move_to_pose"}), ("action", set())]
    assert set(live.peers) >= {"/chatter", "/numbers"}
    found = verify([declared_talker(tmp_path)], live)
    assert sorted((f.node, f.message.split(",")[0]) for f in found) == [
        ("/other", "'/arm/move_to_pose': declared robot_arm_msgs/MoveToPose"),
        ("/other", "'/numbers': declared std_msgs/Int32")]


@pytest.mark.parametrize(("no_describe", "describes", "whole"), [
    (False, True, False),   # every node answers Describe: its own answer, not the graph
    (False, False, True),   # a node without Describe is read off the graph
    (True, True, True),     # --no-describe: read off the graph
])
def test_import_from_nodes_read_off_the_graph_waits_for_the_whole_graph_to_be_quiet(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, no_describe: bool, describes: bool, whole: bool) -> None:
    """A node's endpoints are discovered one by one, with pauses under load: an import read off the graph
    waits until the whole graph is quiet (``wait_for(whole=True)``), as verify does, not only for a moment
    without change (a CI run imported /live_probe without two of its publishers)."""
    import contextlib

    from iface.live import graph as graph_module

    waits: list[bool] = []

    class Stand:
        def wait_for(self, names: list[str], whole: bool = False, **_: Any) -> list[str]:
            waits.append(whole)
            return []

        def describes(self, full: str) -> bool:
            return describes

        def read_nodes(self, names: list[str], describe: bool = True) -> dict[str, NodeReading]:
            return {n: NodeReading(n) for n in names}

    monkeypatch.setattr(graph_module, "open_graph", lambda timeout: contextlib.nullcontext(Stand()))
    monkeypatch.setattr(graph_module, "ros_missing", lambda: None)  # no ROS needed: the graph is a stand-in
    args = ["import", "--from", "node", "/talker", "--out", str(tmp_path), "-q", *(["--no-describe"] if no_describe else [])]
    from tests.conftest import run_main

    done = run_main(*args)
    assert done.returncode == 0, done.stderr
    assert waits == ([False, True] if whole else [False])
