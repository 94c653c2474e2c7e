"""Generate a large, valid Thrift file of about N lines for benchmarks."""

from __future__ import annotations

import sys


def generate(lines: int) -> str:
    """A Thrift text of roughly ``lines`` lines mixing every kind of definition."""
    out: list[str] = ["namespace cpp bench", "namespace py bench", ""]
    i = 0
    while len(out) < lines:
        out += [
            f"/** Enum number {i}. */",
            f"enum Kind{i} {{",
            "  ALPHA = 1,",
            "  BETA = 2,",
            "  GAMMA",
            "}",
            "",
            f"const i32 LIMIT_{i} = {i * 7 + 3}",
            f"typedef list<string> Names{i}",
            "",
            f"/** Struct number {i}. */",
            f"struct Record{i} {{",
            "  1: required i64 id,",
            f"  2: optional string name = \"record {i}\",",
            "  3: list<double> values,",
            "  4: map<string, i32> counts,",
            f"  5: Kind{i} kind = Kind{i}.BETA,",
            f"  6: Names{i} aliases,",
            "  7: set<i16> flags (cpp.type = \"std::set<int16_t>\"),",
            "}",
            "",
            f"exception Failure{i} {{",
            "  1: string message,",
            "  2: i32 code",
            "}",
            "",
            f"service Store{i} {{",
            f"  Record{i} get(1: i64 id) throws (1: Failure{i} failure),",
            f"  void put(1: Record{i} record),",
            "  oneway void ping()",
            "}",
            "",
        ]
        i += 1
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.stdout.write(generate(int(sys.argv[1]) if len(sys.argv) > 1 else 10000))
