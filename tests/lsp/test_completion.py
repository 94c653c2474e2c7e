"""Completion: keywords and snippets, types, annotation keys, topics, wiring, members."""

from __future__ import annotations

import pytest
import pytest_asyncio
from lsprotocol import types as lsp

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")

DOC = """component comp version "1"
include "common.iface"

message Local {
    u8 count
}

enum Mode { IDLE = 0, RUN = 1 }

"""


async def complete(client: Client, uri: str, text: str) -> list[lsp.CompletionItem]:
    """Replace the document with ``text`` up to ``|`` and complete there."""
    at = text.index("|")
    body = text.replace("|", "")
    client.replace(uri, body)
    client.texts[uri] = body
    line = body.count("\n", 0, at)
    col = at - (body.rfind("\n", 0, at) + 1)
    result = await client.text_document_completion_async(
        lsp.CompletionParams(client.doc(uri), lsp.Position(line=line, character=col)))
    assert result is not None
    return result.items if isinstance(result, lsp.CompletionList) else result


def labels(items: list[lsp.CompletionItem]) -> set[str]:
    return {i.label for i in items}


@pytest_asyncio.fixture(scope="module", loop_scope="session")
async def doc(client: Client) -> str:
    uri = client.open("completion.iface", DOC)
    await client.wait_diagnostics(uri, 1)
    return uri


async def test_keywords_and_snippets_at_top_level(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "|")
    assert {"message", "service", "action", "publishes", "include"} <= labels(items)
    service = next(i for i in items if i.label == "service")
    snippets = client.profile == "visual-studio-code" or bool(
        client.capabilities.text_document.completion.completion_item.snippet_support)
    if snippets:
        assert service.insert_text_format == lsp.InsertTextFormat.Snippet and "request {" in service.insert_text
    else:
        assert service.insert_text_format is None


async def test_types_where_a_type_goes(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "message New {\n    |\n}\n")
    found = labels(items)
    assert {"u8", "float64", "string", "Local", "Mode", "common.Vec3", "common.Level", "const"} <= found
    assert "message" not in found
    prefixed = await complete(client, doc, DOC + "message New {\n    Lo|\n}\n")
    assert "Local" in labels(prefixed) and "u8" not in labels(prefixed)


async def test_every_base_type_is_offered_wchar_too(client: Client, doc: str) -> None:
    from iface.model.nodes import BASE_ALIASES

    found = labels(await complete(client, doc, DOC + "message New {\n    |\n}\n"))
    assert {"wchar", "wstring", "char", "octet", "list", "set", "map"} <= found
    assert set(BASE_ALIASES) <= found
    prefixed = await complete(client, doc, DOC + "message New {\n    wc|\n}\n")
    assert "wchar" in labels(prefixed) and "wstring" not in labels(prefixed)


async def test_sections_in_a_service(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "service S {\n    |\n}\n")
    assert {"request", "response"} <= labels(items)


async def test_annotation_keys(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "configuration P {\n    float64 speed (|)\n}\n")
    assert {"unit", "range", "min", "max"} <= labels(items)
    qos = await complete(client, doc, DOC + 'publishes Local on "/local" (|)\n')
    assert "qos.depth" in labels(qos)


async def test_wiring_offers_messages_then_topics_of_the_workspace(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "publishes |")
    assert "Local" in labels(items) and "Mode" not in labels(items)
    await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query=""))  # the workspace is indexed
    topics = await complete(client, doc, DOC + "subscribes common.Vec3 on |")
    assert '"/arm/pose"' in labels(topics) and '"/planner/goal"' in labels(topics)


async def test_enum_members_and_field_names_of_the_wired_message(client: Client, doc: str) -> None:
    items = await complete(client, doc, DOC + "struct S {\n    Mode m = Mode.|\n}\n")
    assert {"Mode.IDLE", "Mode.RUN"} <= labels(items)
    fields = await complete(client, doc, DOC + 'publishes Local on "/l" (key = |)\n')
    assert '"count"' in labels(fields)


async def test_member_completion_after_a_constant(client: Client, doc: str) -> None:
    """A blank line right after a constant member still offers types (seen in VS Code)."""
    items = await complete(client, doc, DOC + "message Limits {\n    const u8 MAX_JOINTS = 6\n    |\n}\n")
    assert {"float64", "Local"} <= labels(items)


async def test_many_types_give_the_best_hundred_by_name_and_say_the_list_is_incomplete(client: Client) -> None:
    """Completion builds only the first names of each group (its cost does not grow with the file); the
    answer is still the first hundred of all candidates sorted, and says that more exist."""
    numbers = [(i * 7919) % 600 for i in range(600)]  # every number once, out of order
    body = 'component many version "1"\n\n' + "".join(f"message T{n} {{\n    u8 a\n}}\n\n" for n in numbers)
    uri = client.open("many_types.iface", body)
    await client.wait_diagnostics(uri, 1)
    result = await client.text_document_completion_async(lsp.CompletionParams(
        client.doc(uri), lsp.Position(line=body.count("\n") - 3, character=4)))
    assert isinstance(result, lsp.CompletionList) and result.is_incomplete
    everything = [f"T{n}" for n in numbers] + ["const", "required", "optional"]  # sort group 2, before builtins
    assert [i.label for i in result.items] == sorted(everything)[:100]
    client.close(uri)
