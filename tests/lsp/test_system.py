"""A system file in the editor: diagnostics (its checks and its graph's conflicts), hover, go-to, completion,
outline and semantic tokens, over stdio. The files are written into the server's workspace by the fixture
(plant.iface instantiates probe and display), so that the commands' sweep over tests/ does not run them."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp

from iface.lsp.features.semantic_tokens import TOKEN_TYPES

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


PROBE = """/** Measures and publishes readings. */
component probe version "1.0.0"
namespace ros2 probe_msgs

message Reading { float64 value }

publishes Reading on "/probe/reading" (qos.reliability = "best_effort")
"""
DISPLAY = """/** Shows readings. */
component display version "1.0.0"
namespace ros2 display_msgs
include "probe.iface"

subscribes probe.Reading on "/probe/reading" (qos.reliability = "reliable")
subscribes probe.Reading on "/probe/other"
"""
PLANT = """/** A probe and its display. */
system plant version "1.0.0"
include "probe.iface"
include "display.iface"

/** The probe. */
instance front : probe
instance screen : display (after = "front", restart = "sometimes")
instance spare : prbe
"""


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def plant(client: Client) -> str:
    folder = client.root / "system"
    folder.mkdir(exist_ok=True)
    for name, text in (("probe.iface", PROBE), ("display.iface", DISPLAY), ("plant.iface", PLANT)):
        (folder / name).write_text(text, encoding="utf-8")
    uri = client.open("system/plant.iface")
    await client.wait_diagnostics(uri, 1)
    return uri


async def test_diagnostics_of_instances_and_of_the_system_graph(client: Client, plant: str) -> None:
    found = await client.wait_diagnostics(plant, 1)
    got = {(d.code, d.range.start.line, d.range.start.character, d.range.end.character) for d in found}
    assert ("invalid-instance-annotation", 7, 54, 65) in got  # "sometimes"
    assert ("unknown-component", 8, 17, 21) in got  # prbe
    qos = next(d for d in found if d.code == "graph-qos-mismatch")
    assert (qos.range.start.line, qos.range.start.character, qos.range.end.character) == (7, 9, 15)  # screen
    assert qos.severity == lsp.DiagnosticSeverity.Error and "best_effort" in qos.message
    assert qos.related_information and qos.related_information[0].location.uri.endswith("display.iface")
    unpublished = next(d for d in found if d.code == "graph-unpublished-topic")
    assert unpublished.severity == lsp.DiagnosticSeverity.Warning and "/probe/other" in unpublished.message
    prbe = next(d for d in found if d.code == "unknown-component")
    assert "did you mean 'probe'" in prbe.message


async def hover(client: Client, uri: str, needle: str, delta: int = 0) -> str:
    result = await client.text_document_hover_async(lsp.HoverParams(client.doc(uri), client.pos(uri, needle, delta)))
    assert result is not None, needle
    assert isinstance(result.contents, lsp.MarkupContent)
    return result.contents.value


async def test_hover_on_system_instance_component_and_annotation(client: Client, plant: str) -> None:
    system = await hover(client, plant, "plant", 1)
    assert "**system** `plant`" in system and "start order: front → screen → spare" in system
    instance = await hover(client, plant, "screen", 1)
    assert "**instance** `screen` : `display`" in instance and "`/screen`" in instance and "front" in instance
    component = await hover(client, plant, ": probe", 3)
    assert "**component** `probe`" in component and "Measures and publishes readings." in component
    assert "1 published" in component
    after = await hover(client, plant, "after", 1)
    assert "**instance annotation** `after`" in after


async def test_go_to_component_and_after(client: Client, plant: str) -> None:
    found = await client.text_document_definition_async(
        lsp.DefinitionParams(client.doc(plant), client.pos(plant, ": display", 3)))
    assert isinstance(found, list) and len(found) == 1
    assert found[0].uri.endswith("system/display.iface") and found[0].range.start == lsp.Position(line=1, character=10)
    found = await client.text_document_definition_async(
        lsp.DefinitionParams(client.doc(plant), client.pos(plant, '"front"', 2)))
    assert isinstance(found, list) and found[0].uri == plant
    assert found[0].range.start == lsp.Position(line=6, character=9)  # instance front
    refs = await client.text_document_references_async(lsp.ReferenceParams(
        context=lsp.ReferenceContext(include_declaration=True), text_document=client.doc(plant),
        position=client.pos(plant, "front", 1)))
    assert refs is not None and sorted((r.range.start.line, r.range.start.character) for r in refs) == [(6, 9), (7, 36)]


async def complete(client: Client, uri: str, text: str) -> set[str]:
    """Replace the document with ``text`` up to ``|`` and complete there: the labels."""
    at = text.index("|")
    body = text.replace("|", "")
    client.replace(uri, body)
    client.texts[uri] = body
    await client.wait_diagnostics(uri, client.versions[uri])
    line = body.count("\n", 0, at)
    col = at - (body.rfind("\n", 0, at) + 1)
    result = await client.text_document_completion_async(
        lsp.CompletionParams(client.doc(uri), lsp.Position(line=line, character=col)))
    assert result is not None
    items = result.items if isinstance(result, lsp.CompletionList) else result
    return {i.label for i in items}


HEAD = 'system plant\ninclude "probe.iface"\ninclude "display.iface"\ninstance front : probe\n'


async def test_completion_of_components_annotations_and_values(client: Client, plant: str) -> None:
    uri = client.open("system/editing.iface", HEAD)
    await client.wait_diagnostics(uri, 1)
    assert {"probe", "display"} <= await complete(client, uri, HEAD + "instance back : |")
    keys = await complete(client, uri, HEAD + "instance back : display (|)")
    assert {"package", "executable", "node", "restart", "snapshot", "after", "parameters"} <= keys
    assert {'"never"', '"on-failure"', '"always"'} <= await complete(client, uri, HEAD + 'instance back : display (restart = "|")')
    assert "standby" in keys
    assert {'"true"', '"false"'} <= await complete(client, uri, HEAD + 'instance back : display (standby = "|")')
    assert '"front"' in await complete(client, uri, HEAD + 'instance back : display (node = "b", after = |)')
    assert {"system", "instance"} <= await complete(client, uri, HEAD + "|")


async def test_completion_and_hover_of_a_container(client: Client, plant: str) -> None:
    """The container keys and their values: the runtimes, true/false, and the containers the file already names."""
    uri = client.open("system/boxes.iface", HEAD)
    await client.wait_diagnostics(uri, 1)
    boxed = HEAD + 'instance back : display (container = "box")\n'
    keys = await complete(client, uri, boxed + "instance more : display (|)")
    assert {"container", "runtime", "plugin", "intra_process"} <= keys
    assert '"box"' in await complete(client, uri, boxed + 'instance more : display (container = "|")')
    assert {'"rclpy"', '"rclcpp"'} <= await complete(client, uri, boxed + 'instance more : display (runtime = "|")')
    assert {'"true"', '"false"'} <= await complete(client, uri, boxed + 'instance more : display (intra_process = "|")')
    client.replace(uri, boxed)
    client.texts[uri] = boxed
    await client.wait_diagnostics(uri, client.versions[uri])
    shown = await hover(client, uri, "back", 1)
    assert "- container: `box` (shares its process; intra-process where the QoS allows)" in shown
    assert "standby" not in shown
    spare = boxed.replace('(container = "box")', '(container = "box", standby = "true")')
    client.replace(uri, spare)
    client.texts[uri] = spare
    await client.wait_diagnostics(uri, client.versions[uri])
    shown = await hover(client, uri, "back", 1)
    assert "- standby: a spare container process started ahead, which becomes the container at a restart" in shown
    assert "- runtime: `rclcpp`" in shown
    key = await hover(client, uri, "container", 1)
    assert "**instance annotation** `container`" in key and "share its process" in key


async def test_outline_and_semantic_tokens(client: Client, plant: str) -> None:
    found = await client.text_document_document_symbol_async(lsp.DocumentSymbolParams(client.doc(plant)))
    assert found
    if isinstance(found[0], lsp.DocumentSymbol):
        group = next(g for g in found if g.name == "instances")
        assert [(c.name, c.detail) for c in group.children or []] == [
            ("front", "probe"), ("screen", "display"), ("spare", "prbe")]
    else:
        assert {"front", "screen", "spare"} <= {s.name for s in found}
    tokens = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(client.doc(plant)))
    assert tokens is not None
    line = col = 0
    kinds: dict[tuple[int, int], str] = {}
    for i in range(0, len(tokens.data), 5):
        dl, dc, _, ttype, _ = tokens.data[i:i + 5]
        line += dl
        col = col + dc if dl == 0 else dc
        kinds[(line, col)] = TOKEN_TYPES[ttype]
    assert kinds[(6, 0)] == "keyword" and kinds[(6, 9)] == "variable" and kinds[(6, 17)] == "namespace"
    assert kinds[(1, 0)] == "keyword" and kinds[(1, 7)] == "namespace"  # system plant
    assert kinds[(7, 27)] == "decorator"  # after
