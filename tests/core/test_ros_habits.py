"""ROS habits get a hint: ``uint8 LEVEL=1`` is a field here, ``std_msgs/Header`` is spelled ``std_msgs.Header``.

The editor's quick fixes for both are tested over the language server (tests/lsp/test_ros_habits.py).
"""

from __future__ import annotations

from iface.semantics.compile import Workspace

from ..conftest import run_main

HABITS = """component cam
namespace ros2 cam

message Image {
    std_msgs/Header header
    u32 seq
}

message Status {
    uint8 LEVEL=1
    float64 MAX_RANGE = 3.5
    uint8 level
}
publishes Image on "/image"
publishes Status on "/status"
"""


def test_a_package_slash_type_says_how_iface_writes_it(tmp_path) -> None:  # type: ignore[no-untyped-def]
    comp = Workspace().compile_text(str(tmp_path / "cam.iface"), HABITS)
    (d,) = [d for d in comp.diagnostics if d.code == "syntax-error"]
    assert d.location()[:2] == (5, 5) and comp.source.text[d.span.start:d.span.end] == "std_msgs/Header"
    assert "`std_msgs.Header`, with `include \"std_msgs.iface\"`" in d.message and "`external std_msgs`" in d.message
    assert d.data == {"ros_type": "std_msgs/Header", "package": "std_msgs", "replacement": "std_msgs.Header"}


def test_a_ros_constant_written_as_a_field_is_told_it_is_a_field(tmp_path) -> None:  # type: ignore[no-untyped-def]
    comp = Workspace().compile_text(str(tmp_path / "cam.iface"), HABITS.replace("    std_msgs/Header header\n", ""))
    found = {d.data["name"]: d for d in comp.diagnostics if d.code == "ros-constant-as-field"}
    assert sorted(found) == ["LEVEL", "MAX_RANGE"]
    level = found["LEVEL"]
    assert level.severity.label == "warning"
    assert level.message == ("'LEVEL' is a field with the default 1, not a constant: ROS 2 writes a constant "
                             "`uint8 LEVEL=1`, .iface writes `const u8 LEVEL = 1`")
    assert found["MAX_RANGE"].data["replacement"] == "const float64 MAX_RANGE = 3.5"
    assert not [d for d in comp.diagnostics if d.code == "ros-naming"]  # the hint replaces the naming warning


def test_the_cli_shows_both_hints(tmp_path) -> None:  # type: ignore[no-untyped-def]
    (tmp_path / "cam.iface").write_text(HABITS)
    done = run_main("check", str(tmp_path / "cam.iface"))
    assert done.returncode == 1
    assert "error[syntax-error]: 'std_msgs/Header' is how ROS 2 writes a type of another package" in done.stdout
    assert done.stdout.splitlines()[-1].startswith("failed: 1 error")
