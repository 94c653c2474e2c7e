"""The editor is never stale: after every change the published diagnostics equal a fresh compile's.

A property test over random edit sequences (insertions and deletions across lines, at line starts,
inside blocks and strings), each step compared with a fresh server state that opens the same text.
1,000 edits a run; ``IFACE_SOAK_EDITS=100000`` for a soak. The same code path the server uses for
didChange (``Project.change``) is driven in-process; test_robustness.py drives the real server.
"""

from __future__ import annotations

import asyncio
import os
import random
from pathlib import Path
from typing import Any

import pytest
from lsprotocol import types as lsp

from iface.lsp.documents import path_to_uri
from iface.lsp.project import Project
from iface.lsp.versions import names_of

from .harness import DATA
from .test_robustness import TOKENS, position, random_edit, ver

EDITS = int(os.environ.get("IFACE_SOAK_EDITS", "1000"))
#: Text typed where the problems showed: a constant, then Enter, at a line start inside a struct.
TYPED = "const i32 C = 9\n"
BLOCK_TOKENS = [*TOKENS, "const i32 C = 9", "u8 x", "1: i32 y,", '"a string"', "\\n", "}\nmessage N {"]


def _key(d: lsp.Diagnostic) -> tuple[Any, ...]:
    r = d.range
    return (r.start.line, r.start.character, r.end.line, r.end.character, d.code, d.severity, d.message)


class Recorder:
    """A project whose published diagnostics are kept per document."""

    def __init__(self) -> None:
        self.published: dict[str, tuple[int | None, list[lsp.Diagnostic]]] = {}
        self.project = Project(self._publish)

    def _publish(self, uri: str, version: int | None, diags: list[Any]) -> None:
        self.published[uri] = (version, diags)

    async def diagnostics(self, uri: str) -> list[tuple[Any, ...]]:
        latest = await self.project.latest(uri, fresh=True)
        assert latest is not None
        version, diags = self.published[uri]
        assert version == self.project.docs[uri].state.version
        return sorted(_key(d) for d in diags)


async def _fresh(uri: str, text: str) -> list[tuple[Any, ...]]:
    fresh = Recorder()
    try:
        fresh.project.open(uri, text, 1)
        return await fresh.diagnostics(uri)
    finally:
        fresh.project.model.shutdown(wait=True)


def _line_start_in_block(rng: random.Random, text: str) -> int | None:
    """The start of a line inside a ``{ … }`` block, if the text has one."""
    starts = [i + 1 for i, c in enumerate(text) if c == "\n"]
    inside = []
    depth = 0
    pos = 0
    for s in starts:
        depth += text.count("{", pos, s) - text.count("}", pos, s)
        pos = s
        if depth > 0:
            inside.append(s)
    return rng.choice(inside) if inside else None


async def _edit(rec: Recorder, uri: str, text: str, a: int, b: int, new: str, version: int) -> str:
    start, end = position(text, a), position(text, b)
    rec.project.change(uri, [lsp.TextDocumentContentChangePartial(range=lsp.Range(start=start, end=end), text=new)],
                       version)
    return text[:a] + new + text[b:]


@pytest.mark.asyncio
async def test_typing_a_constant_inside_a_struct_one_character_at_a_time(tmp_path: Path) -> None:
    rec = Recorder()
    uri = path_to_uri(str(tmp_path / "arm.iface"))
    (tmp_path / "common.iface").write_text((DATA / "common.iface").read_text(encoding="utf-8"), encoding="utf-8")
    text = (DATA / "arm.iface").read_text(encoding="utf-8")
    try:
        rec.project.open(uri, text, 1)
        await rec.diagnostics(uri)
        at = text.index("    float64 yaw")
        version = 1
        for ch in TYPED * 2:
            version += 1
            text = await _edit(rec, uri, text, at, at, ch, version)
            at += 1
            assert await rec.diagnostics(uri) == await _fresh(uri, text), f"after typing up to {text[at - 20:at]!r}"
    finally:
        rec.project.model.shutdown(wait=True)


@pytest.mark.asyncio
async def test_random_edits_leave_the_diagnostics_of_a_fresh_compile(tmp_path: Path) -> None:
    rng = random.Random(20261124)
    rec = Recorder()
    uri = path_to_uri(str(tmp_path / "fuzz.iface"))
    (tmp_path / "common.iface").write_text((DATA / "common.iface").read_text(encoding="utf-8"), encoding="utf-8")
    text = (DATA / "arm.iface").read_text(encoding="utf-8")
    try:
        rec.project.open(uri, text, 1)
        await rec.diagnostics(uri)
        version = 1
        original = text
        typing: list[tuple[int, str]] = []  # characters still to type, one per step
        for step in range(EDITS):
            roll = rng.random()
            if step % 60 == 59:  # back to a valid text now and then, so edits meet whole definitions
                a, b, new = 0, len(text), original
                typing = []
            elif typing:
                at, ch = typing.pop(0)
                a = b = min(at, len(text))
                new = ch
            elif roll < 0.15 and (at := _line_start_in_block(rng, text)) is not None:
                word = rng.choice(["const i32 C = 9\n", "struct X {\n", "message M {}\n", "}\n", "include \"x\"\n"])
                typing = [(at + k, c) for k, c in enumerate(word)]
                at, ch = typing.pop(0)
                a = b = at
                new = ch
            elif roll < 0.35 and (at := _line_start_in_block(rng, text)) is not None:
                a = b = at
                new = rng.choice(BLOCK_TOKENS) + rng.choice(["", "\n"])
            elif roll < 0.35 and text:
                a = rng.randint(0, len(text))
                b = min(len(text), a + rng.randint(1, 80))  # deletions across lines
                new = ""
            else:
                a, b, new = random_edit(rng, text)
            a, b = ver(text, a), ver(text, b)
            version += 1
            text = await _edit(rec, uri, text, a, b, new, version)
            if len(text) > 6000:  # keep the document near its size: drop a random stretch
                cut = rng.randint(0, len(text) - 3000)
                cut = ver(text, cut)
                version += 1
                text = await _edit(rec, uri, text, cut, ver(text, cut + 2000), "", version)
            got = await rec.diagnostics(uri)
            want = await _fresh(uri, text)
            assert got == want, f"step {step}: the published diagnostics differ from a fresh compile\n{text!r}"
            kept = rec.project.compiled[uri]
            if kept.comp is not None:  # completion's names, kept or spliced from the last version's, as made anew
                fresh = await rec.project.run(names_of, kept.comp)
                assert (kept.names, kept.topics) == fresh, f"step {step}: names differ\n{text!r}"
    finally:
        rec.project.model.shutdown(wait=True)
        await asyncio.sleep(0)
