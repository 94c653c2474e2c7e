"""``system status --format html``: one self-contained page, the system graph with each instance's state, the
processes (each component container drawn around the instances it holds), a table and the findings."""

from __future__ import annotations

import html
import os
from typing import Any

from ..compat.graph import graph_json
from ..compat.svg import builtin_svg
from ..compat.systemfile import system_graph
from ..semantics.compile import Workspace

COLOURS = {"active": "#2e7d32", "inactive": "#f9a825", "starting": "#1565c0", "stopped": "#6d4c41",
           "failed": "#c62828", "down": "#757575"}


def _display(path: str) -> str:
    try:
        return os.path.relpath(path)
    except ValueError:
        return path


def _state(state: str) -> str:
    colour = COLOURS.get(state, "#757575")
    return f"<span class=\"state\" style=\"background:{colour}\">{html.escape(state)}</span>"


def processes(instances: list[dict[str, Any]]) -> str:
    """Each process as a box: a component container around the instances it holds, else one instance alone."""
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for i in instances:
        key = ("container", i["container"]) if i.get("container") else ("process", i["name"])
        groups.setdefault(key, []).append(i)
    boxes = []
    for (kind, name), members in groups.items():
        pid = next((m["pid"] for m in members if m["pid"]), 0)
        running = f"<small>pid {pid}</small>" if pid else "<small>not running</small>"
        if kind == "container":
            head = f'<div class="process container" id="container-{html.escape(name)}">'
            title = f"container <b>{html.escape(name)}</b> {running}"
        else:
            head, title = '<div class="process">', f"process {running}"
        cards = "".join(f'<div class="instance" id="instance-{html.escape(m["name"])}"><b>{html.escape(m["name"])}</b> '
                        f'{_state(m["state"])}<br><small>{html.escape(m["node"])}, restarts {m["restarts"]}</small>'
                        "</div>" for m in members)
        boxes.append(f'{head}<div class="title">{title}</div>{cards}</div>')
    return "\n".join(boxes)


def render(spec: Any, data: dict[str, Any]) -> str:
    """The page: the graph (instances named with their state), the processes, a table of the instances, the findings."""
    by_name = {i["name"]: i for i in data["instances"]}
    graph = graph_json(system_graph(Workspace().compile_path(str(spec.file))), _display)
    for c in graph["components"]:
        i = by_name.get(c["name"], {})
        c["name"] = f"{c['name']} [{i.get('state', '?')}]" + (f" in {i['container']}" if i.get("container") else "")
    rows = []
    for i in data["instances"]:
        rows.append(
            f"<tr><td>{html.escape(i['name'])}</td><td>{html.escape(i['node'])}</td>"
            f"<td>{html.escape(i['component'])}</td>"
            f"<td>{_state(i['state'])}</td>"
            f"<td>{i['pid']}</td><td>{html.escape(i.get('container') or '-')}</td><td>{i['restarts']}</td>"
            f"<td><code>{html.escape(i['interface_hash'])}</code></td>"
            f"<td>{html.escape(i['last_snapshot'] or '-')}</td></tr>")
    findings = "".join(f"<li><b>{html.escape(f['instance'])}</b>: {html.escape(f['message'])}</li>"
                       for f in data["findings"]) or "<li>none</li>"
    title = html.escape(f"{spec.name} {spec.version or ''}".strip())
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{title}: status</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
td, th {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: left; }}
.state {{ color: white; padding: 0.1em 0.5em; border-radius: 0.3em; }}
#processes {{ display: flex; flex-wrap: wrap; gap: 0.8em; align-items: flex-start; }}
.process {{ border: 1px solid #999; border-radius: 0.4em; padding: 0.4em; }}
.process.container {{ border: 2px solid #3d6fb6; background: #f3f7fd; }}
.process .title {{ margin-bottom: 0.3em; }}
.instance {{ display: inline-block; border: 1px solid #ccc; border-radius: 0.3em; background: white;
  padding: 0.3em 0.5em; margin: 0.2em; }}
</style></head>
<body>
<h1>{title}</h1>
<section id="graph">{builtin_svg(graph)}</section>
<h2>Processes</h2>
<section id="processes">{processes(data["instances"])}</section>
<table id="instances"><tr><th>instance</th><th>node</th><th>component</th><th>state</th><th>pid</th><th>container</th>
<th>restarts</th>
<th>interface hash</th><th>last snapshot</th></tr>
{chr(10).join(rows)}
</table>
<h2>Findings</h2>
<ul id="findings">{findings}</ul>
</body></html>
"""
