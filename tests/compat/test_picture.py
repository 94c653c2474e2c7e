"""The system graph as a picture: the data an editor draws from, the built-in layout, and SVG."""

from __future__ import annotations

import os
import random
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from compat_support import DATA, cached, run_main

from iface.compat.graph import build, graph_json, render_dot
from iface.compat.layout import Box, Edge, Layout, layered
from iface.compat.svg import LayoutUnavailable, builtin_svg, dot_svg, picture_dot, render_svg

SYSTEM = [DATA / "system" / n for n in ("camera.iface", "detector.iface", "logger.iface")]
ARM = [DATA / "verdicts" / n for n in ("arm_v1.iface", "planner.iface", "monitor.iface")]
GOLDEN = Path(__file__).parent / "golden"
SVG = "{http://www.w3.org/2000/svg}"


def _data(paths: list[Path]) -> dict:  # type: ignore[type-arg]
    return graph_json(build([cached(p) for p in paths]), str)


def _line(loc: dict) -> str:  # type: ignore[type-arg]
    return Path(loc["file"]).read_text(encoding="utf-8").splitlines()[loc["line"] - 1]


# ---- the data ---------------------------------------------------------------------------------

def test_every_element_knows_where_it_is_defined() -> None:
    data = _data(SYSTEM)
    for c in data["components"]:
        assert f"component {c['name']}" in _line(c["at"])
    for link in data["links"]:
        assert link["name"] in _line(link["from_at"]) and link["name"] in _line(link["to_at"])
        assert _line(link["definition"]).lstrip().startswith("message ")
        assert link["type"].rpartition("/")[2] in _line(link["definition"])
    for p in data["open"]:
        assert p["name"] in _line(p["at"])
    assert {(p["name"], p["check"], p["severity"]) for p in data["open"]} == {
        ("/depth", "graph-unpublished-topic", "warning"), ("/track", "graph-unprovided-service", "warning")}


def test_conflicts_are_marked_on_their_links() -> None:
    data = _data(SYSTEM)
    by_name = {lk["name"]: lk for lk in data["links"]}
    assert by_name["/detections"]["type_conflict"] is True
    assert (by_name["/detections"]["type"], by_name["/detections"]["to_type"]) == ("vision_msgs/Detections",
                                                                                  "vision_msgs/Boxes")
    assert by_name["/image"]["type_conflict"] is False and by_name["/image"]["qos_mismatch"]
    assert all(lk["type_conflict"] is False and not lk["qos_mismatch"] for lk in _data(ARM)["links"])
    dot = render_dot(build([cached(p) for p in SYSTEM]))
    assert dot.count("color=red") == 2  # the QoS mismatch and the type conflict


def test_an_included_type_points_into_its_file(tmp_path: Path) -> None:
    from iface.semantics.compile import Workspace

    (tmp_path / "msgs.iface").write_text("namespace ros2 shared_msgs\nmessage Ping { u32 seq }\n")
    (tmp_path / "a.iface").write_text('component a\ninclude "msgs.iface"\npublishes msgs.Ping on "/ping"\n')
    (tmp_path / "b.iface").write_text('component b\ninclude "msgs.iface"\nsubscribes msgs.Ping on "/ping"\n')
    ws = Workspace()
    data = graph_json(build([ws.compile_path(str(tmp_path / n)) for n in ("a.iface", "b.iface")]), str)
    (link,) = data["links"]
    assert Path(link["definition"]["file"]).name == "msgs.iface"
    assert (link["definition"]["line"], link["definition"]["column"]) == (2, 9)


# ---- the built-in layout ----------------------------------------------------------------------

def _overlap(a: tuple[float, float, float, float], b: tuple[float, float, float, float]) -> bool:
    """Rectangles (left, top, right, bottom) that share more than a hair."""
    return a[0] < b[2] - 0.5 and b[0] < a[2] - 0.5 and a[1] < b[3] - 0.5 and b[1] < a[3] - 0.5


def _rects(lay: Layout, edges: list[Edge]) -> list[tuple[str, tuple[float, float, float, float]]]:
    out = [(k, (p.x - p.width / 2, p.y - p.height / 2, p.x + p.width / 2, p.y + p.height / 2))
           for k, p in lay.boxes.items()]
    for e in edges:
        label = lay.routes[e.id].label
        if label is not None:
            x, y = label
            out.append((e.id, (x - e.label_width / 2, y - e.label_height / 2,
                               x + e.label_width / 2, y + e.label_height / 2)))
    return out


def _random_graph(seed: int) -> tuple[list[Box], list[Edge]]:
    rnd = random.Random(seed)
    boxes = [Box(f"n{i}", rnd.uniform(40, 160), rnd.uniform(20, 60)) for i in range(rnd.randint(1, 14))]
    edges = []
    for k in range(rnd.randint(0, 30)):
        s, t = rnd.choice(boxes).id, rnd.choice(boxes).id
        labelled = rnd.random() < 0.7
        edges.append(Edge(f"e{k}", s, t, rnd.uniform(30, 150) if labelled else 0, 28 if labelled else 0))
    return boxes, edges


@pytest.mark.parametrize("seed", range(60))
def test_layout_keeps_boxes_and_labels_apart_and_routes_join_the_boxes(seed: int) -> None:
    boxes, edges = _random_graph(seed)
    lay = layered(boxes, edges)
    assert lay == layered(boxes, edges)  # deterministic
    rects = _rects(lay, edges)
    for i, (a, ra) in enumerate(rects):
        assert 0 <= ra[0] and 0 <= ra[1] and ra[2] <= lay.width and ra[3] <= lay.height, a
        for b, rb in rects[i + 1:]:
            assert not _overlap(ra, rb), f"{a} overlaps {b}"
    for e in edges:
        route = lay.routes[e.id]
        src, dst = lay.boxes[e.source], lay.boxes[e.target]
        (x0, y0), (x1, y1) = route.points[0], route.points[-1]
        if e.source == e.target:
            assert route.loop and y0 == y1 == src.y - src.height / 2
            continue
        assert abs(abs(x0 - src.x) - src.width / 2) < 1e-6 and abs(y0 - src.y) <= src.height / 2
        assert abs(abs(x1 - dst.x) - dst.width / 2) < 1e-6 and abs(y1 - dst.y) <= dst.height / 2
        assert (route.label is not None) == (e.label_width > 0)


def test_layout_points_most_edges_right() -> None:
    boxes = [Box(n, 80, 30) for n in "abcde"]
    chain = [Edge(f"{s}{t}", s, t, 40, 20) for s, t in ("ab", "bc", "cd", "de", "ea")]
    lay = layered(boxes, chain)
    xs = [lay.boxes[n].x for n in "abcde"]
    assert xs == sorted(xs) and len(set(xs)) == 5  # one cycle edge (e -> a) runs back


def test_layout_rejects_edges_to_unknown_boxes() -> None:
    with pytest.raises(ValueError, match="unknown box"):
        layered([Box("a", 10, 10)], [Edge("x", "a", "b")])


# ---- SVG --------------------------------------------------------------------------------------

def _svg(text: str) -> ET.Element:
    return ET.fromstring(text.encode("utf-8"))


def _groups(root: ET.Element, cls: str) -> list[ET.Element]:
    return [g for g in root.iter(f"{SVG}g") if cls in (g.get("class") or "").split()]


def test_builtin_svg_draws_components_links_stubs_and_conflicts() -> None:
    root = _svg(builtin_svg(_data(SYSTEM)))
    names = ["".join(g.itertext()) for g in _groups(root, "component")]
    assert [n.split("v1.0")[0].strip().splitlines()[-1] for n in names] == ["camera", "detector", "logger"]
    edges = _groups(root, "edge")
    assert len(edges) == 4  # two links, two stubs
    conflicts = [g.findtext(f"{SVG}title") or "" for g in _groups(root, "conflict") if "edge" in g.get("class", "")]
    assert len(conflicts) == 2 and any("several types" in t for t in conflicts) and any("QoS" in t for t in conflicts)
    stubs = sorted(g.get("class") or "" for g in _groups(root, "stub"))
    assert stubs == ["stub warning", "stub warning"]  # a subscribed topic and a called service nobody serves
    labels = ["".join(g.itertext()) for g in _groups(root, "label")]
    assert any("/detections" in t and "vision_msgs/Detections ≠ vision_msgs/Boxes" in t for t in labels)
    tips = [g.findtext(f"{SVG}title") or "" for g in _groups(root, "component")]
    assert any(t.endswith("camera.iface:2:11") for t in tips)


def test_builtin_svg_matches_its_golden(tmp_path: Path) -> None:
    # paths relative to the fixtures, as the CLI shows them when run there
    data = graph_json(build([cached(p) for p in ARM]), lambda p: os.path.relpath(p, DATA))
    text = builtin_svg(data)
    golden = GOLDEN / "arm-system.svg"
    if os.environ.get("UPDATE_GOLDEN") == "1":
        golden.parent.mkdir(exist_ok=True)
        golden.write_text(text, encoding="utf-8")
    assert text == golden.read_text(encoding="utf-8")


def test_a_conflict_between_types_of_one_name_says_so(tmp_path: Path) -> None:
    from iface.semantics.compile import Workspace

    (tmp_path / "nav.iface").write_text('component nav\nnamespace ros2 nav_pkg\nmessage Status { u8 mode }\n'
                                        'publishes Status on "/nav/status"\n')
    (tmp_path / "mon.iface").write_text('component mon\nnamespace ros2 mon_pkg\nmessage Status { u8 mode }\n'
                                        'subscribes Status on "/nav/status"\n')
    ws = Workspace()
    data = graph_json(build([ws.compile_path(str(tmp_path / n)) for n in ("nav.iface", "mon.iface")]), str)
    labels = [[t.text for t in g.iter(f"{SVG}text")] for g in _groups(_svg(builtin_svg(data)), "label")]
    assert labels == [["/nav/status", "nav_pkg/Status ≠ mon_pkg/Status"]]


def test_names_cannot_break_out_of_the_svg(tmp_path: Path) -> None:
    from iface.semantics.compile import Workspace

    (tmp_path / "a.iface").write_text('component a\nmessage M { u8 x }\npublishes M on "/a<b>&\\"c"\n')
    data = graph_json(build([Workspace().compile_path(str(tmp_path / "a.iface"))]), str)
    text = builtin_svg(data)
    root = _svg(text)
    assert any('/a<b>&"c' in "".join(g.itertext()) for g in _groups(root, "stub"))
    assert "<b>" not in text


def test_dot_svg() -> None:
    if shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed (apt-get install graphviz)")
    data = _data(SYSTEM)
    root = _svg(dot_svg(data))
    text = "".join(root.itertext())
    for name in ("camera", "detector", "logger", "/detections", "vision_msgs/Detections ≠ vision_msgs/Boxes"):
        assert name in text
    assert picture_dot(data).count('color="#cf222e", fontcolor') == 2
    assert 'stroke="#cf222e"' in dot_svg(data)


def test_render_svg_without_dot_uses_the_builtin_layout_unless_dot_is_asked_for(
        monkeypatch: pytest.MonkeyPatch) -> None:
    g = build([cached(p) for p in SYSTEM])
    monkeypatch.setattr(shutil, "which", lambda name: None)
    assert render_svg(g, str, "auto") == builtin_svg(graph_json(g, str))
    with pytest.raises(LayoutUnavailable, match="dot.*not on PATH.*--layout builtin"):
        render_svg(g, str, "dot")


@pytest.mark.parametrize("layout", ["builtin", "dot", "auto"])
def test_cli_svg(layout: str) -> None:
    if layout == "dot" and shutil.which("dot") is None:
        pytest.skip("Graphviz's dot is not installed (apt-get install graphviz)")
    args = ["graph", "system/camera.iface", "system/detector.iface", "system/logger.iface", "--format", "svg",
            "--layout", layout]
    one, two = run_main(*args), run_main(*args)
    assert one.returncode == 1, one.stderr  # the checks find errors, as with the other formats
    assert one.stdout == two.stdout
    assert "error[graph-qos-mismatch]" in one.stderr
    root = _svg(one.stdout)
    assert root.tag == f"{SVG}svg"
    clean = run_main("graph", "verdicts/arm_v1.iface", "verdicts/planner.iface", "verdicts/monitor.iface",
                    "--format", "svg", "--layout", layout)
    assert clean.returncode == 0 and clean.stderr == ""


def test_cli_svg_says_what_is_missing_when_dot_is_asked_for_and_absent(tmp_path: Path) -> None:
    import subprocess
    import sys

    env = dict(os.environ, PATH=str(tmp_path))  # no dot on this PATH
    done = subprocess.run([sys.executable, "-m", "iface", "graph", "system/camera.iface", "--format", "svg",
                           "--layout", "dot"], capture_output=True, text=True, cwd=DATA, env=env, timeout=120,
                          check=False)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.strip() == ("iface-lsp graph: Graphviz's `dot` is not on PATH (install the graphviz "
                                   "package, or use the built-in layout: --layout builtin)")
    auto = subprocess.run([sys.executable, "-m", "iface", "graph", "system/camera.iface", "--format", "svg"],
                          capture_output=True, text=True, cwd=DATA, env=env, timeout=120, check=False)
    assert auto.returncode == 0 and 'class="legend"' in auto.stdout  # the built-in drawing


def test_cli_layout_needs_svg() -> None:
    done = run_main("graph", "system/camera.iface", "--format", "dot", "--layout", "builtin")
    assert done.returncode == 2 and "--layout applies to --format svg only" in done.stderr
