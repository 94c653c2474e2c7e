"""Issue 16 in the editor: Δ and flat diagnostics bodies in hover; ROS habits and package metadata quick fixes."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from .harness import Client
from .test_editing import apply, fixes
from .test_hover import hover

pytestmark = pytest.mark.asyncio(loop_scope="session")
#: complete package metadata: another test may have configured the ros2 target for the session
META = '(license = "MIT", maintainer = "Habit Team", maintainer_email = "habits@example.com")'

MONITORED = """component monitored
namespace ros2 monitored

/** Health of the component. */
service Health {
    request { string cmd }
    response { string status }
} (diagnostics)

service diagnostics {
    string result,
    i32 r,
    string cmd
}

message Beat { u32 seq }
publishes Beat on "/beat"
provides Health on "/monitored/health"
"""


async def test_hover_says_delta_not_s_and_how_a_flat_diagnostics_body_reads(client: Client) -> None:
    uri = client.open("monitored.iface", MONITORED)
    await client.wait_diagnostics(uri, 1)
    health = await hover(client, uri, "service Health", 8)
    assert "Δ (diagnostics and control, served as `/monitored/health`; not in S): guarantee" in health
    assert "S (" not in health
    flat = await hover(client, uri, "service diagnostics", 8)
    assert "Read as a diagnostics service, last field first: request (what the caller sends): cmd; " \
           "response (what it gets back): result, r" in flat
    assert "served as `diagnostics`" in flat
    client.close(uri)


def _edited(client: Client, uri: str, action: lsp.CodeAction) -> str:
    assert action.edit is not None and action.edit.changes is not None
    return apply(client.texts[uri], action.edit.changes[uri])


async def test_a_ros_constant_written_as_a_field_is_rewritten_as_a_constant(client: Client) -> None:
    text = f'component habits {META}\n' + 'namespace ros2 habits\n\nmessage Status {\n    uint8 LEVEL=1\n    uint8 level\n}\n' \
           'publishes Status on "/status"\n'
    uri = client.open("habits.iface", text)
    diag, actions = await fixes(client, uri, "ros-constant-as-field")
    assert "`const u8 LEVEL = 1`" in diag.message and diag.severity == lsp.DiagnosticSeverity.Warning
    assert actions[0].title == "Make it a constant: `const u8 LEVEL = 1`"
    fixed = _edited(client, uri, actions[0])
    assert "message Status {\n    const u8 LEVEL = 1\n    uint8 level\n}" in fixed
    client.replace(uri, fixed)
    after = await client.wait_diagnostics(uri, client.versions[uri])
    assert not [d for d in after if d.severity in (lsp.DiagnosticSeverity.Error, lsp.DiagnosticSeverity.Warning)]
    client.close(uri)


async def test_a_ros_package_path_points_to_the_qualified_spelling_with_a_fix(client: Client) -> None:
    text = f'component camera {META}\n' + 'namespace ros2 camera\n\nmessage Frame {\n    std_msgs/Header header\n    u32 seq\n}\n' \
           'publishes Frame on "/frame"\n'
    uri = client.open("camera.iface", text)
    diag, actions = await fixes(client, uri, "syntax-error")
    assert "'std_msgs/Header' is how ROS 2 writes a type of another package" in diag.message
    assert '`std_msgs.Header`, with `include "std_msgs.iface"`' in diag.message
    titles = [a.title for a in actions]
    # no std_msgs.iface in the workspace: `external` first, `include` offered too
    assert titles == ["Write 'std_msgs.Header' and add `external std_msgs`",
                      "Write 'std_msgs.Header' and add `include \"std_msgs.iface\"`"]
    fixed = _edited(client, uri, actions[0])
    assert fixed.startswith(f"component camera {META}\nnamespace ros2 camera\nexternal std_msgs\n")
    assert "    std_msgs.Header header\n" in fixed
    client.replace(uri, fixed)
    after = await client.wait_diagnostics(uri, client.versions[uri])
    assert not [d for d in after if d.severity == lsp.DiagnosticSeverity.Error]
    client.close(uri)


async def test_the_include_is_preferred_when_the_package_file_is_there(client: Client) -> None:
    (client.root / "nav_msgs.iface").write_text("component nav_msgs\nnamespace ros2 nav_msgs\nmessage Path { u32 n }\n")
    try:
        text = f'component planner2 {META}\n' + '\nmessage Plan {\n    nav_msgs/Path path\n}\npublishes Plan on "/plan"\n'
        uri = client.open("planner2.iface", text)
        _, actions = await fixes(client, uri, "syntax-error")
        assert actions[0].title == "Write 'nav_msgs.Path' and add `include \"nav_msgs.iface\"`"
        fixed = _edited(client, uri, actions[0])
        assert fixed.startswith(f'component planner2 {META}\ninclude "nav_msgs.iface"\n')
        client.replace(uri, fixed)
        after = await client.wait_diagnostics(uri, client.versions[uri])
        assert not [d for d in after if d.severity == lsp.DiagnosticSeverity.Error], after
        client.close(uri)
    finally:
        (client.root / "nav_msgs.iface").unlink()


async def test_package_metadata_warning_and_its_fix_with_the_ros2_target(client: Client) -> None:
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(settings={"iface": {"targets": ["ros2"]}}))
    try:
        text = 'component lidar version "1.0"\nnamespace ros2 lidar\n\nmessage Scan { u32 n }\npublishes Scan on "/scan"\n'
        uri = client.open("lidar.iface", text)
        diag, actions = await fixes(client, uri, "ros2-package-metadata-missing")
        assert diag.severity == lsp.DiagnosticSeverity.Warning and diag.range.start.line == 0
        assert "license TODO and maintainer 'unknown'" in diag.message
        assert actions and actions[0].title.startswith('Add license = "Apache-2.0", maintainer = "')
        fixed = _edited(client, uri, actions[0])
        assert fixed.startswith('component lidar version "1.0" (license = "Apache-2.0", maintainer = "')
        assert "maintainer_email = " in fixed.split("\n", 1)[0]
        client.replace(uri, fixed)
        after = await client.wait_diagnostics(uri, client.versions[uri])
        assert not [d for d in after if d.code == "ros2-package-metadata-missing"]
        client.close(uri)
        # a file without a component line gets one
        bare = client.open("bare.iface", 'namespace ros2 bare\nmessage M { u8 a }\npublishes M on "/m"\n')
        _, more = await fixes(client, bare, "ros2-package-metadata-missing")
        assert _edited(client, bare, more[0]).startswith('component bare (license = "Apache-2.0", maintainer = "')
        client.close(bare)
    finally:
        client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(settings={"iface": {"targets": []}}))
