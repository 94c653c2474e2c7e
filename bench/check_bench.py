"""Benchmark: full check (parse, model, validation) against a bare lark LALR parse.

Run: ``python bench/check_bench.py`` — prints lines/s and the ratios the
speed issue asks for, measured in one run: check ≤ 0.7× a bare lark LALR parse
of the same text, and check of 50k lines ≤ 5.2× check of 10k (linear is 5.0).
"""

from __future__ import annotations

import gc
import os
import sys
import time
from collections.abc import Callable

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "server"))
sys.path.insert(0, os.path.dirname(__file__))

from gen_thrift import generate  # noqa: E402

from iface.model.source import Source  # noqa: E402
from iface.semantics.compile import compile_source  # noqa: E402
from iface.syntax.grammar import build_parser  # noqa: E402


def best(fn: Callable[[], object], repeat: int) -> float:
    """The best wall time of ``repeat`` runs, in seconds."""
    times = []
    for _ in range(repeat):
        gc.collect()
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    bare = build_parser(None)
    repeat = int(os.environ.get("BENCH_REPEAT", "5"))
    results = {}
    for lines in (10_000, 50_000):
        text = generate(lines)
        n = text.count("\n")
        t_bare = best(lambda: bare.parse(text), repeat)
        t_check = best(lambda: compile_source(Source("bench.thrift", text)), repeat)
        comp = compile_source(Source("bench.thrift", text))
        errors = [d for d in comp.diagnostics if d.severity == 1]
        assert not errors, errors[:3]
        results[lines] = (t_bare, t_check)
        print(f"{n:>6} lines: bare LALR parse {t_bare * 1000:8.1f} ms ({n / t_bare:8.0f} lines/s)   "
              f"full check {t_check * 1000:8.1f} ms ({n / t_check:8.0f} lines/s)   "
              f"check/bare {t_check / t_bare:5.2f}x (goal <= 0.7x{'' if t_check / t_bare <= 0.7 else ': MISSES'})")
    ratio = results[50_000][1] / results[10_000][1]
    print(f"check 50k / check 10k: {ratio:.2f}x (goal <= 5.2x{'' if ratio <= 5.2 else ': MISSES'}; linear is 5.0)")


if __name__ == "__main__":
    main()
