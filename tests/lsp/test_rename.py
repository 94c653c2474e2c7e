"""Rename with prepareRename, across included files, refusing bad or clashing names."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcException

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def arm(client: Client) -> str:
    client.open("planner.iface")
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, 1)
    return uri


async def test_prepare_rename(client: Client, arm: str) -> None:
    ok = await client.text_document_prepare_rename_async(
        lsp.PrepareRenameParams(client.doc(arm), client.pos(arm, "ToolPose", 2)))
    assert isinstance(ok, lsp.PrepareRenamePlaceholder) and ok.placeholder == "ToolPose"
    qualified = await client.text_document_prepare_rename_async(
        lsp.PrepareRenameParams(client.doc(arm), client.pos(arm, "common.Vec3", 8)))
    assert isinstance(qualified, lsp.PrepareRenamePlaceholder) and qualified.placeholder == "Vec3"
    builtin = await client.text_document_prepare_rename_async(
        lsp.PrepareRenameParams(client.doc(arm), client.pos(arm, "float64 yaw", 1)))
    assert builtin is None


async def test_rename_across_files(client: Client, arm: str) -> None:
    edit = await client.text_document_rename_async(
        lsp.RenameParams(client.doc(arm), client.pos(arm, "message Pose", 9), "Pose2"))
    assert edit is not None and edit.changes is not None
    files = {uri.rsplit("/", 1)[-1]: sorted(e.range.start.line for e in edits) for uri, edits in edit.changes.items()}
    assert files["arm.iface"] == [6, 13, 27, 36, 46]
    assert files["planner.iface"] == [6, 9]
    assert all(e.new_text == "Pose2" for edits in edit.changes.values() for e in edits)


async def test_rename_a_field_only_touches_it(client: Client, arm: str) -> None:
    edit = await client.text_document_rename_async(
        lsp.RenameParams(client.doc(arm), client.pos(arm, "yaw"), "heading"))
    assert edit is not None and edit.changes is not None
    assert [len(v) for v in edit.changes.values()] == [1]


@pytest.mark.parametrize("name, reason", [("2bad", "not a name"), ("message", "keyword"),
                                          ("Command", "already defined")])
async def test_rename_refuses(client: Client, arm: str, name: str, reason: str) -> None:
    with pytest.raises(JsonRpcException, match=reason):
        await client.text_document_rename_async(
            lsp.RenameParams(client.doc(arm), client.pos(arm, "message Pose", 9), name))


async def test_prepare_rename_of_an_enum_value_named_in_a_value(client: Client) -> None:
    """``Mode.RUN`` in a default and ``Mode.IDLE`` in a constant: the range is the value's own name (it
    was an error: the span of the value, anchored in its chunk, could not be copied)."""
    text = ("enum Mode {\n    IDLE = 0,\n    RUN = 1\n}\nstruct S {\n    1: Mode m = Mode.RUN\n}\n"
            "const Mode START = Mode.IDLE\n")
    uri = client.open("enum_values.iface", text)
    await client.wait_diagnostics(uri, 1)
    for needle, name in (("Mode.RUN", "RUN"), ("Mode.IDLE", "IDLE")):
        at = client.pos(uri, needle, len("Mode.") + 1)
        ok = await client.text_document_prepare_rename_async(lsp.PrepareRenameParams(client.doc(uri), at))
        assert isinstance(ok, lsp.PrepareRenamePlaceholder) and ok.placeholder == name, ok
        assert ok.range.start.character == at.character - 1 and ok.range.end.character == at.character - 1 + len(name)
    client.close(uri)
