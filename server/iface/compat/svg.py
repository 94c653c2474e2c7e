"""The system graph as an SVG picture.

Two ways to draw it: Graphviz's ``dot`` on the DOT form (where ``dot`` is
installed), or the built-in layered layout of ``layout.py`` drawn from the
graph's JSON data. Both draw components as boxes, topics as solid and services
and actions as dashed links labelled with their names and types, endpoints
without a peer as dotted stubs, and conflicts (types or QoS that cannot match)
in red. The built-in drawing also names each element's file and line in its
tooltip and adds a legend. The same graph gives byte-identical SVG.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Iterable
from html import escape
from itertools import pairwise
from typing import Any

from .graph import CHECKS, Display, Graph, graph_json
from .layout import Box, Edge, Layout, Route, layered

LAYOUTS = ("auto", "dot", "builtin")
FONT = "Helvetica, Arial, 'Liberation Sans', sans-serif"
DOT_TIMEOUT = 120.0

#: advance widths of Helvetica (= Arial, Liberation Sans) in 1/1000 em, for ' ' to '~'
_WIDTHS = (
    278, 278, 355, 556, 556, 889, 667, 191, 333, 333, 389, 584, 278, 333, 278, 278,
    556, 556, 556, 556, 556, 556, 556, 556, 556, 556, 278, 278, 584, 584, 584, 556,
    1015, 667, 667, 722, 722, 667, 611, 778, 722, 278, 500, 667, 556, 833, 722, 778,
    667, 778, 722, 667, 611, 722, 667, 944, 667, 667, 611, 278, 278, 278, 469, 556,
    333, 556, 556, 500, 556, 556, 278, 556, 556, 222, 222, 500, 222, 833, 556, 556,
    556, 556, 333, 500, 278, 556, 500, 722, 500, 500, 500, 334, 260, 334, 584,
)

_STYLE = """
.bg { fill: #ffffff; }
text { fill: #1f2328; }
.component rect { fill: #eaf1fb; stroke: #3d6fb6; stroke-width: 1.5; }
.component .name { font-weight: bold; font-size: 13px; }
.detail { fill: #57606a; font-size: 10.5px; }
.edge path { fill: none; stroke: #57606a; stroke-width: 1.4; }
.edge.service path, .edge.action path { stroke-dasharray: 6 4; }
.edge.open path { stroke-dasharray: 2 3; }
.edge.conflict path { stroke: #cf222e; stroke-width: 2; }
.label rect { fill: #ffffff; stroke: #d0d7de; stroke-width: 0.8; }
.label .name { font-size: 11px; }
.label.conflict rect { stroke: #cf222e; stroke-width: 1.2; }
.label.conflict text { fill: #cf222e; }
.stub rect { fill: #ffffff; stroke-width: 1.2; stroke-dasharray: 3 2; }
.stub.error rect { stroke: #cf222e; }
.stub.warning rect { stroke: #9a6700; }
.stub.information rect { stroke: #8c959f; }
.stub.error text { fill: #cf222e; }
.legend text { font-size: 10.5px; fill: #57606a; }
"""


class LayoutUnavailable(Exception):
    """The layout engine asked for cannot run (``dot`` missing or failing)."""


def text_width(text: str, size: float, bold: bool = False) -> float:
    """The width of ``text`` in Helvetica at ``size`` px (an estimate for other fonts; never too small)."""
    units = sum(_WIDTHS[ord(c) - 32] if 32 <= ord(c) <= 126 else 1000 if ord(c) > 0x2E80 else 600 for c in text)
    return units * size / 1000 * (1.08 if bold else 1.0) * 1.05


def _xml(text: str) -> str:
    """Text for an XML document: markup escaped, characters XML cannot hold shown as ``\\xNN``."""
    cleaned = "".join(c if c in "\t\n" or (ord(c) >= 32 and not 0xD800 <= ord(c) <= 0xDFFF and ord(c) not in
                                           (0xFFFE, 0xFFFF)) else f"\\x{ord(c):02x}" for c in text)
    return escape(cleaned, quote=True)


def _num(v: float) -> str:
    text = f"{v:.1f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _where(loc: dict[str, Any] | None) -> str:
    return f"{loc['file']}:{loc['line']}:{loc['column']}" if loc else ""


def render_svg(g: Graph, display: Display, layout: str = "auto") -> str:
    """The graph as SVG: with ``dot`` (``layout="dot"``, or ``"auto"`` when it is installed) or the
    built-in layout. Raises ``LayoutUnavailable`` when ``dot`` is asked for and cannot run."""
    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}")
    data = graph_json(g, display)
    if layout == "dot" or (layout == "auto" and shutil.which("dot") is not None):
        return dot_svg(data)
    return builtin_svg(data)


def _dot_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _dot_html(text: str) -> str:
    return _xml(text).replace("\n", "<br/>")


def picture_dot(data: dict[str, Any]) -> str:
    """The graph's JSON data as DOT styled like the built-in drawing (colours, tooltips, stubs)."""
    lines = ["digraph system {", '  rankdir=LR; bgcolor="white"; pad=0.2; nodesep=0.35; ranksep=0.6;',
             '  node [shape=box, style="rounded,filled", fillcolor="#eaf1fb", color="#3d6fb6", penwidth=1.5, '
             'fontname="Helvetica", fontsize=12];',
             '  edge [color="#57606a", fontname="Helvetica", fontsize=10, penwidth=1.3];']
    for c in data["components"]:
        detail = " · ".join(x for x in (c["version"] and f"v{c['version']}", c["file"].rsplit("/", 1)[-1]) if x)
        label = f'<<b>{_dot_html(c["name"])}</b><br/><font point-size="9" color="#57606a">{_dot_html(detail)}</font>>'
        tip = f"component {c['name']}\n{_where(c.get('at'))}"
        lines.append(f"  {_dot_string(c['id'])} [label={label}, tooltip={_dot_string(tip)}];")
    colours = {"error": "#cf222e", "warning": "#9a6700", "information": "#8c959f"}
    for i, p in enumerate(data["open"]):
        colour = colours[p["severity"]]
        label = f'<{_dot_html(p["name"])}<br/><font point-size="9" color="#57606a">{_dot_html(p["type"])}</font>>'
        tip = f"{p['role']} {p['name']}: {p['type']}\n{CHECKS[p['check']][1]}\n{_where(p.get('at'))}"
        lines.append(f'  "open-{i}" [label={label}, style="rounded,dashed", color="{colour}", fontsize=11, '
                     f"tooltip={_dot_string(tip)}];")
    for link in data["links"]:
        conflict = bool(link["qos_mismatch"] or link.get("type_conflict"))
        style = "solid" if link["kind"] == "topic" else "dashed"
        colour = ', color="#cf222e", fontcolor="#cf222e", penwidth=2' if conflict else ""
        tip = _link_tip(data, link)
        lines.append(f"  {_dot_string(link['from'])} -> {_dot_string(link['to'])} "
                     f"[label={_dot_string(link['name'] + chr(10) + _link_type(link))}, style={style}{colour}, "
                     f"tooltip={_dot_string(tip)}];")
    for i, p in enumerate(data["open"]):
        a, b = p["component"], f"open-{i}"
        src, dst = (a, b) if p["role"] in ("publishes", "calls") else (b, a)
        lines.append(f"  {_dot_string(src)} -> {_dot_string(dst)} [style=dotted];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def dot_svg(data: dict[str, Any]) -> str:
    """Graphviz's drawing of the graph's JSON data (``graph_json``)."""
    dot = shutil.which("dot")
    if dot is None:
        raise LayoutUnavailable("Graphviz's `dot` is not on PATH (install the graphviz package, "
                                "or use the built-in layout: --layout builtin)")
    try:
        done = subprocess.run([dot, "-Tsvg"], input=picture_dot(data).encode("utf-8"), capture_output=True,
                              timeout=DOT_TIMEOUT, check=False)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise LayoutUnavailable(f"`dot` did not run: {e}") from e
    if done.returncode != 0:
        first = done.stderr.decode("utf-8", "replace").strip().splitlines()[:1]
        raise LayoutUnavailable(f"`dot` failed (exit {done.returncode}): {first[0] if first else 'no message'}")
    return done.stdout.decode("utf-8", "replace")


class _Text:
    """A block of lines: (text, size, class, bold)."""

    def __init__(self, lines: Iterable[tuple[str, float, str, bool]], pad_x: float, pad_y: float) -> None:
        self.lines = [ln for ln in lines if ln[0]]
        self.width = max((text_width(t, s, b) for t, s, _, b in self.lines), default=0.0) + 2 * pad_x
        self.height = sum(s * 1.3 for _, s, _, _ in self.lines) + 2 * pad_y

    def svg(self, cx: float, cy: float) -> list[str]:
        out = []
        y = cy - self.height / 2 + (self.height - sum(s * 1.3 for _, s, _, _ in self.lines)) / 2
        for text, size, cls, _ in self.lines:
            y += size * 1.3
            out.append(f'<text x="{_num(cx)}" y="{_num(y - size * 0.3)}" text-anchor="middle"'
                       f'{f" class={chr(34)}{cls}{chr(34)}" if cls else ""}>{_xml(text)}</text>')
        return out


def _kind(link: dict[str, Any]) -> str:
    """What a link is, in words: topic, service, action or diagnostics (a call of a Δ service)."""
    return "diagnostics" if link.get("set") == "Δ" else str(link["kind"])


def _link_type(link: dict[str, Any]) -> str:
    """The type a link carries; both when its ends disagree (same name, other package or fields: "types differ")."""
    if link.get("to_type") not in (None, link["type"]):
        shown = f"{link['type']} ≠ {link['to_type']}"
    else:
        shown = link["type"] + (" — types differ" if link.get("type_conflict") else "")
    return shown if link["kind"] == "topic" else f"{shown} ({_kind(link)})"


def _conflict_message(data: dict[str, Any], link: dict[str, Any]) -> str | None:
    """The message of the type-conflict check on a link's topic or name."""
    if not link.get("type_conflict"):
        return None
    return next((c["message"] for c in data["checks"] if c["code"].endswith("-type-conflict")
                 and f"'{link['name']}'" in c["message"]), "the two ends use different types")


def _link_tip(data: dict[str, Any], link: dict[str, Any]) -> str:
    """What a link's tooltip says: name, type, ends, conflicts and where the type is defined."""
    names = {c["id"]: c["name"] for c in data["components"]}
    lines = [f"{_kind(link)} {link['name']}: {_link_type(link)}", f"{names[link['from']]} → {names[link['to']]}"]
    conflict = _conflict_message(data, link)
    lines += [conflict] if conflict else []
    lines += [f"QoS: {q}" for q in link["qos_mismatch"]]
    lines += [f"defined at {_where(link['definition'])}"] if link.get("definition") else []
    return "\n".join(lines)


def _path(route: Route) -> str:
    pts = route.points
    d = [f"M{_num(pts[0][0])},{_num(pts[0][1])}"]
    for (x0, y0), (x1, y1) in pairwise(pts):
        if route.loop:
            d.append(f"L{_num(x1)},{_num(y1)}")
        else:
            dx = (x1 - x0) / 2
            d.append(f"C{_num(x0 + dx)},{_num(y0)} {_num(x1 - dx)},{_num(y1)} {_num(x1)},{_num(y1)}")
    return " ".join(d)


def builtin_svg(data: dict[str, Any]) -> str:
    """The graph's JSON data (``graph_json``) drawn with the built-in layout."""
    texts: dict[str, _Text] = {}
    boxes: list[Box] = []
    for c in data["components"]:
        detail = " · ".join(x for x in (c["version"] and f"v{c['version']}", c["file"].rsplit("/", 1)[-1]) if x)
        t = _Text([(c["name"], 13, "name", True), (detail, 10.5, "detail", False)], 14, 8)
        texts[c["id"]] = t
        boxes.append(Box(c["id"], max(t.width, 90), t.height))
    for i, p in enumerate(data["open"]):
        t = _Text([(p["name"], 11, "", False), (p["type"], 10, "detail", False)], 8, 5)
        texts[f"open-{i}"] = t
        boxes.append(Box(f"open-{i}", t.width, t.height))
    edges: list[Edge] = []
    for i, link in enumerate(data["links"]):
        t = _Text([(link["name"], 11, "name", False), (_link_type(link), 10, "detail", False)], 6, 3)
        texts[f"link-{i}"] = t
        edges.append(Edge(f"link-{i}", link["from"], link["to"], t.width, t.height))
    for i, p in enumerate(data["open"]):
        sends = p["role"] in ("publishes", "calls")
        src, dst = (p["component"], f"open-{i}") if sends else (f"open-{i}", p["component"])
        edges.append(Edge(f"open-edge-{i}", src, dst))
    lay = layered(boxes, edges)
    return _draw(data, lay, texts)


def _legend(y: float) -> tuple[list[str], float, float]:
    items = [("topic", ""), ("service, action", "6 4"), ("no peer", "2 3"), ("conflict", "")]
    out = ['<g class="legend">']
    x = 12.0
    for name, dash in items:
        stroke = "#cf222e" if name == "conflict" else "#57606a"
        dashes = f' stroke-dasharray="{dash}"' if dash else ""
        out.append(f'<path d="M{_num(x)},{_num(y)} h24" stroke="{stroke}" stroke-width="1.6"{dashes} fill="none"/>')
        out.append(f'<text x="{_num(x + 30)}" y="{_num(y + 3.5)}">{name}</text>')
        x += 30 + text_width(name, 10.5) + 22
    out.append("</g>")
    return out, x, 22.0


def _draw(data: dict[str, Any], lay: Layout, texts: dict[str, _Text]) -> str:
    errors = sum(1 for c in data["checks"] if c["severity"] == "error")
    warnings = sum(1 for c in data["checks"] if c["severity"] == "warning")
    summary = (f"System graph: {len(data['components'])} component(s), {len(data['links'])} link(s), "
               f"{errors} error(s), {warnings} warning(s)")
    legend, legend_width, legend_height = _legend(lay.height + 6)
    width, height = max(lay.width, legend_width), lay.height + legend_height
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<svg xmlns="http://www.w3.org/2000/svg" width="{_num(width)}" height="{_num(height)}" '
           f'viewBox="0 0 {_num(width)} {_num(height)}" font-family="{_xml(FONT)}" font-size="12" role="img">',
           f"<title>{_xml(summary)}</title>",
           f"<style>{_STYLE}</style>",
           "<defs>",
           '<marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" '
           'orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#57606a"/></marker>',
           '<marker id="arrow-conflict" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" '
           'orient="auto"><path d="M0,0 L10,5 L0,10 z" fill="#cf222e"/></marker>',
           "</defs>",
           f'<rect class="bg" x="0" y="0" width="{_num(width)}" height="{_num(height)}"/>',
           '<g class="edges">']
    labels: list[str] = []
    for i, link in enumerate(data["links"]):
        route = lay.routes[f"link-{i}"]
        conflict = bool(link["qos_mismatch"] or link.get("type_conflict"))
        cls = f"edge {link['kind']}{' conflict' if conflict else ''}"
        tip = _link_tip(data, link)
        marker = "arrow-conflict" if conflict else "arrow"
        out.append(f'<g class="{cls}"><title>{_xml(tip)}</title>'
                   f'<path d="{_path(route)}" marker-end="url(#{marker})"/></g>')
        if route.label is not None:
            t = texts[f"link-{i}"]
            x, y = route.label
            labels.append(f'<g class="label{" conflict" if conflict else ""}"><title>{_xml(tip)}'
                          f'</title><rect x="{_num(x - t.width / 2)}" y="{_num(y - t.height / 2)}" '
                          f'width="{_num(t.width)}" height="{_num(t.height)}" rx="3"/>')
            labels.extend(t.svg(x, y))
            labels.append("</g>")
    for i, p in enumerate(data["open"]):
        route = lay.routes[f"open-edge-{i}"]
        out.append(f'<g class="edge open {p["kind"]}"><path d="{_path(route)}" marker-end="url(#arrow)"/></g>')
    out.append("</g>")
    out.append('<g class="labels">')
    out.extend(labels)
    out.append("</g>")
    out.append('<g class="nodes">')
    for c in data["components"]:
        box, t = lay.boxes[c["id"]], texts[c["id"]]
        tip = f"component {c['name']}{' ' + c['version'] if c['version'] else ''}\n{_where(c.get('at'))}"
        out.append(f'<g class="component"><title>{_xml(tip)}</title>'
                   f'<rect x="{_num(box.x - box.width / 2)}" y="{_num(box.y - box.height / 2)}" '
                   f'width="{_num(box.width)}" height="{_num(box.height)}" rx="4"/>')
        out.extend(t.svg(box.x, box.y))
        out.append("</g>")
    for i, p in enumerate(data["open"]):
        box, t = lay.boxes[f"open-{i}"], texts[f"open-{i}"]
        tip = f"{p['role']} {p['name']}: {p['type']}\n{CHECKS[p['check']][1]}\n{_where(p.get('at'))}"
        out.append(f'<g class="stub {p["severity"]}"><title>{_xml(tip)}</title>'
                   f'<rect x="{_num(box.x - box.width / 2)}" y="{_num(box.y - box.height / 2)}" '
                   f'width="{_num(box.width)}" height="{_num(box.height)}" rx="9"/>')
        out.extend(t.svg(box.x, box.y))
        out.append("</g>")
    out.append("</g>")
    out.extend(legend)
    out.append("</svg>")
    return "\n".join(out) + "\n"
