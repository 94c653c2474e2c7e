"""A layered (Sugiyama-style) layout of a directed graph, left to right, in pure Python.

Boxes are placed in columns (ranks) so that most edges point right; an edge that
spans several columns runs through a point in each, and its label is a point of
its own with the label's size, so labels never overlap boxes or other labels.
The steps are the classic ones: break cycles (depth-first, reversed back edges),
rank by longest path, order each column by barycenters (down and up sweeps, the
order with the fewest crossings kept), then place each column's points as close
to their neighbours as the separations allow (isotonic regression per column).
Everything is deterministic: ties go to the input order. Time is
O(iterations × edges × log edges) and memory linear.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise

Point = tuple[float, float]
#: sweeps of the ordering and of the vertical placement
ORDER_SWEEPS = 8
PLACE_SWEEPS = 8


@dataclass(frozen=True)
class Box:
    """A node to place: its id and size."""

    id: str
    width: float
    height: float


@dataclass(frozen=True)
class Edge:
    """A directed edge with an optional label of the given size (0 × 0: no label)."""

    id: str
    source: str
    target: str
    label_width: float = 0.0
    label_height: float = 0.0


@dataclass(frozen=True)
class Placed:
    """A placed box: its centre and size."""

    x: float
    y: float
    width: float
    height: float


@dataclass
class Route:
    """The points an edge runs through, from its source to its target, and its label's centre."""

    points: list[Point]
    label: Point | None = None
    #: a loop from a box back to itself (drawn with straight segments)
    loop: bool = False


@dataclass
class Layout:
    """Where everything went; the drawing spans (0, 0) to (width, height)."""

    width: float
    height: float
    boxes: dict[str, Placed] = field(default_factory=dict)
    routes: dict[str, Route] = field(default_factory=dict)


@dataclass
class _Node:
    """A point of the layered graph: a box, a label, or a bend of a long edge."""

    key: int
    width: float
    height: float
    rank: int = 0
    y: float = 0.0
    up: list[int] = field(default_factory=list)      # neighbours in the rank before
    down: list[int] = field(default_factory=list)    # neighbours in the rank after
    weight: float = 1.0


def layered(boxes: Sequence[Box], edges: Sequence[Edge], *, rank_gap: float = 36.0, node_gap: float = 18.0,
            margin: float = 12.0, loop_gap: float = 14.0) -> Layout:
    """Place ``boxes`` in columns and route ``edges`` between them (left to right)."""
    index = {b.id: i for i, b in enumerate(boxes)}
    for e in edges:
        if e.source not in index or e.target not in index:
            raise ValueError(f"edge {e.id} joins an unknown box")
    loops = [e for e in edges if e.source == e.target]
    # a box with loops reserves room above it for them and their labels
    reserve = [0.0] * len(boxes)
    widths = [b.width for b in boxes]
    for e in loops:
        reserve[index[e.source]] += loop_gap + max(e.label_height, 0.0)
        widths[index[e.source]] = max(widths[index[e.source]], e.label_width)
    nodes = [_Node(i, widths[i], b.height + reserve[i]) for i, b in enumerate(boxes)]
    flows = [(e, index[e.source], index[e.target]) for e in edges if e.source != e.target]
    flipped = _back_edges(len(boxes), [(s, t) for _, s, t in flows])
    directed = [(t, s) if k in flipped else (s, t) for k, (_, s, t) in enumerate(flows)]
    ranks = _ranks(len(boxes), directed, [2 if e.label_width > 0 else 1 for e, _, _ in flows])
    for n, r in zip(nodes, ranks):
        n.rank = r
    chains, labels = _chains(nodes, [e for e, _, _ in flows], directed)
    columns = _order(nodes)
    xs = _columns_x(nodes, columns, rank_gap, margin)
    _place(nodes, columns, node_gap)
    top = min((nodes[k].y - nodes[k].height / 2 for col in columns for k in col), default=0.0)
    shift = margin - top
    for n in nodes:
        n.y += shift
    out = Layout(0.0, 0.0)
    for i, box in enumerate(boxes):
        out.boxes[box.id] = Placed(xs[nodes[i].rank], nodes[i].y + reserve[i] / 2, box.width, box.height)
    ports = _ports(nodes, out, boxes, chains)
    for k, (e, _, _) in enumerate(flows):
        chain = chains[k]
        pts: list[Point] = [ports[(k, 0)]]
        label_point: Point | None = None
        for key in chain[1:-1]:
            n = nodes[key]
            x = xs[n.rank]
            if key == labels[k]:
                label_point = (x, n.y)
                pts.extend([(x - n.width / 2, n.y), (x + n.width / 2, n.y)])
            else:
                pts.append((x, n.y))
        pts.append(ports[(k, 1)])
        if k in flipped:
            pts.reverse()
        out.routes[e.id] = Route(pts, label_point)
    for e in loops:
        out.routes[e.id] = _loop(out.boxes[e.source], e, loops, loop_gap)
    right = max((p.x + p.width / 2 for p in out.boxes.values()), default=0.0)
    bottom = max((p.y + p.height / 2 for p in out.boxes.values()), default=0.0)
    for route in out.routes.values():
        for x, y in route.points:
            right, bottom = max(right, x), max(bottom, y)
    for e in edges:
        centre = out.routes[e.id].label
        if centre is not None:
            right = max(right, centre[0] + e.label_width / 2)
            bottom = max(bottom, centre[1] + e.label_height / 2)
    out.width, out.height = right + margin, bottom + margin
    return out


def _chains(nodes: list[_Node], edges: list[Edge],
            directed: list[tuple[int, int]]) -> tuple[list[list[int]], list[int | None]]:
    """Each edge as a chain of points, one per column it crosses; the one in the middle holds its label."""
    chains: list[list[int]] = []
    labels: list[int | None] = []
    for e, (s, t) in zip(edges, directed):
        chain = [s]
        label: int | None = None
        middle = nodes[s].rank + max(1, (nodes[t].rank - nodes[s].rank) // 2)
        for r in range(nodes[s].rank + 1, nodes[t].rank):
            is_label = e.label_width > 0 and r == middle
            n = _Node(len(nodes), e.label_width if is_label else 0.0, e.label_height if is_label else 2.0, r,
                      weight=2.0 if is_label else 4.0)
            nodes.append(n)
            chain.append(n.key)
            if is_label:
                label = n.key
        chain.append(t)
        for a, b in pairwise(chain):
            nodes[a].down.append(b)
            nodes[b].up.append(a)
        chains.append(chain)
        labels.append(label)
    return chains, labels


def _back_edges(n: int, edges: list[tuple[int, int]]) -> set[int]:
    """Indices of edges to reverse so that the graph has no cycle (depth-first, in input order)."""
    succ: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for k, (s, t) in enumerate(edges):
        succ[s].append((t, k))
    state = [0] * n  # 0 new, 1 on the stack, 2 done
    back: set[int] = set()
    for root in range(n):
        if state[root]:
            continue
        state[root] = 1
        stack = [(root, 0)]
        while stack:
            v, i = stack[-1]
            if i < len(succ[v]):
                stack[-1] = (v, i + 1)
                t, k = succ[v][i]
                if state[t] == 1:
                    back.add(k)
                elif state[t] == 0:
                    state[t] = 1
                    stack.append((t, 0))
            else:
                state[v] = 2
                stack.pop()
    return back


def _ranks(n: int, edges: list[tuple[int, int]], minlen: list[int]) -> list[int]:
    """Longest-path ranks (each edge at least its minimum length), sources pulled next to their successors."""
    succ: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    indeg = [0] * n
    for (s, t), length in zip(edges, minlen):
        succ[s].append((t, length))
        indeg[t] += 1
    rank = [0] * n
    queue = deque(v for v in range(n) if indeg[v] == 0)
    order: list[int] = []
    while queue:
        v = queue.popleft()
        order.append(v)
        for t, length in succ[v]:
            rank[t] = max(rank[t], rank[v] + length)
            indeg[t] -= 1
            if indeg[t] == 0:
                queue.append(t)
    has_pred = [False] * n
    for _, t in edges:
        has_pred[t] = True
    for v in reversed(order):  # a source sits just before its nearest successor
        if not has_pred[v] and succ[v]:
            rank[v] = min(rank[t] - length for t, length in succ[v])
    low = min(rank, default=0)
    return [r - low for r in rank]


def _order(nodes: list[_Node]) -> list[list[int]]:
    """Columns, each ordered top to bottom, with few crossings."""
    depth = max((n.rank for n in nodes), default=-1) + 1
    columns: list[list[int]] = [[] for _ in range(depth)]
    seen = [False] * len(nodes)
    # initial order: depth-first from each node in input order, so that chains stay together
    for start in range(len(nodes)):
        if seen[start]:
            continue
        stack = [start]
        while stack:
            v = stack.pop()
            if seen[v]:
                continue
            seen[v] = True
            columns[nodes[v].rank].append(v)
            stack.extend(reversed(nodes[v].down))
    best = [list(c) for c in columns]
    best_crossings = _crossings(nodes, columns)
    for sweep in range(ORDER_SWEEPS):
        downward = sweep % 2 == 0
        rng = range(1, depth) if downward else range(depth - 2, -1, -1)
        for r in rng:
            ref = columns[r - 1] if downward else columns[r + 1]
            pos = {k: i for i, k in enumerate(ref)}
            keyed = []
            for i, k in enumerate(columns[r]):
                near = nodes[k].up if downward else nodes[k].down
                # a point without neighbours on that side keeps its place
                keyed.append(((sum(pos[x] for x in near) / len(near) if near else float(i), i), k))
            keyed.sort(key=lambda item: item[0])
            columns[r] = [k for _, k in keyed]
        crossings = _crossings(nodes, columns)
        if crossings < best_crossings:
            best, best_crossings = [list(c) for c in columns], crossings
    return best


def _crossings(nodes: list[_Node], columns: list[list[int]]) -> int:
    """Edge crossings between neighbouring columns (inversions counted with a Fenwick tree)."""
    total = 0
    for r in range(len(columns) - 1):
        below = {k: i for i, k in enumerate(columns[r + 1])}
        pairs = sorted((i, below[t]) for i, k in enumerate(columns[r]) for t in nodes[k].down)
        size = len(columns[r + 1])
        tree = [0] * (size + 1)
        for seen, (_, j) in enumerate(pairs):
            # count earlier edges that end below j
            i, smaller = j + 1, 0
            while i > 0:
                smaller += tree[i]
                i -= i & -i
            total += seen - smaller
            i = j + 1
            while i <= size:
                tree[i] += 1
                i += i & -i
    return total


def _columns_x(nodes: list[_Node], columns: list[list[int]], gap: float, margin: float) -> list[float]:
    """The centre x of each column."""
    xs: list[float] = []
    right = margin - gap
    for col in columns:
        width = max((nodes[k].width for k in col), default=0.0)
        xs.append(right + gap + width / 2)
        right += gap + width
    return xs


def _place(nodes: list[_Node], columns: list[list[int]], gap: float) -> None:
    """Vertical centres: each point near its neighbours, in its column's order, never overlapping."""
    for col in columns:
        y = 0.0
        for k in col:
            nodes[k].y = y + nodes[k].height / 2
            y += nodes[k].height + gap
    for sweep in range(PLACE_SWEEPS):
        downward = sweep % 2 == 0
        order = columns if downward else list(reversed(columns))
        for col in order:
            wanted: list[float] = []
            weights: list[float] = []
            for k in col:
                n = nodes[k]
                near = (n.up if downward else n.down) or (n.down if downward else n.up)
                wanted.append(sum(nodes[x].y for x in near) / len(near) if near else n.y)
                weights.append(n.weight * (len(near) or 0.25))
            seps = [(nodes[a].height + nodes[b].height) / 2 + gap for a, b in pairwise(col)]
            for k, y in zip(col, _isotonic(wanted, weights, seps)):
                nodes[k].y = y


def _isotonic(wanted: list[float], weights: list[float], seps: list[float]) -> list[float]:
    """Positions y₀ ≤ y₁ ≤ … with yᵢ₊₁ − yᵢ ≥ sepᵢ, closest to ``wanted`` in weighted least squares (PAVA)."""
    offsets = [0.0]
    for s in seps:
        offsets.append(offsets[-1] + s)
    # blocks of (mean, weight, count) over z = y - offset, which must not decrease
    blocks: list[list[float]] = []
    for w, want, off in zip(weights, wanted, offsets):
        blocks.append([want - off, w, 1])
        while len(blocks) > 1 and blocks[-2][0] > blocks[-1][0]:
            m2, w2, c2 = blocks.pop()
            m1, w1, c1 = blocks.pop()
            total = w1 + w2
            blocks.append([(m1 * w1 + m2 * w2) / total, total, c1 + c2])
    out: list[float] = []
    for mean, _, count in blocks:
        out.extend([mean] * int(count))
    return [z + off for z, off in zip(out, offsets)]


def _ports(nodes: list[_Node], out: Layout, boxes: Sequence[Box],
           chains: list[list[int]]) -> dict[tuple[int, int], Point]:
    """Where each edge leaves and enters its boxes: spread over the facing side, in the order of the other end."""
    sides: dict[tuple[int, str], list[tuple[float, int, int]]] = {}
    for k, chain in enumerate(chains):
        first, second = chain[0], chain[1]
        last, before = chain[-1], chain[-2]
        sides.setdefault((first, "right"), []).append((nodes[second].y, k, 0))
        sides.setdefault((last, "left"), []).append((nodes[before].y, k, 1))
    ports: dict[tuple[int, int], Point] = {}
    for (key, side), items in sides.items():
        box = out.boxes[boxes[key].id]
        items.sort()
        x = box.x + box.width / 2 if side == "right" else box.x - box.width / 2
        usable = box.height * 0.6
        for i, (_, k, end) in enumerate(items):
            offset = 0.0 if len(items) == 1 else -usable / 2 + usable * i / (len(items) - 1)
            ports[(k, end)] = (x, box.y + offset)
    return ports


def _loop(box: Placed, edge: Edge, loops: list[Edge], gap: float) -> Route:
    """A loop over the top of its box, its label above it."""
    mine = [e for e in loops if e.source == edge.source]
    level = sum(gap + e.label_height for e in mine[:mine.index(edge) + 1])
    top = box.y - box.height / 2
    left, right = box.x - box.width / 4, box.x + box.width / 4
    peak = top - level + edge.label_height
    points = [(right, top), (right, peak), (left, peak), (left, top)]
    label = (box.x, peak - edge.label_height / 2) if edge.label_width > 0 else None
    return Route(points, label, loop=True)
