"""The server never stops answering: 1,000 random edits, and malformed JSON-RPC on the wire."""

from __future__ import annotations

import asyncio
import json
import random
import re
import shutil
from pathlib import Path
from typing import Any

import pytest
import pytest_lsp
from lsprotocol import types as lsp

from iface.text.formatter import format_text

from .harness import CONFIG, DATA, SERVER, Client, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

EDITS = 1000
TOKENS = ["message", "service", "{", "}", "(", ")", "=", '"', "/**", "*/", "//", "u8", "float64[3]", "list<",
          ">", "publishes", "on", '"/t"', "request", "const", "\n", "\n\n", "  ", "Pose", "common.", ",", ";",
          "0x1F", "-1.5e3", "é", "𝔸", "\r\n", "\t", "enum", "include"]
_BREAK = re.compile(r"\r\n|\r|\n")


def position(text: str, offset: int) -> lsp.Position:
    """An LSP position (UTF-16 columns; lines end at \\n, \\r\\n or \\r), computed independently of the server."""
    line, start = 0, 0
    for m in _BREAK.finditer(text, 0, offset):
        if m.end() > offset:
            break
        line, start = line + 1, m.end()
    return lsp.Position(line=line, character=len(text[start:offset].encode("utf-16-le")) // 2)


def random_edit(rng: random.Random, text: str) -> tuple[int, int, str]:
    """A random deletion, insertion of tokens, or insertion of random characters; offsets on code points."""
    a = rng.randint(0, len(text))
    if text and rng.random() < 0.35:
        b = min(len(text), a + rng.randint(1, 12))
        return a, b, ""
    if rng.random() < 0.75:
        return a, a, "".join(rng.choice(TOKENS) for _ in range(rng.randint(1, 3)))
    chars = [chr(rng.choice([rng.randint(1, 127), rng.randint(128, 0x2FFF), rng.randint(0x10000, 0x1F6FF)]))
             for _ in range(rng.randint(1, 4))]
    return a, a, "".join(c for c in chars if not 0xD800 <= ord(c) <= 0xDFFF)


def ver(text: str, offset: int) -> int:
    """Never split a \\r\\n pair: an edit between them would change the line count in two ways at once."""
    return offset - 1 if 0 < offset < len(text) and text[offset - 1] == "\r" and text[offset] == "\n" else offset


@pytest_lsp.fixture(config=CONFIG, scope="module")
async def fuzz_client(lsp_client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    root = tmp_path_factory.mktemp("fuzz")
    shutil.copy(DATA / "common.iface", root / "common.iface")
    await start(lsp_client, root, "visual-studio-code")
    yield
    await lsp_client.shutdown_session()


async def test_random_edits_each_get_diagnostics_and_hover_answers(fuzz_client: Client) -> None:
    client = fuzz_client
    rng = random.Random(20240611)
    text = (DATA / "arm.iface").read_text(encoding="utf-8")
    uri = client.open("fuzz.iface", text)
    await client.wait_diagnostics(uri, 1)
    for _ in range(EDITS):
        a, b, new = random_edit(rng, text)
        a, b = ver(text, a), ver(text, b)
        start_pos, end_pos = position(text, a), position(text, b)
        text = text[:a] + new + text[b:]
        version = client.edit(uri, (start_pos.line, start_pos.character), (end_pos.line, end_pos.character), new)
        at = position(text, rng.randint(0, len(text)))
        hover = client.text_document_hover_async(lsp.HoverParams(client.doc(uri), at))
        await client.wait_diagnostics(uri, version)
        result = await hover
        assert result is None or isinstance(result, lsp.Hover)
    # the server's text is still the client's: replacing the whole text by range leaves nothing behind
    valid = format_text((DATA / "arm.iface").read_text(encoding="utf-8"))
    end = position(text, len(text))
    version = client.edit(uri, (0, 0), (end.line, end.character), valid)
    final = await client.wait_diagnostics(uri, version)
    assert not [d for d in final if d.severity == lsp.DiagnosticSeverity.Error]
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        client.doc(uri), lsp.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits


def frame(body: bytes) -> bytes:
    return b"Content-Length: %d\r\n\r\n" % len(body) + body


def message(payload: dict[str, Any]) -> bytes:
    return frame(json.dumps(payload).encode())


async def read_message(stream: asyncio.StreamReader) -> dict[str, Any]:
    length = 0
    while True:
        line = await stream.readline()
        if not line:
            raise EOFError("the server closed its output")
        if line.lower().startswith(b"content-length:"):
            length = int(line.split(b":")[1])
        elif line == b"\r\n" and length:
            return json.loads(await stream.readexactly(length))


async def response(stream: asyncio.StreamReader, msg_id: int,
                   keep: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    """The response to request ``msg_id``; the messages before it are dropped, or added to ``keep``."""
    while True:
        msg = await asyncio.wait_for(read_message(stream), 30)
        if msg.get("id") == msg_id and "method" not in msg:
            return msg
        if keep is not None:
            keep.append(msg)


async def test_malformed_json_rpc_does_not_kill_the_server(tmp_path: Path) -> None:
    proc = await asyncio.create_subprocess_exec(*SERVER, stdin=asyncio.subprocess.PIPE,
                                                stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE)
    assert proc.stdin is not None and proc.stdout is not None
    send = proc.stdin.write
    send(message({"jsonrpc": "2.0", "id": 1, "method": "initialize",
                  "params": {"processId": None, "rootUri": tmp_path.as_uri(), "capabilities": {}}}))
    assert "capabilities" in (await response(proc.stdout, 1))["result"]
    send(message({"jsonrpc": "2.0", "method": "initialized", "params": {}}))
    send(frame(b"{this is not json"))
    send(frame(b"[1, 2, 3]"))
    send(frame(b'"just a string"'))
    send(message({"id": 2, "method": "textDocument/hover"}))  # no jsonrpc member
    send(b"garbage that is no header\r\n")
    send(message({"jsonrpc": "2.0", "id": 3, "method": "textDocument/hover", "params": {"textDocument": 5}}))
    send(message({"jsonrpc": "2.0", "id": 4, "method": "no/such/method", "params": {}}))
    send(frame(b'{"jsonrpc": "2.0", "id": 5, "method": "textDocument/hover", "params": {"textDocument": {"uri": "file:///x.iface"}, "position": {"line": "zero"}}}'))
    await proc.stdin.drain()
    invalid = await response(proc.stdout, 3)
    assert invalid["error"]["code"] == -32602
    assert (await response(proc.stdout, 4))["error"]["code"] == -32601
    assert "error" in await response(proc.stdout, 5)
    uri = (tmp_path / "ok.iface").as_uri()
    send(message({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "iface", "version": 1, "text": "message M { u8 a }\npublishes M on \"/m\"\n"}}}))
    send(message({"jsonrpc": "2.0", "id": 6, "method": "textDocument/hover",
                  "params": {"textDocument": {"uri": uri}, "position": {"line": 0, "character": 9}}}))
    await proc.stdin.drain()
    hover = await response(proc.stdout, 6)
    assert "message" in hover["result"]["contents"]["value"]
    send(message({"jsonrpc": "2.0", "id": 7, "method": "shutdown"}))
    await response(proc.stdout, 7)
    send(message({"jsonrpc": "2.0", "method": "exit"}))
    await proc.stdin.drain()
    assert await asyncio.wait_for(proc.wait(), 30) == 0



async def test_a_refused_request_is_an_answer_not_an_error_in_the_log(tmp_path: Path) -> None:
    """A rename where there is no name and a command asked with a wrong argument get their error answers; the
    server's stderr (an editor's log of it) then holds no traceback and no error line, and no error goes to
    the client's log (``window/logMessage``)."""
    proc = await asyncio.create_subprocess_exec(*SERVER, stdin=asyncio.subprocess.PIPE,
                                                stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE)
    assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
    send = proc.stdin.write
    logged: list[dict[str, Any]] = []
    send(message({"jsonrpc": "2.0", "id": 1, "method": "initialize",
                  "params": {"processId": None, "rootUri": tmp_path.as_uri(), "capabilities": {}}}))
    await response(proc.stdout, 1, logged)
    send(message({"jsonrpc": "2.0", "method": "initialized", "params": {}}))
    uri = (tmp_path / "ok.iface").as_uri()
    send(message({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": uri, "languageId": "iface", "version": 1, "text": "message M { u8 a }\n\n"}}}))
    send(message({"jsonrpc": "2.0", "id": 2, "method": "textDocument/rename", "params": {
        "textDocument": {"uri": uri}, "position": {"line": 1, "character": 0}, "newName": "N"}}))
    send(message({"jsonrpc": "2.0", "id": 3, "method": "workspace/executeCommand", "params": {
        "command": "iface.generate", "arguments": [uri, "no-such-target"]}}))
    await proc.stdin.drain()
    answers: dict[int, dict[str, Any]] = {}
    while len(answers) < 2:  # in either order
        msg = await asyncio.wait_for(read_message(proc.stdout), 30)
        if msg.get("id") in (2, 3) and "method" not in msg:
            answers[msg["id"]] = msg
        else:
            logged.append(msg)
    renamed, generated = answers[2], answers[3]
    assert "nothing to rename" in renamed["error"]["message"]
    assert "unknown target 'no-such-target'" in generated["error"]["message"]
    send(message({"jsonrpc": "2.0", "id": 4, "method": "shutdown"}))
    await response(proc.stdout, 4, logged)
    send(message({"jsonrpc": "2.0", "method": "exit"}))
    await proc.stdin.drain()
    assert await asyncio.wait_for(proc.wait(), 30) == 0
    stderr = (await proc.stderr.read()).decode()
    assert "Traceback" not in stderr and "ERROR" not in stderr, stderr
    errors = [m["params"]["message"] for m in logged if m.get("method") == "window/logMessage"
              and m["params"]["type"] == lsp.MessageType.Error]
    assert errors == []


async def test_requests_before_initialize_and_after_shutdown_get_errors_not_silence(tmp_path: Path) -> None:
    """LSP: -32002 (ServerNotInitialized) before ``initialize``, InvalidRequest after ``shutdown``; ``exit`` ends it."""
    proc = await asyncio.create_subprocess_exec(*SERVER, stdin=asyncio.subprocess.PIPE,
                                                stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE)
    assert proc.stdin is not None and proc.stdout is not None
    send = proc.stdin.write
    hover = {"textDocument": {"uri": (tmp_path / "x.iface").as_uri()}, "position": {"line": 0, "character": 0}}
    send(message({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": (tmp_path / "x.iface").as_uri(), "languageId": "iface", "version": 1, "text": "message M {}"}}}))
    send(message({"jsonrpc": "2.0", "id": 1, "method": "textDocument/hover", "params": hover}))
    send(message({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}))
    await proc.stdin.drain()
    for msg_id in (1, 2):
        early = await response(proc.stdout, msg_id)
        assert early["error"]["code"] == -32002 and "initialize" in early["error"]["message"], early
    send(message({"jsonrpc": "2.0", "id": 3, "method": "initialize",
                  "params": {"processId": None, "rootUri": tmp_path.as_uri(), "capabilities": {}}}))
    assert "capabilities" in (await response(proc.stdout, 3))["result"]
    send(message({"jsonrpc": "2.0", "method": "initialized", "params": {}}))
    send(message({"jsonrpc": "2.0", "id": 4, "method": "textDocument/hover", "params": hover}))
    await proc.stdin.drain()
    # answered before shutdown is sent: pygls cancels what is still pending at shutdown (-32800), and the
    # hover may wait for the model thread (the parser's warm-up, the workspace index) on a busy machine
    assert "error" not in await response(proc.stdout, 4)
    send(message({"jsonrpc": "2.0", "id": 5, "method": "shutdown"}))
    await proc.stdin.drain()
    assert (await response(proc.stdout, 5))["result"] is None
    send(message({"jsonrpc": "2.0", "id": 6, "method": "textDocument/hover", "params": hover}))
    send(message({"jsonrpc": "2.0", "id": 7, "method": "shutdown"}))
    await proc.stdin.drain()
    for msg_id in (6, 7):
        late = await response(proc.stdout, msg_id)
        assert late["error"]["code"] == -32600 and "shut down" in late["error"]["message"], late
    send(message({"jsonrpc": "2.0", "method": "exit"}))
    await proc.stdin.drain()
    assert await asyncio.wait_for(proc.wait(), 30) == 0


async def test_tcp_server_answers_on_a_loopback_port() -> None:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = await asyncio.create_subprocess_exec(SERVER[0], "-m", "iface", "--tcp", f"127.0.0.1:{port}",
                                                stderr=asyncio.subprocess.PIPE)
    try:
        for _ in range(200):  # bounded: the server needs a moment to listen
            try:
                reader, writer = await asyncio.open_connection("127.0.0.1", port)
                break
            except OSError:
                await asyncio.sleep(0.05)
        else:
            raise AssertionError("the TCP server did not listen")
        writer.write(message({"jsonrpc": "2.0", "id": 1, "method": "initialize",
                              "params": {"processId": None, "rootUri": None, "capabilities": {}}}))
        await writer.drain()
        result = (await response(reader, 1))["result"]
        assert result["serverInfo"]["name"] == "iface-lsp" and "hoverProvider" in result["capabilities"]
        writer.write(message({"jsonrpc": "2.0", "id": 2, "method": "shutdown"}))
        await writer.drain()
        await response(reader, 2)
        writer.close()
    finally:
        if proc.returncode is None:
            proc.terminate()
        await proc.wait()


@pytest_lsp.fixture(config=CONFIG, scope="module")
async def slow_client(lsp_client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    root = tmp_path_factory.mktemp("slow")
    shutil.copy(DATA / "common.iface", root / "common.iface")
    await start(lsp_client, root, "visual-studio-code", {"diagnosticsDelay": 1500})
    yield
    await lsp_client.shutdown_session()


async def test_requests_before_the_check_use_the_last_one_through_the_edits(slow_client: Client) -> None:
    client = slow_client
    uri = client.open("arm.iface", (DATA / "arm.iface").read_text(encoding="utf-8"))
    await client.wait_diagnostics(uri, 1)
    # two lines typed at the top; the next check is 1.5 s away
    version = client.edit(uri, (0, 0), (0, 0), "// one\n// two 𝔸\n")
    client.texts[uri] = "// one\n// two 𝔸\n" + client.texts[uri]
    hover = await client.text_document_hover_async(lsp.HoverParams(client.doc(uri), client.pos(uri, "Vec3", 1)))
    assert hover is not None and hover.range is not None and "A point in space." in hover.contents.value
    assert (hover.range.start.line, hover.range.start.character) == (10, 4)  # `common.Vec3`
    found = await client.text_document_definition_async(
        lsp.DefinitionParams(client.doc(uri), client.pos(uri, "Pose goal", 1)))
    assert found and found[0].range.start.line == 8
    assert version not in {p.version for p in client.published if p.uri == uri}  # not checked yet
    await client.wait_diagnostics(uri, version)
