"""Formatting and code actions: quick fixes keyed on diagnostic codes, refactorings, source actions."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from iface.text.formatter import format_range, format_text

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")

UGLY = 'component ugly version "1"\n// keep me\nmessage   M {   u8    a\n  float64 b=1.0 }\npublishes M on "/m"\n'


def apply(text: str, edits: list[lsp.TextEdit]) -> str:
    """Apply LSP edits (ASCII text: positions are characters in any encoding)."""
    lines = text.split("\n")
    starts = [0]
    for line in lines[:-1]:
        starts.append(starts[-1] + len(line) + 1)

    def off(p: lsp.Position) -> int:
        return starts[p.line] + p.character

    for e in sorted(edits, key=lambda e: off(e.range.start), reverse=True):
        text = text[:off(e.range.start)] + e.new_text + text[off(e.range.end):]
    return text


async def test_formatting_is_the_fmt_formatter_and_idempotent(client: Client) -> None:
    uri = client.open("ugly.iface", UGLY)
    await client.wait_diagnostics(uri, 1)
    opts = lsp.FormattingOptions(tab_size=4, insert_spaces=True)
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(client.doc(uri), opts))
    assert edits
    formatted = apply(UGLY, edits)
    assert formatted == format_text(UGLY) and "// keep me" in formatted
    client.replace(uri, formatted)
    again = await client.text_document_formatting_async(lsp.DocumentFormattingParams(client.doc(uri), opts))
    assert not again
    client.replace(uri, UGLY)
    rng = lsp.Range(start=lsp.Position(line=2, character=0), end=lsp.Position(line=3, character=5))
    ranged = await client.text_document_range_formatting_async(
        lsp.DocumentRangeFormattingParams(client.doc(uri), rng, opts))
    expected = UGLY
    for e in reversed(format_range(UGLY, UGLY.index("message"), UGLY.index("publishes") - 1)):
        expected = expected[:e.start] + e.new_text + expected[e.end:]
    assert ranged and apply(UGLY, ranged) == expected and "message M {\n    u8 a" in expected
    client.close(uri)


async def fixes(client: Client, uri: str, code: str, only: list[str] | None = None) -> tuple[lsp.Diagnostic, list[lsp.CodeAction]]:
    diags = await client.wait_diagnostics(uri, client.versions[uri])
    diag = next(d for d in diags if d.code == code)
    actions = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=diag.range,
        context=lsp.CodeActionContext(diagnostics=[diag], only=only or [lsp.CodeActionKind.QuickFix])))
    return diag, [a for a in actions or [] if isinstance(a, lsp.CodeAction)]


def edited(client: Client, uri: str, action: lsp.CodeAction) -> str:
    assert action.edit is not None and action.edit.changes is not None
    return apply(client.texts[uri], action.edit.changes[uri])


async def test_did_you_mean_and_create_missing_type(client: Client) -> None:
    uri = client.open("broken.iface")
    _, actions = await fixes(client, uri, "unknown-type")
    titles = [a.title for a in actions]
    assert titles[0] == "Change to 'float64'" and "Create message 'flaot64'" in titles
    assert "float64 value" in edited(client, uri, actions[0])
    diags = await client.wait_diagnostics(uri, 1)
    vec = next(d for d in diags if "'Vec'" in d.message)
    more = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=vec.range, context=lsp.CodeActionContext(diagnostics=[vec])))
    create = next(a for a in more or [] if isinstance(a, lsp.CodeAction) and a.title == "Create message 'Vec'")
    assert "message Vec {\n}" in edited(client, uri, create)
    client.close(uri)


async def test_fixes_for_naming_direction_flat_service_parts_and_defaults(client: Client) -> None:
    uri = client.open("fixes.iface")
    _, naming = await fixes(client, uri, "ros-naming")
    assert "float64 max_speed" in edited(client, uri, naming[0])
    _, wire = await fixes(client, uri, "message-no-direction")
    assert [a.title for a in wire] == ['Add `publishes Unwired on "/unwired"`', 'Add `subscribes Unwired on "/unwired"`']
    assert 'provides Half on "/fixes/half"\npublishes Unwired on "/unwired"' in edited(client, uri, wire[0])
    _, flat = await fixes(client, uri, "flat-service")
    explicit = edited(client, uri, flat[0])
    assert "service Flat {\n    request {\n        u32 a\n    }\n    response {\n        bool ok\n    }\n}" in explicit
    _, half = await fixes(client, uri, "service-part-missing")
    assert "        u32 a\n    }\n    response {}\n}" in edited(client, uri, half[0])
    _, default = await fixes(client, uri, "missing-default")
    assert "float64 gain = 0.5 (range" in edited(client, uri, default[0])
    for code in ("ros-naming", "message-no-direction", "flat-service", "service-part-missing", "missing-default"):
        _, actions = await fixes(client, uri, code)
        client.replace(uri, edited(client, uri, actions[0]))
    final = await client.wait_diagnostics(uri, client.versions[uri])
    assert not [d for d in final if d.severity in (lsp.DiagnosticSeverity.Error, lsp.DiagnosticSeverity.Warning)]
    client.close(uri)


async def test_px4_timestamp_and_source_actions(client: Client) -> None:
    text = 'component drone version "1"\nnamespace px4 drone\n\nmessage Battery {\n    float32 voltage\n}\npublishes Battery on "/battery"\n'
    uri = client.open("drone.iface", text)
    await client.wait_diagnostics(uri, 1)
    rewrite = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=lsp.Range(start=client.pos(uri, "voltage"), end=client.pos(uri, "voltage")),
        context=lsp.CodeActionContext(diagnostics=[], only=[lsp.CodeActionKind.RefactorRewrite])))
    stamp = next(a for a in rewrite or [] if isinstance(a, lsp.CodeAction) and "timestamp" in a.title)
    assert "message Battery {\n    uint64 timestamp" in edited(client, uri, stamp)
    source = await client.text_document_code_action_async(lsp.CodeActionParams(
        text_document=client.doc(uri), range=lsp.Range(start=lsp.Position(line=0, character=0), end=lsp.Position(line=0, character=0)),
        context=lsp.CodeActionContext(diagnostics=[], only=[lsp.CodeActionKind.Source])))
    titles = {a.title: a for a in source or [] if isinstance(a, lsp.CodeAction)}
    assert {"Generate for ros2", "Generate for px4", "Export JSON"} <= set(titles)
    gen = titles["Generate for px4"]
    assert gen.command is not None and gen.command.command == "iface.generate" and list(gen.command.arguments or []) == [uri, "px4"]
    assert any(t.startswith("Preview generated files") for t in titles)
    client.close(uri)
