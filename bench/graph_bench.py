"""Benchmark: the built-in layout of the system graph (``graph --format svg --layout builtin``).

Run: ``python bench/graph_bench.py`` — lays out synthetic systems of growing size and prints
the time, the size of the drawing and the ratio of the time to the previous size's. Two shapes: a pipeline (components in stages, each publishing
to the next stage, as ROS systems mostly are) and a random wiring (links between any two
components: long links, many crossings; the worst case of a layered layout, whose work grows
with links × columns crossed).
"""

from __future__ import annotations

import gc
import os
import random
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "server"))

from iface.compat.layout import Box, Edge, layered  # noqa: E402


def pipeline(n: int) -> tuple[list[Box], list[Edge]]:
    """``n`` components in stages of 5, each linked to two components of the next stage."""
    rnd = random.Random(n)
    boxes = [Box(f"c{i}", rnd.uniform(90, 160), 44) for i in range(n)]
    edges = []
    for i in range(n - 5):
        for k in (5, 5 + rnd.randrange(1, 5)):
            if i + k < n:
                edges.append(Edge(f"e{len(edges)}", f"c{i}", f"c{i + k}", rnd.uniform(80, 200), 30))
    return boxes, edges


def scattered(n: int) -> tuple[list[Box], list[Edge]]:
    """``n`` components, ``2n`` links between random pairs."""
    rnd = random.Random(n)
    boxes = [Box(f"c{i}", rnd.uniform(90, 160), 44) for i in range(n)]
    edges = [Edge(f"e{k}", f"c{rnd.randrange(n)}", f"c{rnd.randrange(n)}", rnd.uniform(80, 200), 30)
             for k in range(2 * n)]
    return boxes, edges


def main() -> None:
    for name, shape, sizes in (("pipeline", pipeline, (20, 100, 500)), ("random", scattered, (20, 50, 100))):
        previous, prev_n = None, 1
        for n in sizes:
            boxes, edges = shape(n)
            gc.collect()
            t = time.perf_counter()
            lay = layered(boxes, edges)
            took = time.perf_counter() - t
            ratio = f"  x{took / previous:.1f} for x{n // prev_n} components" if previous else ""
            print(f"{name:8} {n:4} components {len(edges):5} links: {took * 1000:8.1f} ms, "
                  f"{lay.width:8.0f} x {lay.height:6.0f} px{ratio}")
            previous, prev_n = took, n


if __name__ == "__main__":
    main()
