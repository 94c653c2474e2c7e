"""Benchmark: inputs that used to take quadratic time or unbounded memory, at 10k and 50k.

Run: ``python bench/hardening_bench.py`` — for each input shape prints the time at
10,000 and 50,000 (lines, names or brackets), their ratio (linear is about 5x;
quadratic would be 25x) and the peak memory Python allocated at 50k (tracemalloc,
measured in a separate run so that it does not slow the timed ones).

Shapes (issue 15, "Linear time and bounded memory"):

- ``unknown types, one struct``: one struct of N fields, each of its own unknown type (did-you-mean);
- ``unknown types, N structs``: N one-field structs, each with its own unknown type (did-you-mean);
- ``fmt N lines``: formatting the generated N-line Thrift file of ``check_bench.py``;
- ``fmt one line``: formatting one line of N fields, each with a block comment;
- ``N definitions with syntax errors``: each also with an unknown type (findings inside broken
  definitions are dropped);
- ``[ x N``: ``const list<i32> X = [[[…`` never closed;
- ``/* + N lines``: an unterminated block comment before 3N lines of definitions (3.3 MB at 50k).

``BENCH_REPEAT`` (default 3) sets how many runs each time is the best of.
"""

from __future__ import annotations

import gc
import os
import sys
import tracemalloc
from collections.abc import Callable

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "server"))
sys.path.insert(0, os.path.dirname(__file__))

from check_bench import best  # noqa: E402
from gen_thrift import generate  # noqa: E402

from iface.model.source import Source  # noqa: E402
from iface.semantics.compile import compile_source  # noqa: E402
from iface.text.formatter import format_text  # noqa: E402


def unknown_in_one_struct(n: int) -> str:
    # no field ids: ids past 32767 would add findings at 50k that 10k does not have
    return "struct S {\n" + "".join(f"    T{i} f{i},\n" for i in range(n)) + "}\n"


def broken_definitions(n: int) -> str:
    return "".join(f"struct S{i} {{\n    Unknown{i} x\n    i32 = \n}}\n" for i in range(n))


def unknown_in_many_structs(n: int) -> str:
    return "".join(f"struct S{i} {{\n    1: Unknown{i} f\n}}\n" for i in range(n))


def one_line_with_comments(n: int) -> str:
    return "struct S { " + " ".join(f"{i + 1}: i32 f{i} /* note {i} */," for i in range(n)) + " }\n"


def open_brackets(n: int) -> str:
    return "const list<i32> X = " + "[" * n + "\n"


def open_comment(n: int) -> str:
    return "/*\n" + "struct S { 1: i32 x }\n" * (3 * n)


def check(text: str) -> Callable[[], object]:
    return lambda: compile_source(Source("bench.thrift", text))


def fmt(text: str) -> Callable[[], object]:
    return lambda: format_text(text)


CASES: list[tuple[str, Callable[[int], str], Callable[[str], Callable[[], object]]]] = [
    ("check: unknown types, one struct", unknown_in_one_struct, check),
    ("check: unknown types, N structs", unknown_in_many_structs, check),
    ("fmt N lines", generate, fmt),
    ("fmt one line of N commented fields", one_line_with_comments, fmt),
    ("check: N definitions with syntax errors", broken_definitions, check),
    ("check: [ x N, never closed", open_brackets, check),
    ("check: /* + 3N lines, never closed", open_comment, check),
    ("fmt /* + 3N lines, never closed", open_comment, fmt),
]


def peak_mb(fn: Callable[[], object]) -> float:
    """The most memory Python held while ``fn`` ran, in MB."""
    gc.collect()
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 1e6
    finally:
        tracemalloc.stop()


def main() -> None:
    repeat = int(os.environ.get("BENCH_REPEAT", "3"))
    print(f"{'input':<38} {'10k':>9} {'50k':>9} {'50k/10k':>8} {'input 50k':>10} {'peak 50k':>9}")
    for name, make, run in CASES:
        small, large = make(10_000), make(50_000)
        t10 = best(run(small), repeat)
        t50 = best(run(large), repeat)
        peak = peak_mb(run(large))
        print(f"{name:<38} {t10 * 1000:7.0f}ms {t50 * 1000:7.0f}ms {t50 / t10:7.2f}x {len(large) / 1e6:8.2f}MB "
              f"{peak:7.1f}MB")


if __name__ == "__main__":
    main()
