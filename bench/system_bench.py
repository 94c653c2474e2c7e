"""Benchmark: a system file of growing size — compile and check it, its system graph's findings, ``system_spec``
and the launch file.

Run: ``python bench/system_bench.py`` — writes synthetic systems (one component file per 5 instances,
each component publishing one topic of a shared type and subscribing the previous one's, the instances
in a chain of ``after``) to a temporary folder and prints, per size, the time of each step and the
ratio to the previous size's.
"""

from __future__ import annotations

import gc
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "server"))

from iface.compat.systemfile import system_findings  # noqa: E402
from iface.nodes.launch import generate  # noqa: E402
from iface.nodes.system import spec_of  # noqa: E402
from iface.semantics.compile import Workspace  # noqa: E402


def write_system(root: Path, n: int) -> Path:
    """``n`` instances of ``n // 5`` components; returns the system file."""
    kinds = max(1, n // 5)
    (root / "types.iface").write_text("namespace ros2 bench_msgs\n\nmessage Reading { float64 value }\n",
                                      encoding="utf-8")
    for k in range(kinds):
        previous = f'subscribes types.Reading on "/stage{k - 1}"\n' if k else ""
        (root / f"part{k}.iface").write_text(
            f"component part{k} version \"1.0.0\"\nnamespace ros2 part{k}_msgs\ninclude \"types.iface\"\n\n"
            f"state s {{ i64 n }}\n\npublishes types.Reading on \"/stage{k}\"\n{previous}", encoding="utf-8")
    lines = [f"system bench{n} version \"1.0.0\""]
    lines += [f"include \"part{k}.iface\"" for k in range(kinds)]
    lines.append("")
    for i in range(n):
        after = f' (after = "i{i - 1}", snapshot = "1s")' if i else ""
        lines.append(f"instance i{i} : part{i % kinds}{after}")
    path = root / f"bench{n}.iface"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def timed(fn, *args):  # type: ignore[no-untyped-def]
    gc.collect()
    t = time.perf_counter()
    value = fn(*args)
    return value, time.perf_counter() - t


def main() -> None:
    previous: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in (20, 100, 500):
            folder = Path(tmp) / str(n)
            folder.mkdir()
            path = write_system(folder, n)
            comp, t_check = timed(lambda p: Workspace().compile_path(str(p)), path)
            found, t_graph = timed(system_findings, comp)
            spec, t_spec = timed(spec_of, comp)
            result, t_launch = timed(generate, comp, {"out": str(folder)})
            assert not found and len(spec.instances) == n and len(result.files) == 1
            figures = {"check": t_check, "graph findings": t_graph, "system_spec": t_spec, "launch": t_launch}
            shown = ", ".join(f"{k} {v * 1000:7.1f} ms" + (f" (x{v / previous[k]:.1f})" if k in previous else "")
                              for k, v in figures.items())
            print(f"{n:4} instances: {shown}")
            previous = figures


if __name__ == "__main__":
    main()
