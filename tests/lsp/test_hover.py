"""Hover: definitions with docs, typedef chains and targets; fields; set membership."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def hover(client: Client, uri: str, needle: str, delta: int = 0, nth: int = 0) -> str:
    result = await client.text_document_hover_async(
        lsp.HoverParams(client.doc(uri), client.pos(uri, needle, delta, nth)))
    assert result is not None, needle
    assert isinstance(result.contents, lsp.MarkupContent)
    return result.contents.value


async def test_type_reference_shows_definition_doc_and_targets(client: Client) -> None:
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, 1)
    text = await hover(client, uri, "Vec3", 1)
    assert "**message** `Vec3`" in text and "A point in space." in text
    assert "message Vec3 {" in text
    assert "ROS 2: `common/msg/Vec3`" in text and "IDL: `common::msg::Vec3`" in text
    assert "PX4:" in text and "JSON Schema:" in text


async def test_definition_shows_its_set_and_contract_role(client: Client) -> None:
    uri = client.uri("arm.iface")
    pose = await hover(client, uri, "message Pose", 9)
    assert "N (published on `/arm/pose`): guarantee" in pose
    command = await hover(client, uri, "message Command", 9)
    assert "M (subscribed on `/arm/command`): assumption" in command
    plan = await hover(client, uri, "service Plan", 9)
    assert "S (provides `/arm/plan`): guarantee (provided)" in plan


async def test_typedef_chain_is_resolved(client: Client) -> None:
    uri = client.uri("arm.iface")
    text = await hover(client, uri, "ToolPose", 1)
    assert "Typedef chain: `ToolPose` → `Pose`" in text


async def test_field_shows_type_default_range_and_unit(client: Client) -> None:
    uri = client.uri("arm.iface")
    text = await hover(client, uri, "max_speed", 1)
    assert "**field** `max_speed`: `float64`" in text
    assert "default: `1.5`" in text and "range: 0..3" in text and "unit: `m/s`" in text
    assert "P (parameter): assumption" in text
    assert "ROS 2: `float64`" in text


async def test_base_type_and_nothing_on_blank(client: Client) -> None:
    uri = client.uri("arm.iface")
    text = await hover(client, uri, "float64 yaw", 2)
    assert "float64" in text and "double" in text  # IDL spells it double
    blank = await client.text_document_hover_async(lsp.HoverParams(client.doc(uri), lsp.Position(line=4, character=0)))
    assert blank is None


async def test_hover_over_wchar_says_how_each_target_writes_it(client: Client) -> None:
    uri = client.open("wide.iface", "namespace ros2 wide\nmessage Key {\n    wchar code\n}\n")
    await client.wait_diagnostics(uri, 1)
    text = await hover(client, uri, "wchar code", 1)
    assert text.startswith("**wchar**") and "OMG IDL: `wchar`" in text and "PX4 (uORB): —" in text


async def test_hover_over_a_typedef_cycle_answers(client: Client) -> None:
    """`typedef list<Loop> Loop` is an error; hovering its uses still answers (and ends)."""
    uri = client.open("loop.iface", 'typedef list<Loop> Loop\nmessage UsesLoop {\n    Loop field\n}\n'
                                    'publishes UsesLoop on "/loop"\n')
    diags = await client.wait_diagnostics(uri, 1)
    assert [d.code for d in diags if d.severity == lsp.DiagnosticSeverity.Error] == ["typedef-cycle"]
    text = await hover(client, uri, "Loop field", 1)
    assert "Loop" in text
    client.close(uri)
