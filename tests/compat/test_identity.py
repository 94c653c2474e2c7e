"""One name for a definition everywhere: its package (ros2 namespace) and name, in graph and compat --system.

Issue 16: ``graph`` named a type of an included file by the file stem in one place and by its
namespace in another, so a component that includes the robot arm's file conflicted with the
arm on its own topics; and ``compat --system`` compared only local names, so a peer's type of
another package with the same local name passed. Both now name types ``package/Name``.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from compat_support import run_main

from iface.compat import compare
from iface.compat.graph import build, graph_json
from iface.semantics.compile import Compilation, Workspace

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

#: includes the arm's file and uses its types on the arm's own topics and service
GRIPPER = """component gripper
namespace ros2 gripper_msgs
include "robot_arm.iface"
subscribes robot_arm.JointState on "/arm/joint_state" (qos.reliability = "best_effort")
publishes robot_msgs_alias.JointCommand on "/arm/joint_command"
provides robot_arm.MoveToPose on "/gripper/move_to_pose"
"""
#: its own JointState, in its own package, on the arm's topic
SPY = """component spy
namespace ros2 spy_msgs
message JointState { u64 timestamp }
subscribes JointState on "/arm/joint_state" (qos.reliability = "best_effort")
"""


def _system(tmp_path: Path) -> dict[str, Path]:
    for name in ("robot_arm.iface", "arm_common.iface"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    # the same type written through the include's ros2 namespace instead of its stem
    (tmp_path / "gripper.iface").write_text(GRIPPER.replace("robot_msgs_alias", "robot_arm_msgs"))
    (tmp_path / "spy.iface").write_text(SPY)
    arm = (tmp_path / "robot_arm.iface").read_text()
    # an older arm that did not publish the joint state yet
    (tmp_path / "arm_old.iface").write_text(arm.replace(
        'publishes JointState on "/arm/joint_state" (qos.reliability = "best_effort", qos.depth = 1)\n', ""))
    return {p.stem: p for p in tmp_path.glob("*.iface")}


def _comp(path: Path) -> Compilation:
    return Workspace().compile_path(str(path))


def test_graph_of_the_bundled_example_exits_0() -> None:
    done = run_main("graph", str(EXAMPLES / "robot_arm.iface"), cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert "error" not in done.stderr
    systems = [EXAMPLES / "living_room.iface"]  # a system file is graphed alone: its instances are the graph
    every = run_main("graph", *(str(p) for p in sorted(EXAMPLES.glob("*.iface")) if p not in systems), cwd=ROOT)
    assert every.returncode == 0, every.stderr
    for system in systems:
        alone = run_main("graph", str(system), cwd=ROOT)
        assert alone.returncode == 0 and "error" not in alone.stderr, alone.stderr


def test_a_type_is_one_type_whether_written_by_stem_or_namespace(tmp_path: Path) -> None:
    files = _system(tmp_path)
    g = build([_comp(files["robot_arm"]), _comp(files["gripper"])])
    data = graph_json(g, str)
    assert not [c for c in data["checks"] if "type-conflict" in c["code"]], data["checks"]
    assert {(lk["name"], lk["type"]) for lk in data["links"]} == {
        ("/arm/joint_state", "robot_arm_msgs/JointState"), ("/arm/joint_command", "robot_arm_msgs/JointCommand"),
        ("/gripper/move_to_pose", "robot_arm_msgs/MoveToPose")}
    done = run_main("graph", str(files["robot_arm"]), str(files["gripper"]), "--format", "json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    data = json.loads(done.stdout)
    assert data["components"][0]["at"] == {"file": "robot_arm.iface", "line": 2, "column": 11}
    link = data["links"][0]
    assert {"set", "type_conflict", "from_at", "to_at"} <= set(link)
    assert link["from_at"]["file"].endswith(".iface") and link["from_at"]["line"] >= 1


def test_graph_and_compat_system_agree_on_who_conflicts(tmp_path: Path) -> None:
    files = _system(tmp_path)
    old, new = _comp(files["arm_old"]), _comp(files["robot_arm"])
    for peer, conflicts in (("gripper", False), ("spy", True)):
        system = [_comp(files[peer])]
        graph = build([new, *system])
        in_graph = any(d.code == "graph-topic-type-conflict" for d in graph.checks)
        report = compare(old, new, system)
        in_compat = any(f.rule == "system-conflict" and "/arm/joint_state" in f.subject for f in report.findings)
        assert in_graph == in_compat == conflicts, peer
    spy = next(f for f in compare(old, new, [_comp(files["spy"])]).findings if f.rule == "system-conflict")
    assert "spy_msgs/JointState" in spy.message and spy.components == ["spy"]


def test_the_diagnostics_service_is_a_delta_port_in_the_graph(tmp_path: Path) -> None:
    for name in ("robot_arm.iface", "arm_common.iface"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    (tmp_path / "monitor.iface").write_text('component monitor\nnamespace ros2 monitor_msgs\n'
                                            'include "robot_arm.iface"\n'
                                            'calls robot_arm.ArmDiagnostics on "/arm/diagnostics"\n')
    g = build([_comp(tmp_path / "robot_arm.iface"), _comp(tmp_path / "monitor.iface")])
    (link,) = [lk for lk in graph_json(g, str)["links"] if lk["name"] == "/arm/diagnostics"]
    assert (link["kind"], link["set"], link["type"]) == ("service", "Δ", "robot_arm_msgs/ArmDiagnostics")
    assert not [d for d in g.checks if d.code == "graph-unprovided-service" and "/arm/diagnostics" in d.message]
    from iface.compat.graph import render_mermaid
    assert '"/arm/diagnostics: robot_arm_msgs/ArmDiagnostics (diagnostics)"' in render_mermaid(g)


def test_a_parameter_renamed_under_its_id_is_incompatible_and_named(tmp_path: Path) -> None:
    arm = (EXAMPLES / "robot_arm.iface").read_text()
    for name in ("robot_arm.iface", "arm_common.iface"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    (tmp_path / "renamed.iface").write_text(arm.replace("2: float max_speed", "2: float top_speed"))
    done = run_main("compat", "robot_arm.iface", "renamed.iface", cwd=tmp_path)
    assert done.returncode == 1
    assert "error[parameter-renamed]" in done.stdout
    assert "'max_speed' (id 2 of 'arm_params') is now named 'top_speed'" in done.stdout
    assert "verdict: incompatible" in done.stdout
