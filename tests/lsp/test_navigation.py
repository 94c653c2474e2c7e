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


async def test_a_request_waits_for_the_included_file_just_changed(client: Client) -> None:
    """Go-to right after an included file's text changed answers from that text, not from the includer's
    check against the text before (the includer is re-checked first)."""
    (client.root / "stale_arm.iface").write_text('component stale_arm version "1"\nmessage Pose {\n    float64 x\n}\n')
    (client.root / "stale_user.iface").write_text(
        'component stale_user version "1"\ninclude "stale_arm.iface"\nmessage Goal {\n    stale_arm.Pose where\n}\n')
    renamed = 'component stale_arm version "1"\nmessage Posed {\n    float64 x\n}\n'
    arm = client.open("stale_arm.iface", renamed)
    await client.wait_diagnostics(arm, 1)
    user = client.open("stale_user.iface")
    await client.wait_diagnostics(user, 1)
    for round_ in range(3):
        client.replace(arm, (client.root / "stale_arm.iface").read_text())
        found = await client.text_document_definition_async(
            lsp.DefinitionParams(client.doc(user), client.pos(user, "stale_arm.Pose where", 11)))
        assert found and [at(x) for x in found] == [("stale_arm.iface", 1, 8)], round_
        client.replace(arm, renamed)
        gone = await client.text_document_definition_async(
            lsp.DefinitionParams(client.doc(user), client.pos(user, "stale_arm.Pose where", 11)))
        assert gone is None, round_
    client.close(arm)
    client.close(user)
