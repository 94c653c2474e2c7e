"""Code lens, workspace/executeCommand (preview, generate, export JSON, compatibility, graph) and settings."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcException

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def run(client: Client, command: str, *arguments: object) -> object:
    return await client.workspace_execute_command_async(
        lsp.ExecuteCommandParams(command=command, arguments=list(arguments)))


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def arm(client: Client) -> str:
    await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query=""))  # waits for the workspace index
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, 1)
    return uri


async def test_code_lens_shows_who_uses_each_definition(client: Client, arm: str) -> None:
    lenses = await client.text_document_code_lens_async(lsp.CodeLensParams(client.doc(arm)))
    assert lenses
    by_line: dict[int, list[str]] = {}
    for lens in lenses:
        assert lens.command is not None
        by_line.setdefault(lens.range.start.line, []).append(lens.command.title)
    assert by_line[6] == ["published by arm · subscribed by planner", "Generate"]
    assert by_line[25] == ["called by planner · provided by arm", "Generate"]
    generate = next(x for x in lenses if x.command and x.command.title == "Generate")
    assert generate.command is not None and generate.command.command == "iface.generate"


async def test_preview_returns_files_without_writing(client: Client, arm: str) -> None:
    result = await run(client, "iface.preview", arm, "ros2")
    assert isinstance(result, dict) and result["target"] == "ros2" and not result["errors"]
    paths = [f["path"] for f in result["files"]]
    assert any(p.endswith("Pose.msg") for p in paths)
    assert not (client.root / "generated").exists() or not any((client.root / "generated").rglob("Pose.msg"))


async def test_generate_writes_into_the_configured_folder(client: Client, arm: str) -> None:
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"iface": {"output": {"folder": "out"}, "targets": ["ros2"], "includePaths": [],
                            "compat": {"baseline": ""}}}))
    result = await run(client, "iface.generate", {"uri": arm})
    assert isinstance(result, dict) and result["target"] == "ros2" and not result["errors"]
    files = result["written"] + result["unchanged"]  # the second profile finds the first one's files
    folder = Path(result["folder"])
    assert folder == client.root / "out" / "ros2" and files
    assert all((folder / p).is_file() for p in files)


async def test_export_json(client: Client, arm: str) -> None:
    result = await run(client, "iface.exportJson", arm)
    assert isinstance(result, dict) and not result["errors"]
    written = Path(result["files"][0]["path"])
    assert written.is_file() and json.loads(written.read_text())["name"] == "arm"


async def test_compat_against_a_baseline_file(client: Client, arm: str) -> None:
    old = client.root / "arm_old.iface"
    old.write_text((client.root / "arm.iface").read_text().replace("    bool reached\n", ""))
    result = await run(client, "iface.compat", arm, str(old))
    assert isinstance(result, dict) and "verdict:" in result["text"]
    old.unlink()


async def test_graph_of_the_workspace(client: Client, arm: str) -> None:
    result = await run(client, "iface.graph", "mermaid")
    assert isinstance(result, dict) and result["components"] >= 2
    assert "arm" in result["text"] and "planner" in result["text"]


async def test_graph_data_for_a_picture(client: Client, arm: str) -> None:
    result = await run(client, "iface.graph", {"format": "json"})
    assert isinstance(result, dict) and json.loads(result["text"])["schema"] == "iface-graph/1"
    data = result["graph"]
    by_name = {c["name"]: c for c in data["components"]}
    assert {"arm", "planner"} <= set(by_name)
    where = by_name["arm"]["at"]
    assert Path(where["file"]).is_absolute() and Path(where["file"]).name == "arm.iface"
    assert "component arm" in Path(where["file"]).read_text().splitlines()[where["line"] - 1]
    link = next(lk for lk in data["links"] if lk["from"] == "arm" and lk["to"] == "planner")
    assert Path(link["definition"]["file"]).is_absolute()
    svg = await run(client, "iface.graph", "svg")
    assert isinstance(svg, dict) and svg["text"].startswith("<?xml") and "planner" in svg["text"]


async def test_bad_arguments_get_a_clear_error_and_the_server_goes_on(client: Client, arm: str) -> None:
    with pytest.raises(JsonRpcException, match="unknown target 'nope'"):
        await run(client, "iface.preview", arm, "nope")
    with pytest.raises(JsonRpcException, match="uri must be a non-empty string"):
        await run(client, "iface.generate", 42)
    hover = await client.text_document_hover_async(lsp.HoverParams(client.doc(arm), client.pos(arm, "Pose", 1)))
    assert hover is not None


async def test_a_configured_baseline_adds_compatibility_diagnostics_with_fixes(client: Client, arm: str) -> None:
    old = client.root / "arm_baseline.iface"
    old.write_text((client.root / "arm.iface").read_text())
    uri = client.open("arm_copy.iface", old.read_text())
    await client.wait_diagnostics(uri, 1)
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"iface": {"compat": {"baseline": str(old)}}}))
    changed = client.texts[uri].replace("    u32 retries = 3\n", "    u32 retries = 3\n    u32 extra\n", 1)
    version = client.replace(uri, changed)
    diags = await client.wait_diagnostics(uri, version)
    compat = [d for d in diags if str(d.code).startswith("compat-")]
    assert compat and all(d.related_information for d in compat)
    added = next(d for d in compat if d.code == "compat-parameter-added-required")
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=added.range, context=lsp.CodeActionContext(diagnostics=[added])))
    fix = next(a for a in actions or [] if isinstance(a, lsp.CodeAction) and a.title.startswith("Add a default"))
    assert fix.edit is not None and fix.edit.changes is not None
    assert [e.new_text for e in fix.edit.changes[uri]] == [" = 0"]
    client.workspace_did_change_configuration(lsp.DidChangeConfigurationParams(
        settings={"iface": {"compat": {"baseline": ""}}}))
    version = client.replace(uri, client.texts[uri])
    assert not [d for d in await client.wait_diagnostics(uri, version) if str(d.code).startswith("compat-")]
    client.close(uri)
    old.unlink()
