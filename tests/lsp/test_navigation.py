"""Definition, type definition, references and highlights, across included files."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


def at(loc: lsp.Location | lsp.LocationLink) -> tuple[str, int, int]:
    assert isinstance(loc, lsp.Location)
    return loc.uri.rsplit("/", 1)[-1], loc.range.start.line, loc.range.start.character


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def planner(client: Client) -> str:
    uri = client.open("planner.iface")
    await client.wait_diagnostics(uri, 1)
    client.open("arm.iface")
    return uri


async def test_definition_in_an_included_file(client: Client, planner: str) -> None:
    found = await client.text_document_definition_async(
        lsp.DefinitionParams(client.doc(planner), client.pos(planner, "arm.Pose where", 5)))
    assert found and [at(x) for x in found] == [("arm.iface", 6, 8)]
    include = await client.text_document_definition_async(
        lsp.DefinitionParams(client.doc(planner), client.pos(planner, '"arm.iface"', 2)))
    assert include and at(include[0])[0] == "arm.iface"


async def test_type_definition_of_a_field(client: Client, planner: str) -> None:
    arm = client.uri("arm.iface")
    found = await client.text_document_type_definition_async(
        lsp.TypeDefinitionParams(client.doc(arm), client.pos(arm, "position", 2)))
    assert found and [at(x) for x in found] == [("common.iface", 4, 8)]


async def test_references_across_files(client: Client, planner: str) -> None:
    arm = client.uri("arm.iface")
    found = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=client.doc(arm), position=client.pos(arm, "message Pose", 9),
        context=lsp.ReferenceContext(include_declaration=True)))
    places = sorted(at(x) for x in found or [])
    assert ("arm.iface", 6, 8) in places  # the declaration
    assert ("arm.iface", 13, 8) in places  # typedef Pose ToolPose
    assert ("arm.iface", 46, 10) in places  # publishes Pose
    assert ("planner.iface", 6, 8) in places and ("planner.iface", 9, 15) in places
    without = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=client.doc(arm), position=client.pos(arm, "message Pose", 9),
        context=lsp.ReferenceContext(include_declaration=False)))
    assert len(without or []) == len(places) - 1


async def test_document_highlight(client: Client, planner: str) -> None:
    arm = client.uri("arm.iface")
    found = await client.text_document_document_highlight_async(
        lsp.DocumentHighlightParams(client.doc(arm), client.pos(arm, "Pose goal", 1)))
    lines = sorted(h.range.start.line for h in found or [])
    assert lines == [6, 13, 27, 36, 46]
    kinds = {h.range.start.line: h.kind for h in found or []}
    assert kinds[6] == lsp.DocumentHighlightKind.Write and kinds[46] == lsp.DocumentHighlightKind.Read
