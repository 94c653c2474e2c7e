"""Bounds of the server: the file size limit, a cap on findings per file, and nothing kept for closed documents."""

from __future__ import annotations

import asyncio
import concurrent.futures
import gc
import tracemalloc
from pathlib import Path
from typing import Any

import lark
import pytest
from lsprotocol import types as lsp

import iface
from iface.lsp.documents import path_to_uri
from iface.lsp.findings import MAX_DIAGNOSTICS
from iface.lsp.project import Project
from iface.semantics.compile import MAX_FILE_BYTES

from .harness import Client

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_a_document_over_the_size_limit_gets_one_diagnostic_and_is_not_read(client: Client) -> None:
    line = "message M%d { u8 a }\n"
    text = "".join(line % i for i in range(MAX_FILE_BYTES // len(line % 0) + 10_000))
    assert len(text.encode()) > MAX_FILE_BYTES
    uri = client.open("huge.iface", text)
    found = await client.wait_diagnostics(uri, 1)
    assert [d.code for d in found] == ["file-too-large"], found[:3]
    assert "iface reads interface files up to 4 MB" in found[0].message
    edits = await client.text_document_formatting_async(lsp.DocumentFormattingParams(
        client.doc(uri), lsp.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits
    tokens = await client.text_document_semantic_tokens_full_async(lsp.SemanticTokensParams(client.doc(uri)))
    assert tokens is None or not tokens.data
    folds = await client.text_document_folding_range_async(lsp.FoldingRangeParams(client.doc(uri)))
    assert not folds
    client.close(uri)


async def test_findings_per_file_are_capped_with_one_that_counts_the_rest(client: Client) -> None:
    count = MAX_DIAGNOSTICS + 123
    text = "".join(f"struct S{i} {{ 1: Missing{i} a }}\n" for i in range(count))
    uri = client.open("many.iface", text)
    found = await client.wait_diagnostics(uri, 1)
    assert len(found) == MAX_DIAGNOSTICS + 1
    assert [d.code for d in found[:MAX_DIAGNOSTICS]] == ["unknown-type"] * MAX_DIAGNOSTICS
    last = found[-1]
    assert last.code == "too-many-findings" and "and 123 more finding(s)" in last.message
    assert last.range.start.line == MAX_DIAGNOSTICS
    client.close(uri)


async def _compiled(project: Project, uri: str) -> None:
    assert await project.view(uri, lambda view: view.ver.comp is not None, fresh=True)


async def test_closing_documents_releases_what_was_cached_for_them(tmp_path: Path) -> None:
    """300 opened and closed documents leave nothing cached; an included file stays while its includer is open."""
    published: list[Any] = []
    project = Project(lambda uri, version, diags: published.append(uri))
    shared = tmp_path / "shared.iface"
    shared.write_text("namespace ros2 shared\nstruct Vec { 1: float64 x }\n")
    body = "".join(f"struct T{i} {{ 1: i32 a, 2: string b }}\n" for i in range(200))
    try:
        for i in range(300):
            uri = path_to_uri(str(tmp_path / f"doc{i}.iface"))
            project.open(uri, f'include "shared.iface"\nstruct D{i} {{ 1: shared.Vec v }}\n' + body, 1)
            await _compiled(project, uri)
            project.close(uri)
        await project.run(lambda: None)  # the model thread has released them
        assert project.workspace().cached_paths() == set()
        assert not project.docs and not project.compiled and not project.line_indexes

        keeper = path_to_uri(str(tmp_path / "keeper.iface"))
        project.open(keeper, 'include "shared.iface"\nstruct K { 1: shared.Vec v }\n', 1)
        await _compiled(project, keeper)
        other = path_to_uri(str(tmp_path / "other.iface"))
        project.open(other, 'include "shared.iface"\nstruct O { 1: shared.Vec v }\n', 1)
        await _compiled(project, other)
        project.close(other)
        await project.run(lambda: None)
        cached = project.workspace().cached_paths()
        assert str(shared) in cached and str(tmp_path / "keeper.iface") in cached
        assert str(tmp_path / "other.iface") not in cached
        project.close(keeper)
        await project.run(lambda: None)
        assert project.workspace().cached_paths() == set()
    finally:
        project.model.shutdown(wait=True)
        await asyncio.sleep(0)


def _generated(lines: int) -> str:
    """About ``lines`` lines of valid text: messages that use each other, enums and wirings."""
    out = ['component big version "1.0"', ""]
    i = 0
    while len(out) < lines:
        used = f"Reading{i - 1} previous" if i else "string name"
        out += [f"/** Message {i}. */", f"message Reading{i} {{", "    u8 count", f"    float64[] value_{i % 7}",
                f"    {used}", "}", "", f"enum Mode{i} {{", "    IDLE = 0,", "    RUNNING = 1,", "}", "",
                f'publishes Reading{i} on "/r/{i}"']
        i += 1
    return "\n".join(out) + "\n"


#: The code whose allocations make a document's model: iface's and the parser's (lark).
MODEL_CODE = [tracemalloc.Filter(True, str(Path(iface.__file__).parent / "*")),
              tracemalloc.Filter(True, str(Path(lark.__file__).parent / "*"))]


async def _open_document_bytes(tmp_path: Path, lines: int, project: Project | None = None) -> tuple[int, int]:
    """(bytes Python holds for one open, compiled document of about ``lines`` lines, its characters).

    Only what iface's and lark's code allocated is counted (``MODEL_CODE``): tracemalloc sees every thread and
    task of the process, and a worker under load once counted 77.5 bytes a character at 6,000 lines against 33.1
    at 1,500 (answers of the session's language server arriving meanwhile, held by its client).
    """
    project = project or Project(lambda uri, version, diags: None)
    try:
        warm = path_to_uri(str(tmp_path / f"warm{lines}.iface"))
        project.open(warm, _generated(40), 1)  # what is built once per process or project is not counted
        await _compiled(project, warm)
        text = _generated(lines)
        uri = path_to_uri(str(tmp_path / f"big{lines}.iface"))
        gc.collect()
        tracemalloc.start()
        try:
            project.open(uri, text, 1)
            await _compiled(project, uri)
            gc.collect()
            held = sum(t.size for t in tracemalloc.take_snapshot().filter_traces(MODEL_CODE).traces)
        finally:
            tracemalloc.stop()
        return held, len(text)
    finally:
        project.model.shutdown(wait=True)
        await asyncio.sleep(0)


async def test_an_open_documents_memory_grows_linearly_with_its_text(tmp_path: Path) -> None:
    """What an open document holds (text, model, analysis, compiled version) is the same per character at 1,500 and
    6,000 lines: a structure that grows faster than the text (per-line lists of growing objects, tables
    kept per pair of items) shows as a larger share at 6,000. Live objects are counted, not resident memory,
    which grows by steps and keeps what a parse freed (``bench/lsp_bench.py`` reports that)."""
    small, small_chars = await _open_document_bytes(tmp_path, 1_500)
    large, large_chars = await _open_document_bytes(tmp_path, 6_000)
    per_small, per_large = small / small_chars, large / large_chars
    assert per_large <= 1.15 * per_small, f"{per_small:.1f} bytes a character at 1,500 lines, {per_large:.1f} at 6,000"


KEPT_BESIDE: list[bytearray] = []


async def test_the_memory_count_is_the_models_not_what_else_the_process_keeps_meanwhile(tmp_path: Path) -> None:
    """20 MB kept by other code while the document compiles (here: at its findings) is not counted."""
    project = Project(lambda uri, version, diags: None)
    made = project.findings.of

    def findings_beside_other_work(*args: Any) -> Any:
        if "big" in str(args[0]):
            KEPT_BESIDE.append(bytearray(20_000_000))
        return made(*args)

    project.findings.of = findings_beside_other_work  # type: ignore[method-assign]
    try:
        held, chars = await _open_document_bytes(tmp_path, 200, project)
    finally:
        KEPT_BESIDE.clear()
    assert 10 * chars < held < 5_000_000, f"{held:,} bytes counted for a document of {chars:,} characters"


async def test_notifications_leave_no_future_behind(tmp_path: Path) -> None:
    """Every didOpen/didChange/didClose used to leave its future in pygls' table of pending requests."""
    from iface.lsp.server import build

    server = build()
    protocol = server.protocol
    protocol.set_writer(type("Sink", (), {"write": lambda self, data: None, "close": lambda self: None})())
    protocol.initialized = True
    uri = path_to_uri(str(tmp_path / "a.iface"))

    def notify(method: str, params: dict[str, Any]) -> None:
        protocol.handle_message(protocol.structure_message({"jsonrpc": "2.0", "method": method, "params": params}))

    def futures() -> int:
        gc.collect()
        return sum(1 for o in gc.get_objects() if isinstance(o, (asyncio.Future, concurrent.futures.Future)))

    try:
        before = futures()
        notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "iface", "version": 1,
                                                         "text": "struct S { 1: i32 a }\n"}})
        for version in range(2, 202):
            notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": version}, "contentChanges": [
                {"range": {"start": {"line": 1, "character": 0}, "end": {"line": 1, "character": 0}}, "text": "x"}]})
        notify("textDocument/didClose", {"textDocument": {"uri": uri}})
        await server.project.run(lambda: None)
        assert futures() - before < 20  # 202 notifications: one future kept for each, when they leaked
    finally:
        server.project.model.shutdown(wait=True)


async def test_ended_progress_leaves_no_token_behind() -> None:
    """pygls keeps every work-done token it registered (its issue #607); ours are dropped at the end."""
    from types import SimpleNamespace

    from pygls.progress import Progress as PyglsProgress

    from iface.lsp.progress import Progress

    sent: list[Any] = []

    async def answer(method: str, params: Any) -> None:
        sent.append(method)

    protocol = SimpleNamespace(send_request_async=answer, notify=lambda method, params: sent.append(method))
    server = SimpleNamespace(work_done_progress=PyglsProgress(protocol),  # type: ignore[arg-type]
                             client_capabilities=lsp.ClientCapabilities(
                                 window=lsp.WindowClientCapabilities(work_done_progress=True)))
    for _ in range(3):
        progress = Progress(server, "Indexing interface files")  # type: ignore[arg-type]
        await progress.begin(10)
        progress.report(5, 10)
        progress.end("done")
    assert sent.count("$/progress") == 9
    assert server.work_done_progress.tokens == {}
