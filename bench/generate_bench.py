"""Benchmark: ``iface-lsp generate`` of every example to every target, into a fresh folder, again over what
it wrote (every file unchanged) and with ``--check``.

Run: ``python bench/generate_bench.py [--rounds 5] [--depth 6]`` — the commands run in this process
(``iface.cli.main``, as ``iface-lsp generate`` runs them, without the interpreter's start), into a
temporary folder ``--depth`` folders deep (a project's build folder is rarely at the root). The three
modes take turns, round after round, and each keeps its best round (CPU time of this process:
``time.process_time``), so that a burst of load from other jobs does not land on one of them only.
Prints, per target, the files written and the milliseconds of each mode for all the examples, then the
totals and files per second.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "server"))

from iface.cli import main
from iface.emit.registry import targets

MODES = ("fresh", "again", "--check")


def generate(example: Path, target: str, out: Path, *extra: str) -> int:
    """``iface-lsp generate EXAMPLE -t TARGET -o OUT EXTRA…`` in this process; its exit code."""
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(["generate", str(example), "-t", target, "-o", str(out), *extra])


def one_round(examples: list[Path], target: str, base: Path) -> tuple[dict[str, float], int]:
    """CPU seconds of each mode over every example, and the number of files the fresh run wrote."""
    out = base / target
    shutil.rmtree(out, ignore_errors=True)
    seconds: dict[str, float] = {}
    for mode in MODES:
        start = time.process_time()
        for example in examples:
            generate(example, target, out / example.stem, *([mode] if mode.startswith("--") else []))
        seconds[mode] = time.process_time() - start
    files = sum(1 for p in out.rglob("*") if p.is_file())
    return seconds, files


def main_bench() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--depth", type=int, default=6)
    a = ap.parse_args()
    examples = sorted((ROOT / "examples").glob("*.iface"))  # the system file's target is launch
    names = sorted(targets())
    best: dict[str, dict[str, float]] = {t: dict.fromkeys(MODES, float("inf")) for t in names}
    files: dict[str, int] = {}
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp).joinpath(*(f"level{i}" for i in range(a.depth)))
        for _ in range(a.rounds):
            for target in names:
                seconds, files[target] = one_round(examples, target, base)
                for mode, s in seconds.items():
                    best[target][mode] = min(best[target][mode], s)
    print(f"{len(examples)} examples, best of {a.rounds} rounds, CPU ms (python {sys.version.split()[0]}, "
          f"{os.cpu_count()} cores)")
    print(f"{'target':<12} {'files':>6} " + " ".join(f"{m:>9}" for m in MODES))
    for target in names:
        print(f"{target:<12} {files[target]:>6} " + " ".join(f"{best[target][m] * 1000:>9.0f}" for m in MODES))
    total = {m: sum(best[t][m] for t in names) for m in MODES}
    count = sum(files.values())
    print(f"{'all':<12} {count:>6} " + " ".join(f"{total[m] * 1000:>9.0f}" for m in MODES))
    print("files/s      " + " ".join(f"{count / total[m]:>9.0f}" for m in MODES))
    return 0


if __name__ == "__main__":
    sys.exit(main_bench())
