"""The editor side of the rclpy component target: the "Generate component package…" action and handler hover."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from lsprotocol import types as lsp

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


def _hover_text(hover: lsp.Hover | None) -> str:
    assert hover is not None and isinstance(hover.contents, lsp.MarkupContent)
    return hover.contents.value


async def test_generate_component_package_writes_the_node_and_keeps_the_user_module(client: Client) -> None:
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, client.versions[uri])
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=lsp.Range(start=lsp.Position(line=1, character=0),
                                                        end=lsp.Position(line=1, character=0)),
        context=lsp.CodeActionContext(diagnostics=[], only=[lsp.CodeActionKind.Source])))
    titles = {a.title: a for a in actions or [] if isinstance(a, lsp.CodeAction)}
    action = titles["Generate component package…"]
    assert action.command is not None and action.command.command == "iface.generate"
    assert list(action.command.arguments or []) == [uri, "rclpy"]

    out = Path(tempfile.mkdtemp(prefix="component-out-", dir=client.root))  # one per client profile
    first = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command="iface.generate", arguments=[uri, "rclpy", str(out)]))
    assert isinstance(first, dict) and not first["errors"], first
    folder = Path(first["folder"])
    user = folder / "arm_node" / "arm_node" / "node.py"
    assert "arm_node/arm_node/base.py" in first["written"] and "arm_node/arm_node/node.py" in first["written"]
    assert user.is_file() and (folder / "iface_msgs" / "srv" / "SaveState.srv").is_file()

    user.write_text(user.read_text() + "\n# the user's own code\n")
    again = await client.workspace_execute_command_async(lsp.ExecuteCommandParams(
        command="iface.generate", arguments=[uri, "rclpy", str(out)]))
    assert isinstance(again, dict) and not again["errors"], again
    assert again["kept"] == ["arm_node/arm_node/node.py"] and "arm_node/arm_node/base.py" in again["unchanged"]
    assert user.read_text().endswith("# the user's own code\n")
    client.close(uri)


async def test_no_component_package_action_without_a_component(client: Client) -> None:
    uri = client.open("types_only.iface", "namespace ros2 t\nstruct S { 1: i32 a }\n")
    await client.wait_diagnostics(uri, 1)
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=lsp.Range(start=lsp.Position(line=0, character=0),
                                                        end=lsp.Position(line=0, character=0)),
        context=lsp.CodeActionContext(diagnostics=[], only=[lsp.CodeActionKind.Source])))
    assert "Generate component package…" not in {a.title for a in actions or [] if isinstance(a, lsp.CodeAction)}
    client.close(uri)


@pytest.mark.parametrize(("needle", "expected"), [
    ('"/arm/command"', "`on_command(msg)` handles subscribes Command on /arm/command"),
    ('"/arm/plan"', "`handle_plan(request, response)` handles provides Plan on /arm/plan"),
    ('"/arm/move"', "`execute_move(goal_handle)` handles provides Move on /arm/move"),
    ('"/arm/pose"', "`publish_pose` for publishes Pose on /arm/pose"),
])
async def test_hover_on_a_wired_member_names_its_generated_handler(client: Client, needle: str,
                                                                   expected: str) -> None:
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, client.versions[uri])
    pos = client.pos(uri, needle)
    hover = await client.text_document_hover_async(lsp.HoverParams(
        text_document=client.doc(uri), position=lsp.Position(line=pos.line, character=pos.character + 2)))
    text = _hover_text(hover)
    assert "**In the generated node** (`Arm` in `arm_node/arm_node/node.py`, target rclpy)" in text
    assert expected in text, text
    client.close(uri)
