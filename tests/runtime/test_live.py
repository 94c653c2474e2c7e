"""Live truth on loopback: import running nodes as .iface, verify a running system against its files.

One scenario per module: the hand-written rclpy nodes of ``data/live/nodes.py`` (/live/talker,
/live/listener, the lifecycle node /live/lifer) and the generated component live_probe (built by the
session's ``ros_workspace``, activated) run in one ROS domain of their own; the real CLI imports them,
verifies planted faults and a conforming system, and the language server publishes verify's findings.
Every wait is bounded; every process started here is stopped by its own handle.
"""

from __future__ import annotations

import asyncio
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from ..ros_harness.ros import DATA, at_once, environment
from .conftest import Workspace

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

LIVE = DATA / "live"
NODES = ["/live/talker", "/live/listener", "/live/lifer", "/live_probe"]
STEP = 180  # seconds a CLI step may take on a loaded machine (a bound, not a measure)
#: The declared files of the planted faults (written by the tests: no more files for the sweeps over tests/).
FAULTS = {
    "talker.iface": """\
/** /live/talker as declared, with two planted faults: count's range and no /extra. */
component talker (ros2.node = "/live/talker")

external diagnostic_msgs
external robot_arm_msgs
external std_msgs

configuration parameters {
    /** Loop rate. */
    float64 rate = 2.5 (unit = "Hz", range = "0.5..10"),
    // fault: the running value is 50
    i64 count = 5 (range = "0..10"),
    string frame = "base" (read_only),
    float64[] gains = [1.0, 2.0],
    bool verbose = false
}

publishes std_msgs.String on "/chatter" (qos.reliability = "best_effort", qos.durability = "transient_local")
subscribes std_msgs.Int32 on "/numbers"
provides diagnostic_msgs.AddDiagnostics on "~/add"
calls robot_arm_msgs.MoveToPose on "/arm/move_to_pose"
provides robot_arm_msgs.FollowTrajectory on "/follow" (action)
""",
    "listener.iface": """\
/** /live/listener as declared: /numbers with the wrong type. */
component listener (ros2.node = "/live/listener")

external std_msgs

configuration parameters {
    i64 threshold = 7
}

subscribes std_msgs.String on "/chatter"
// fault: the running subscription is std_msgs/msg/Int32
subscribes std_msgs.Float64 on "/numbers"
""",
    "ghost.iface": """\
/** A node that is not running. */
component ghost (ros2.node = "/live/ghost")

external std_msgs

publishes std_msgs.String on "/ghost"
""",
}


def _start(cmd: list[str], env: dict[str, str], log: Path) -> subprocess.Popen[bytes]:
    out = open(log, "wb")  # noqa: SIM115 - closed with the process
    return subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True)


def _stop(procs: list[subprocess.Popen[bytes]]) -> None:
    """SIGTERM to each (rclpy's handler ends its spin), then wait; SIGKILL what is still up after 15 s."""
    for proc in procs:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGTERM)
    for proc in procs:
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=15)


def _wait_line(log: Path, needle: str, proc: subprocess.Popen[bytes], timeout: float) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if needle in log.read_text(errors="replace"):
            return
        if proc.poll() is not None:
            break
        time.sleep(0.1)
    raise AssertionError(f"'{needle}' never came from {proc.args}:\n{log.read_text(errors='replace')[-3000:]}")


@pytest.fixture(scope="module")
def live(ros_workspace: Workspace, tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Any]]:
    """The running system and the environment to reach it (its own domain, loopback only)."""
    root = tmp_path_factory.mktemp("live")
    env = environment(ros_workspace.venv, ros_workspace.path, root / "ros-log")
    procs = [_start([sys.executable, str(LIVE / "nodes.py")], env, root / "nodes.log"),
             _start([sys.executable, "-m", "live_probe", "--activate"], env, root / "probe.log")]
    try:
        _wait_line(root / "nodes.log", "ready", procs[0], STEP)
        yield {"env": env, "root": root}
    finally:
        _stop(procs)


def iface(live: dict[str, Any], *args: str) -> subprocess.CompletedProcess[str]:
    """The real CLI in the system's environment."""
    return subprocess.run([sys.executable, "-m", "iface", *args], env=live["env"], capture_output=True, text=True,
                          timeout=STEP, check=False)


@pytest.fixture(scope="module")
def imported(live: dict[str, Any]) -> Path:
    """``import --from node --all`` (the named nodes waited for, every other one taken) ``--system room``."""
    out = live["root"] / "imported"
    done = iface(live, "import", "--from", "node", "--all", *NODES, "--system", "room", "--out", str(out),
                 "--timeout", "60", "-q")
    assert done.returncode == 0, done.stderr
    return out


def test_each_imported_file_names_exactly_what_its_node_has(imported: Path) -> None:
    from iface.semantics.compile import Workspace

    written = sorted(p.name for p in imported.iterdir())
    assert written == ["lifer.iface", "listener.iface", "live_probe.iface", "room.iface", "talker.iface"]
    for name in ("talker", "listener", "lifer", "room"):
        expected = (LIVE / "expected" / f"{name}.iface.expected").read_text(encoding="utf-8")
        assert (imported / f"{name}.iface").read_text(encoding="utf-8") == expected, name
    from iface.commands.common import gather

    for path in sorted(imported.iterdir()):  # as `check` reads them
        found = gather([Workspace().compile_path(str(path))])
        if path.name != "room.iface":
            assert [d.format() for d in found] == [], path.name  # not a finding, not a hint
        else:  # the system file tells the running system's own conflict, the QoS pair of /chatter
            errors = [d for d in found if d.severity.label == "error"]
            assert [(d.code, "'/chatter'" in d.message) for d in errors] == [("graph-qos-mismatch", True)]


def test_a_generated_component_answering_describe_is_imported_fully_equivalent(imported: Path) -> None:
    from iface.compat import compare
    from iface.semantics.compile import Workspace

    report = compare(Workspace().compile_path(str(LIVE / "live_probe.iface")),
                     Workspace().compile_path(str(imported / "live_probe.iface")))
    assert report.verdict == "equivalent", [f.message for f in report.findings]


def test_a_generated_component_imported_without_describe_is_equivalent_on_m_n_s_a_p(live: dict[str, Any]) -> None:
    from iface.compat import compare
    from iface.compat.rules import RULES
    from iface.semantics.compile import Workspace

    out = live["root"] / "without-describe"
    done = iface(live, "import", "--from", "node", "/live_probe", "--no-describe", "--out", str(out),
                 "--timeout", "60", "-q")
    assert done.returncode == 0, done.stderr
    text = (out / "live_probe.iface").read_text(encoding="utf-8")
    assert "external live_probe_msgs" in text and "message " not in text  # read off the graph: no copied types
    report = compare(Workspace().compile_path(str(LIVE / "live_probe.iface")),
                     Workspace().compile_path(str(out / "live_probe.iface")))
    areas = {f.rule: RULES[f.rule].area for f in report.findings}
    in_sets = [f.message for f in report.findings if set(areas[f.rule].split("/")) & set("MNSAPΔ")]
    assert in_sets == []
    # what differs: the types are external in the imported file (no copied messages), nothing else
    assert set(areas.values()) <= {"types", "headers"}, areas


def test_planted_faults_are_each_found_once_with_their_code(imported: Path, live: dict[str, Any]) -> None:
    """Five faults in three files; lifer and live_probe, as imported, conform (no finding of theirs), and so
    does live_probe declared by its own source file (its Describe hash is that file's)."""
    folder = live["root"] / "faults"
    folder.mkdir()
    for name, text in FAULTS.items():
        (folder / name).write_text(text, encoding="utf-8")
    files = [str(folder / f) for f in ("talker.iface", "listener.iface", "ghost.iface")]
    done = iface(live, "verify", *files, str(imported / "lifer.iface"), str(imported / "live_probe.iface"),
                 str(LIVE / "live_probe.iface"), "--format", "json", "--timeout", "60")
    assert done.returncode == 1, done.stderr
    report = json.loads(done.stdout)
    codes = sorted(f["code"] for f in report["findings"])
    assert codes == ["live-endpoint-undeclared", "live-node-missing", "live-param-out-of-range",
                     "live-qos-incompatible", "live-type-mismatch", "live-type-mismatch"], json.dumps(report, indent=1)
    by = {f["code"]: f for f in report["findings"] if f["node"] != "/live/talker" or f["code"] != "live-type-mismatch"}
    assert by["live-node-missing"]["node"] == "/live/ghost" and by["live-node-missing"]["path"].endswith("ghost.iface")
    assert "'/extra'" in by["live-endpoint-undeclared"]["message"]
    assert by["live-endpoint-undeclared"]["severity"] == "warning"
    mismatch = by["live-type-mismatch"]
    assert "std_msgs/Float64" in mismatch["message"] and "std_msgs/Int32" in mismatch["message"]
    assert mismatch["path"].endswith("listener.iface") and mismatch["line"] == 12
    # the same line declares what /live/talker subscribes with another type: issue 33's other node
    other = next(f for f in report["findings"] if f["code"] == "live-type-mismatch" and f["node"] == "/live/talker")
    assert other["message"] == "'/numbers': declared std_msgs/Float64, /live/talker subscribes std_msgs/Int32"
    assert other["path"].endswith("listener.iface") and other["line"] == 12
    assert by["live-param-out-of-range"]["line"] == 12 and "50" in by["live-param-out-of-range"]["message"]
    qos = by["live-qos-incompatible"]
    assert qos["node"] == "/live/talker -> /live/listener" and "reliability" in qos["message"]
    assert qos["path"].endswith("listener.iface") and qos["line"] == 10


def test_the_editor_command_publishes_verify_findings_as_diagnostics(live: dict[str, Any]) -> None:
    from tests.lsp.harness import SERVER, make_client

    folder = live["root"] / "editor"
    folder.mkdir()
    listener = folder / "listener.iface"
    listener.write_text(FAULTS["listener.iface"], encoding="utf-8")

    async def scenario() -> list[Any]:
        from lsprotocol import types as lsp

        client = make_client()
        await client.start_io(*SERVER, env=live["env"])
        try:
            await client.initialize_session(lsp.InitializeParams(
                capabilities=lsp.ClientCapabilities(), root_uri=folder.as_uri(),
                workspace_folders=[lsp.WorkspaceFolder(uri=folder.as_uri(), name="editor")],
                initialization_options={"diagnosticsDelay": 0}))
            uri = listener.as_uri()
            answer = await asyncio.wait_for(client.workspace_execute_command_async(lsp.ExecuteCommandParams(
                command="iface.verify", arguments=[{"uris": [uri], "timeout": 60}])), STEP)
            diags = await client.wait_diagnostics(uri, until=lambda ds: any(d.source == "iface verify" for d in ds))
            await client.shutdown_session()
            return [answer, diags]
        finally:
            await client.stop()

    answer, diags = asyncio.run(asyncio.wait_for(scenario(), STEP))
    codes = sorted(d.code for d in diags if d.source == "iface verify")
    assert codes == ["live-qos-incompatible", "live-type-mismatch", "live-type-mismatch"], diags
    mismatches = [d for d in diags if d.code == "live-type-mismatch"]
    assert [d.range.start.line for d in mismatches] == [11, 11]  # 0-based: the `subscribes std_msgs.Float64` line
    assert sorted(f["code"] for f in answer["findings"]) == codes


def test_a_node_not_declared_with_another_type_on_declared_names_is_found(live: dict[str, Any]) -> None:
    """Issue 33: /intruder (data/live/intruder.py, not declared) publishes std_msgs/Int32 on /chatter, serves
    another type on /arm/move_to_pose and calls /follow with another action: each is a live-type-mismatch at
    talker.iface's line, naming /intruder and both types, in every format. (Last in the module: the intruder
    runs for this test only.)"""
    folder = live["root"] / "intruder"
    folder.mkdir()
    talker = folder / "talker.iface"
    talker.write_text(FAULTS["talker.iface"], encoding="utf-8")
    lines = FAULTS["talker.iface"].splitlines()
    proc = _start([sys.executable, str(LIVE / "intruder.py")], live["env"], live["root"] / "intruder.log")
    try:
        _wait_line(live["root"] / "intruder.log", "ready", proc, STEP)

        def verify(*fmt: str) -> Any:
            """verify in a fresh process, again (3 times at most) while it has not discovered all of /intruder:
            a process discovers another participant within Fast DDS's announcement period (3 s), which a loaded
            machine can exceed; what it reports of what it saw is what this test checks."""
            for _ in range(3):
                done = iface(live, "verify", str(talker), *fmt, "--timeout", "60")
                if all(f"/intruder {what} " in done.stdout for what in ("publishes", "serves", "calls")):
                    break
            return done

        # each run waits for the graph to settle: the three formats at once
        done, text, sarif = at_once(lambda: verify("--format", "json"), verify, lambda: verify("--format", "sarif"))
        assert done.returncode == 1, done.stderr
        report = json.loads(done.stdout)
        found = sorted((f["line"], f["message"]) for f in report["findings"] if f["node"] == "/intruder")
        assert found == sorted([
            (lines.index('publishes std_msgs.String on "/chatter" (qos.reliability = "best_effort", '
                         'qos.durability = "transient_local")') + 1,
             "'/chatter': declared std_msgs/String, /intruder publishes std_msgs/Int32"),
            (lines.index('calls robot_arm_msgs.MoveToPose on "/arm/move_to_pose"') + 1,
             "'/arm/move_to_pose': declared robot_arm_msgs/MoveToPose, /intruder serves diagnostic_msgs/SelfTest"),
            (lines.index('provides robot_arm_msgs.FollowTrajectory on "/follow" (action)') + 1,
             "'/follow': declared robot_arm_msgs/FollowTrajectory, /intruder calls live_probe_msgs/Seek"),
        ]), json.dumps(report, indent=1) + (live["root"] / "intruder.log").read_text(errors="replace")[-2000:]
        assert all(f["code"] == "live-type-mismatch" and f["path"].endswith("talker.iface")
                   for f in report["findings"] if f["node"] == "/intruder")
        assert text.returncode == 1, text.stderr
        assert any(line.endswith("error[live-type-mismatch]: '/chatter': declared std_msgs/String, /intruder "
                                 "publishes std_msgs/Int32 [/intruder]") for line in text.stdout.splitlines()), \
            text.stdout
        results = json.loads(sarif.stdout)["runs"][0]["results"]
        assert sum(r["message"]["text"].endswith("[/intruder]") for r in results) == 3, sarif.stdout
    finally:
        _stop([proc])
