"""The workspace as a whole: indexed at start with ``$/progress``, symbols and references in files that are
not open, and the files that include an edited file re-checked after it, the newest edit first."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import pytest
import pytest_lsp
from lsprotocol import types as lsp

from iface.lsp.documents import path_to_uri
from iface.lsp.project import Project

from .harness import CONFIG, Client, start

pytestmark = pytest.mark.asyncio(loop_scope="module")

COMPONENTS = 12
SHARED = "namespace ros2 shared\n\nmessage Vec {\n    float64 x\n}\n\nenum Level {\n    OK = 0,\n}\n"


def component(i: int) -> str:
    """A component that uses the shared file's types."""
    return (f'component user_{i} version "1.0"\ninclude "../types/shared.iface"\n\n'
            f"message Reading{i} {{\n    shared.Vec where\n    shared.Level level\n}}\n\n"
            f'publishes Reading{i} on "/user_{i}/reading"\n')


def write_workspace(root: Path) -> None:
    (root / "types").mkdir()
    (root / "types" / "shared.iface").write_text(SHARED, encoding="utf-8")
    (root / "components").mkdir()
    for i in range(COMPONENTS):
        (root / "components" / f"user_{i}.iface").write_text(component(i), encoding="utf-8")


@pytest_lsp.fixture(config=CONFIG, scope="module")
async def ws_client(lsp_client: Client, tmp_path_factory: pytest.TempPathFactory) -> AsyncIterator[None]:
    root = tmp_path_factory.mktemp("many")
    write_workspace(root)
    await start(lsp_client, root, "visual-studio-code")
    yield
    await lsp_client.shutdown_session()


async def indexed(client: Client) -> None:
    """Wait for the workspace index (workspace symbols answer once it is complete)."""
    await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query="Reading0"))


async def test_indexing_at_start_reports_progress(ws_client: Client) -> None:
    client = ws_client
    await indexed(client)
    assert len(client.progress_reports) == 1, client.progress_reports
    (reports,) = client.progress_reports.values()
    assert isinstance(reports[0], lsp.WorkDoneProgressBegin) and "Indexing" in reports[0].title
    assert isinstance(reports[-1], lsp.WorkDoneProgressEnd)
    assert f"{COMPONENTS + 1} interface files indexed" in (reports[-1].message or "")
    middle = [r for r in reports[1:-1] if isinstance(r, lsp.WorkDoneProgressReport)]
    assert middle and middle[-1].message == f"{COMPONENTS + 1}/{COMPONENTS + 1} files"
    assert [r.percentage for r in middle] == sorted(r.percentage for r in middle)


async def test_workspace_symbols_find_a_definition_in_a_file_that_is_not_open(ws_client: Client) -> None:
    client = ws_client
    await indexed(client)
    assert not client.versions  # nothing is open
    found = await client.workspace_symbol_async(lsp.WorkspaceSymbolParams(query="Reading7"))
    assert found and [s.name for s in found] == ["Reading7"]
    assert found[0].location.uri == client.uri("components/user_7.iface")


async def test_references_reach_every_file_that_uses_a_shared_type(ws_client: Client) -> None:
    client = ws_client
    await indexed(client)
    uri = client.open("components/user_3.iface")
    await client.wait_diagnostics(uri, 1)
    found = await client.text_document_references_async(lsp.ReferenceParams(
        text_document=client.doc(uri), position=client.pos(uri, "shared.Vec", len("shared.")),
        context=lsp.ReferenceContext(include_declaration=True)))
    assert found is not None
    files = sorted({loc.uri for loc in found})
    expected = sorted([client.uri("types/shared.iface"),
                       *(client.uri(f"components/user_{i}.iface") for i in range(COMPONENTS))])
    assert files == expected
    assert len(found) == COMPONENTS + 1  # one use per component and the declaration
    client.close(uri)


async def test_an_edit_of_an_included_file_rechecks_its_open_dependents_after_it(ws_client: Client) -> None:
    client = ws_client
    await indexed(client)
    opened = client.mark()
    shared = client.open("types/shared.iface")
    await client.wait_diagnostics(shared, 1, after=opened)
    users = [client.open(f"components/user_{i}.iface") for i in range(4)]
    for uri in users:
        assert await client.wait_diagnostics(uri, 1, after=opened) == []
    mark = client.mark()
    version = client.replace(shared, SHARED.replace("message Vec", "message Vector"))
    await client.wait_diagnostics(shared, version, after=mark)
    for uri in users:
        found = await client.wait_diagnostics(uri, after=mark, until=bool)
        assert [d.code for d in found] == ["unknown-type"]
    order = [p.uri for p in client.published[mark:]]
    assert order.index(shared) < min(order.index(u) for u in users)  # its own diagnostics come first
    mark = client.mark()
    version = client.replace(shared, SHARED)
    await client.wait_diagnostics(shared, version, after=mark)
    for uri in users:
        assert await client.wait_diagnostics(uri, after=mark, until=lambda d: not d) == []
    for uri in [*users, shared]:
        client.close(uri)


# ---- the scheduler, in-process: which compile goes next is decided on the event loop ------------------


class Recorder:
    """A project whose publications are kept in order."""

    def __init__(self) -> None:
        self.published: list[tuple[str, int | None, list[Any]]] = []
        self.on_publish: Any = None
        self.arrived = asyncio.Event()
        self.project = Project(self._publish)

    def _publish(self, uri: str, version: int | None, diags: list[Any]) -> None:
        self.published.append((uri, version, diags))
        self.arrived.set()
        if self.on_publish is not None:
            self.on_publish(uri, version)

    async def until(self, done: Any) -> None:
        """Wait (bounded) until ``done()`` holds after some publication."""
        async with asyncio.timeout(30):
            while not done():
                self.arrived.clear()
                await self.arrived.wait()


async def test_a_second_edit_goes_before_dependents_still_waiting_and_nothing_stays_stale(tmp_path: Path) -> None:
    write_workspace(tmp_path)
    rec = Recorder()
    project = rec.project
    shared = path_to_uri(str(tmp_path / "types" / "shared.iface"))
    users = [path_to_uri(str(tmp_path / "components" / f"user_{i}.iface")) for i in range(COMPONENTS)]
    try:
        for i, uri in enumerate(users):
            project.open(uri, component(i), 1)
        project.open(shared, SHARED, 1)
        for uri in [*users, shared]:
            assert await project.latest(uri, fresh=True) is not None

        def settled() -> bool:  # the dependents were re-checked after the shared file's first compile
            at = [i for i, (u, _, _) in enumerate(rec.published) if u == shared]
            return bool(at) and {u for u, _, _ in rec.published[at[0] + 1:]} >= set(users)

        await rec.until(settled)
        await project.run(lambda: None)
        mark = len(rec.published)
        second: list[int] = []

        def second_edit_after_the_first_dependent(uri: str, version: int | None) -> None:
            if uri in users and not second:
                second.append(len(rec.published) - mark)
                project.change(shared, [lsp.TextDocumentContentChangeWholeDocument(text=SHARED)], 3)

        def all_checked_after_the_second() -> bool:
            at = [i for i, (u, v, _) in enumerate(rec.published) if u == shared and v == 3]
            return bool(at) and {u for u, _, _ in rec.published[at[0] + 1:]} >= set(users)

        rec.on_publish = second_edit_after_the_first_dependent
        broken = SHARED.replace("message Vec", "message Vector")
        project.change(shared, [lsp.TextDocumentContentChangeWholeDocument(text=broken)], 2)
        await rec.until(all_checked_after_the_second)
        seq = [(u, v) for u, v, _ in rec.published[mark:]]
        assert seq[0] == (shared, 2)
        assert seq[1][0] in users and [x.code for x in rec.published[mark + 1][2]] == ["unknown-type"]
        # the second edit was compiled next, before the dependents still waiting from the first
        assert second == [2] and seq[2] == (shared, 3), seq[:4]
        last = {u: d for u, _, d in rec.published if u in users}
        assert all(d == [] for d in last.values()), {u: [x.code for x in d] for u, d in last.items() if d}
    finally:
        project.model.shutdown(wait=True)
        await asyncio.sleep(0)
