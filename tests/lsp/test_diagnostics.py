"""Diagnostics over stdio: on open and change, with codes, related locations and data; across includes."""

from __future__ import annotations

import pytest
from lsprotocol import types as lsp

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_open_reports_what_check_finds(client: Client) -> None:
    uri = client.open("broken.iface")
    diags = await client.wait_diagnostics(uri, 1)
    codes = sorted(str(d.code) for d in diags)
    assert codes == ["duplicate-definition", "message-no-direction", "unknown-type", "unknown-type"]
    typo = next(d for d in diags if "flaot64" in d.message)
    assert typo.severity == lsp.DiagnosticSeverity.Error
    assert typo.source == "iface"
    assert (typo.range.start.line, typo.range.start.character, typo.range.end.character) == (3, 4, 11)
    assert typo.data["suggestions"][:1] == ["float64"]
    dup = next(d for d in diags if d.code == "duplicate-definition")
    assert dup.related_information and dup.related_information[0].location.uri == uri
    assert dup.related_information[0].location.range.start.line == 2
    client.close(uri)


async def test_change_gets_new_diagnostics_for_its_version(client: Client) -> None:
    uri = client.open("broken.iface")
    await client.wait_diagnostics(uri, 1)
    fixed = client.texts[uri].replace("flaot64", "float64").replace("    Vec x\n", "")
    version = client.replace(uri, fixed)
    diags = await client.wait_diagnostics(uri, version)
    assert [str(d.code) for d in diags if d.severity == lsp.DiagnosticSeverity.Error] == ["duplicate-definition"]
    version = client.edit(uri, (3, 4), (3, 11), "Missing")
    diags = await client.wait_diagnostics(uri, version)
    assert any(d.code == "unknown-type" and "Missing" in d.message for d in diags)
    client.close(uri)


async def test_errors_in_an_include_are_shown_where_they_are(client: Client) -> None:
    mark = client.mark()
    uri = client.open("uses_broken.iface")
    diags = await client.wait_diagnostics(uri, 1)
    inc = next(d for d in diags if d.code == "include-error")
    assert inc.range.start.line == 1
    assert inc.related_information and inc.related_information[0].location.uri == client.uri("bad_include.iface")
    included = await client.wait_diagnostics(client.uri("bad_include.iface"), after=mark)
    assert any(d.code == "unknown-type" and d.range.start.line == 1 for d in included)
    client.close(uri)


async def test_dependents_are_rechecked_when_an_include_changes(client: Client) -> None:
    user = client.open("uses_broken.iface")
    await client.wait_diagnostics(user, 1)
    inc = client.open("bad_include.iface")
    await client.wait_diagnostics(inc, 1)
    mark = client.mark()
    version = client.replace(inc, client.texts[inc].replace("Missing", "u8"))
    assert not [d for d in await client.wait_diagnostics(inc, version) if d.severity == lsp.DiagnosticSeverity.Error]
    rechecked = await client.wait_diagnostics(
        user, after=mark, until=lambda ds: not any(d.code == "include-error" for d in ds))
    assert not [d for d in rechecked if d.severity == lsp.DiagnosticSeverity.Error]
    client.close(inc)
    client.close(user)


async def test_positions_count_in_the_negotiated_encoding(client: Client) -> None:
    # "𝔸" is one code point, two UTF-16 units: the column of `Nope` depends on the encoding.
    text = 'component astral version "1"\n/** 𝔸 */ message A { Nope x }\npublishes A on "/a"\n'
    uri = client.open("astral.iface", text)
    diags = await client.wait_diagnostics(uri, 1)
    d = next(d for d in diags if d.code == "unknown-type")
    utf32 = client.profile == "neovim"  # Neovim offers utf-32; VS Code speaks utf-16
    assert d.range.start.character == (21 if utf32 else 22)
    assert d.range.end.character == d.range.start.character + 4
    client.close(uri)


async def test_qos_values_rmw_lacks_are_warned_at_the_annotation(client: Client) -> None:
    """The editor says what `check` and `generate` say: qos-not-in-rmw at the annotation, as a warning."""
    text = ('component q\nmessage M { i32 x }\n'
            'publishes M on "/kept" (qos.durability = "transient", qos.depth = 3)\n')
    uri = client.open("qos_rmw.iface", text)
    diags = await client.wait_diagnostics(uri, 1)
    (d,) = [d for d in diags if d.code == "qos-not-in-rmw"]
    assert d.severity == lsp.DiagnosticSeverity.Warning
    assert d.range.start == client.pos(uri, 'qos.durability') and d.range.end == client.pos(uri, ', qos.depth')
    assert d.message == ("qos.durability = transient: ROS 2 has no such durability (rmw's are volatile, "
                         "transient_local, best_available); the generated node asks for transient_local")
    client.close(uri)
