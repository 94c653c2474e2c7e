"""Document and workspace symbols, folding ranges, selection ranges, semantic tokens."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp

from iface.lsp.features.semantic_tokens import TOKEN_TYPES

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def arm(client: Client) -> str:
    uri = client.open("arm.iface")
    await client.wait_diagnostics(uri, 1)
    return uri


async def test_outline_is_grouped_by_the_seven_sets(client: Client, arm: str) -> None:
    found = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(client.doc(arm)))
    assert found
    if isinstance(found[0], lsp.DocumentSymbol):
        groups = {g.name: [c.name for c in g.children or []] for g in found}  # type: ignore[union-attr]
        assert groups["M · subscribed"] == ["Command on /arm/command"]
        assert groups["N · published"] == ["Pose on /arm/pose"]
        assert groups["S · services"] == ["Plan on /arm/plan"]
        assert groups["A · actions"] == ["Move on /arm/move"]
        assert groups["P · parameters"] == ["Params"]
        assert {"Pose", "Command", "ToolPose", "Plan", "Move"} <= set(groups["types"])
        params = next(g for g in found if g.name == "P · parameters").children[0]  # type: ignore[union-attr]
        assert [c.name for c in params.children or []] == ["max_speed", "retries"]
    else:
        names = {s.name for s in found}
        assert {"Pose", "max_speed", "Command on /arm/command"} <= names


async def test_workspace_symbols(client: Client, arm: str) -> None:
    found = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query="vec"))
    assert found and any(s.name == "Vec3" and s.location.uri.endswith("common.iface") for s in found)
    everything = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query=""))
    assert {"Goal", "Pose", "Level", "Tuning"} <= {s.name for s in everything or []}


async def test_folding_ranges(client: Client, arm: str) -> None:
    found = await client.text_document_folding_range_async(lsp.FoldingRangeParams(client.doc(arm)))
    spans = {(r.start_line, r.end_line) for r in found or []}
    assert (6, 11) in spans  # message Pose
    assert (25, 32) in spans and (26, 28) in spans  # service Plan and its request


async def test_selection_ranges_widen(client: Client, arm: str) -> None:
    found = await client.text_document_selection_range_async(
        lsp.SelectionRangeParams(client.doc(arm), [client.pos(arm, "goal", 1)]))
    assert found
    chain = []
    node: lsp.SelectionRange | None = found[0]
    while node is not None:
        chain.append((node.range.start.line, node.range.end.line))
        node = node.parent
    assert chain[0] == (27, 27) and (26, 28) in chain and (25, 32) in chain
    assert chain[-1][0] == 0


async def test_semantic_tokens(client: Client, arm: str) -> None:
    found = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(client.doc(arm)))
    assert found is not None and len(found.data) % 5 == 0
    line = col = 0
    tokens: dict[tuple[int, int], int] = {}
    for i in range(0, len(found.data), 5):
        dl, dc, length, ttype, _ = found.data[i:i + 5]
        line += dl
        col = col + dc if dl == 0 else dc
        tokens[(line, col)] = ttype
    names = {k: TOKEN_TYPES[v] for k, v in tokens.items()}
    assert names[(6, 0)] == "keyword" and names[(6, 8)] == "struct"  # message Pose
    assert names[(8, 11)] == "struct"  # common.Vec3 used as a type
    assert names[(9, 12)] == "property"  # yaw
    assert names[(0, 0)] == "comment"
