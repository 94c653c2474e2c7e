"""The four verdicts and exit codes through the real CLI, with and without --system."""

from __future__ import annotations

from pathlib import Path

import pytest
from compat_support import DATA, compile_text, run_main

V = "verdicts/"


@pytest.mark.parametrize(("new", "verdict", "code"), [
    ("arm_v1_relaid.iface", "equivalent", 0),
    ("arm_v2.iface", "replaceable", 0),
    ("arm_v3.iface", "replaceable-if-unused", 1),
    ("arm_v4.iface", "incompatible", 1),
])
def test_verdicts(new: str, verdict: str, code: int) -> None:
    done = run_main("compat", V + "arm_v1.iface", V + new)
    assert done.returncode == code, done.stderr
    assert done.stdout.splitlines()[-1].startswith(f"verdict: {verdict} (")


def test_system_shows_the_removed_elements_are_unused() -> None:
    done = run_main("compat", V + "arm_v1.iface", V + "arm_v3.iface", "--system", V + "planner.iface")
    assert done.returncode == 0
    assert "verdict: replaceable-if-unused (3 breaking changes, none used by the system" in done.stdout


def test_system_names_the_components_that_break() -> None:
    done = run_main("compat", V + "arm_v1.iface", V + "arm_v3.iface", "--system", V + "planner.iface",
                   V + "monitor.iface")
    assert done.returncode == 1
    lines = done.stdout.splitlines()
    removed = next(line for line in lines if "[published-removed]" in line)
    assert removed.startswith(V + "arm_v3.iface:") and "affects: monitor" in removed
    assert f"(old: {V}arm_v1.iface:41:1)" in removed
    # the planner reads Pose without 'frame': removing it does not break the planner
    frame = next(line for line in lines if "Pose.frame" in line)
    assert "affects" not in frame
    assert lines[-1].startswith("verdict: incompatible")


def test_system_including_old_itself_is_fine() -> None:
    done = run_main("compat", V + "arm_v1.iface", V + "arm_v3.iface", "--system", V + "arm_v1.iface",
                   V + "planner.iface")
    assert done.returncode == 0


def test_subscribing_more_needs_a_publisher(tmp_path: Path) -> None:
    planner = (DATA / "verdicts" / "planner.iface").read_text()
    extra = planner.replace("calls Plan", 'message Status { u8 level; string text; const u8 OK = 0 }\n'
                            'subscribes Status on "/arm/status"\ncalls Plan')
    (tmp_path / "planner2.iface").write_text(extra)
    old, new = str(DATA / "verdicts" / "planner.iface"), str(tmp_path / "planner2.iface")
    alone = run_main("compat", old, new)
    assert alone.returncode == 1 and "replaceable-if-unused" in alone.stdout.splitlines()[-1]
    served = run_main("compat", old, new, "--system", str(DATA / "verdicts" / "arm_v1.iface"))
    assert served.returncode == 0 and "provided by: arm" in served.stdout
    unserved = run_main("compat", old, new, "--system", str(DATA / "verdicts" / "monitor.iface"))
    assert unserved.returncode == 1 and "no component of the system provides it" in unserved.stdout


def test_system_conflict(tmp_path: Path) -> None:
    logger = (DATA / "system" / "logger.iface").read_text()
    (tmp_path / "logger2.iface").write_text(
        logger.replace('subscribes Boxes on "/detections"', 'subscribes Boxes on "/detections"\n'
                       'message Tracks { u32[] ids }\npublishes Tracks on "/depth"'))
    done = run_main("compat", str(DATA / "system" / "logger.iface"), str(tmp_path / "logger2.iface"),
                   "--system", str(DATA / "system" / "detector.iface"), "--format", "json")
    import json
    report = json.loads(done.stdout)
    conflict = [f for f in report["findings"] if f["rule"] == "system-conflict"]
    assert conflict and conflict[0]["components"] == ["detector"]
    assert report["verdict"] == "incompatible" and done.returncode == 1


def test_warnings_are_lines_with_warning_and_keep_the_exit_code() -> None:
    done = run_main("compat", "thrift/default-changed/old.thrift", "thrift/default-changed/new.thrift")
    assert done.returncode == 0
    warnings = [line for line in done.stdout.splitlines() if "warning" in line]
    assert len(warnings) == 1 and "warning[default-changed]" in warnings[0]
    assert done.stdout.splitlines()[-1].startswith("verdict: replaceable")


def test_state_handover() -> None:
    done = run_main("compat", V + "arm_v1.iface", V + "arm_v4.iface")
    assert "state hand-over:\n  carried over: mode (Mode)\n  new, needs an initial value: last_error (string)\n" \
           "  lost: moves (i32)\n" in done.stdout
    widened = run_main("compat", V + "arm_v1.iface", V + "arm_v2.iface")
    assert "  carried over: moves (i32 → i64)\n  new, starts at 0: faults (u32)\n" in widened.stdout


@pytest.mark.parametrize("args", [
    ("compat", "verdicts/arm_v1.iface", "verdicts/missing.iface"),
    ("compat", "verdicts/arm_v1.iface", "rules/expected.json"),
    ("compat", "verdicts/arm_v1.iface", "broken.iface"),
])
def test_tool_errors_exit_2(args: tuple[str, ...], tmp_path: Path) -> None:
    if "broken.iface" in args:
        (tmp_path / "broken.iface").write_text("message {\n")
        args = (args[0], str(DATA / args[1]), str(tmp_path / "broken.iface"))
    done = run_main(*args)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr and done.stderr.strip()


def test_compare_api_on_text(tmp_path: Path) -> None:
    from iface.compat import compare
    old = compile_text(tmp_path, "a.iface", 'message M { 1: required i32 x }\npublishes M on "/m"\n')
    new = compile_text(tmp_path, "b.iface", 'message M { 1: required i32 x, 2: optional i32 y }\n'
                                             'publishes M on "/m"\n')
    report = compare(old, new)
    assert report.verdict == "replaceable" and report.exit_code == 0
    assert [f.rule for f in report.findings] == ["field-added"]
