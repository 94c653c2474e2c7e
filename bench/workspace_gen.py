"""A generated workspace for workspace_bench.py: components that include shared type files.

``common_types.iface`` is included by half of the components; the other half
include one of nine ``geometry_K.iface`` files. Every component defines about
200 lines of its own messages, enums, services and settings, uses the shared
types and wires them. Deterministic for the same arguments.
"""

from __future__ import annotations

from pathlib import Path

SHARED = "common_types"
GEOMETRY = 9
_BASE = ("bool", "u8", "u16", "u32", "i32", "i64", "float32", "float64", "string")


def shared_text(name: str, kinds: int = 12) -> str:
    """A shared type file: messages and enums the components use."""
    out = [f"/** Types shared by many components ({name}). */", f"namespace ros2 {name}", ""]
    for k in range(kinds):
        out += [f"/** Shared message {k}. */", f"message Pose{k} {{", "    float64 x (unit = \"m\")",
                "    float64 y (unit = \"m\")", "    float64 yaw (unit = \"rad\")", f"    u32 seq_{k}", "}", ""]
        out += [f"enum Level{k} {{", "    OK = 0,", "    WARN = 1,", "    ERROR = 2,", "}", ""]
    return "\n".join(out)


def component_text(i: int, include: str, target_lines: int = 200) -> str:
    """One component of about ``target_lines`` lines that includes ``../types/<include>.iface``."""
    name = f"comp_{i:04d}"
    out = [f"/** Component {i}. */", f'component {name} version "1.0"', f"namespace ros2 {name}",
           f'include "../types/{include}.iface"', ""]
    wiring: list[str] = []
    j = 0
    while len(out) + len(wiring) < target_lines:
        kind = j % 4
        if kind in (0, 1):
            out += [f"/** Reading {j} of component {i}. */", f"message Reading{i}x{j} {{",
                    f"    {include}.Pose{j % 12} where", f"    {include}.Level{(j + 1) % 12} level = "
                    f"{include}.Level{(j + 1) % 12}.OK", f"    {_BASE[j % len(_BASE)]} value_{j}",
                    f"    {_BASE[(j + 3) % len(_BASE)]}[] history_{j}", "}", ""]
            direction = "publishes" if j % 2 else "subscribes"
            wiring.append(f'{direction} Reading{i}x{j} on "/{name}/reading_{j}"')
        elif kind == 2:
            out += [f"service Query{i}x{j} {{", "    request {", f"        {include}.Pose{j % 12} goal", "    }",
                    "    response {", "        bool ok", "    }", "}", ""]
            wiring.append(f'provides Query{i}x{j} on "/{name}/query_{j}"')
        else:
            out += [f"configuration Settings{i}x{j} {{",
                    '    float64 max_speed = 1.5 (unit = "m/s", range = "0..3")', "    u32 retries = 3", "}", ""]
        j += 1
    return "\n".join(out + wiring) + "\n"


def write(root: Path, files: int) -> tuple[int, int]:
    """Write the workspace of ``files`` files under ``root``; returns (files, lines)."""
    types = root / "types"
    comps = root / "components"
    types.mkdir(parents=True, exist_ok=True)
    comps.mkdir(parents=True, exist_ok=True)
    shared = [SHARED, *(f"geometry_{k}" for k in range(GEOMETRY))]
    texts = {types / f"{s}.iface": shared_text(s) for s in shared}
    count = max(files - len(shared), 2)
    for i in range(count):
        include = SHARED if i % 2 == 0 else shared[1 + (i // 2) % GEOMETRY]
        texts[comps / f"comp_{i:04d}.iface"] = component_text(i, include)
    lines = 0
    for path, text in texts.items():
        path.write_text(text, encoding="utf-8")
        lines += text.count("\n")
    return len(texts), lines
