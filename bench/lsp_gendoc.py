"""A generated, valid `.iface` document of about N lines, for benchmarks."""

from __future__ import annotations

import random

_BASE = ("bool", "u8", "u16", "u32", "i32", "i64", "float32", "float64", "string", "string<=32")


def _message(i: int, rng: random.Random, names: list[str]) -> list[str]:
    lines = [f"/** Message number {i}: a reading of sensor {i}. */", f"message Reading{i} {{"]
    for j in range(rng.randint(4, 9)):
        if names and rng.random() < 0.3:
            t = rng.choice(names[-20:])
        else:
            t = rng.choice(_BASE)
        suffix = rng.choice(("", "", "", "[]", "[4]", "[<=8]"))
        lines.append(f"    {t}{suffix} field_{j}")
    lines.append("    const u8 MAX_COUNT = 3")
    lines.append("}")
    lines.append("")
    return lines


def _enum(i: int) -> list[str]:
    return [f"enum Mode{i} {{", "    IDLE = 0,", "    RUNNING = 1,", "    FAULT = 2,", "}", ""]


def _service(i: int, names: list[str]) -> list[str]:
    arg = names[-1] if names else "u32"
    return [f"/** Service {i}. */", f"service Query{i} {{", "    request {", f"        {arg} input",
            "        u32 count", "    }", "    response {", "        bool ok", "        string message",
            "    }", "}", ""]


def _configuration(i: int) -> list[str]:
    return [f"configuration Settings{i} {{",
            '    float64 max_speed = 1.5 (unit = "m/s", range = "0..3")',
            '    u32 retries = 3 (min = "0", max = "10")', "}", ""]


def generate(target_lines: int = 10_000, seed: int = 7) -> str:
    """About ``target_lines`` lines of valid iface text, the same for the same seed."""
    rng = random.Random(seed)
    out = ["/** A large generated component. */", 'component big_robot version "1.0"', "",
           "namespace ros2 big_robot", ""]
    names: list[str] = []
    wiring: list[str] = []
    i = 0
    while len(out) + len(wiring) < target_lines:
        kind = i % 6
        if kind in (0, 1, 2):
            out.extend(_message(i, rng, names))
            names.append(f"Reading{i}")
            direction = "publishes" if i % 2 else "subscribes"
            wiring.append(f'{direction} Reading{i} on "/sensors/reading_{i}"')
        elif kind == 3:
            out.extend(_enum(i))
            names.append(f"Mode{i}")
        elif kind == 4:
            out.extend(_service(i, [n for n in names if n.startswith("Reading")]))
            wiring.append(f'provides Query{i} on "/query_{i}"')
        else:
            out.extend(_configuration(i))
        i += 1
    return "\n".join(out + wiring) + "\n"


if __name__ == "__main__":
    print(generate(), end="")
