"""Benchmark: the language server's memory over many edits and opened/closed documents.

Run ``python bench/memory_soak.py`` (``--edits N``, ``--lines L``, ``--docs D``). It opens a
generated document of L lines (10,000 by default), makes N edits (2,400) that insert and remove a
broken line (a syntax error every other version), waiting for each version's diagnostics, then
opens and closes D small documents (200), printing the server's resident memory as it goes and the
growth per 1,000 edits. A server that keeps nothing per edit stays flat once warm (a leak of one
pygls future per notification grew it by about 2.3 MB per 1,000 edits). A benchmark, not a test:
the tests check what is cached by its contents.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import tempfile
from pathlib import Path

from lsprotocol import types as lsp

sys.path.insert(0, str(Path(__file__).parent))
from lsp_bench import OURS, change, field_line, rss_mb, start, stop  # noqa: E402
from lsp_gendoc import generate  # noqa: E402

BROKEN = "    struct { oops [\n"


def opened(uri: str, text: str) -> lsp.DidOpenTextDocumentParams:
    return lsp.DidOpenTextDocumentParams(lsp.TextDocumentItem(uri=uri, language_id="iface", version=1, text=text))


async def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--edits", type=int, default=2400)
    ap.add_argument("--lines", type=int, default=10_000)
    ap.add_argument("--docs", type=int, default=200)
    args = ap.parse_args()
    root = Path(tempfile.mkdtemp(prefix="iface-soak-"))
    text = generate(args.lines)
    uri = (root / "big.iface").as_uri()
    probe, _ = await start(OURS, root)
    probe.client.text_document_did_open(opened(uri, text))
    await probe.diagnostics(1)
    line = field_line(text, 0)
    samples: list[tuple[int, float]] = []
    step = max(args.edits // 12, 1)
    for i in range(args.edits):
        probe.client.text_document_did_change(change(uri, i + 2, line + (i // 2) % 50, BROKEN, delete=i % 2 == 1))
        await probe.diagnostics(i + 2)
        if i % step == 0:
            samples.append((i, rss_mb(probe)))
            print(f"after {i:6d} edits: {samples[-1][1]:7.1f} MB", flush=True)
    samples.append((args.edits, rss_mb(probe)))
    print(f"after {args.edits:6d} edits: {samples[-1][1]:7.1f} MB")
    for k in range(args.docs):
        small = (root / f"s{k}.iface").as_uri()
        probe.client.text_document_did_open(opened(small, generate(300, seed=k)))
        probe.client.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(uri=small)))
    await asyncio.sleep(3)
    print(f"after {args.docs} small documents opened and closed: {rss_mb(probe):7.1f} MB")
    half = samples[len(samples) // 2]
    growth = (samples[-1][1] - half[1]) * 1000 / max(samples[-1][0] - half[0], 1)
    print(f"growth over the second half of the edits: {growth:.2f} MB per 1,000 edits (goal: about 0)")
    await stop(probe)
    return 0


if __name__ == "__main__":
    sys.exit(asyncio.run(main()))
