"""``system status --format html``: one self-contained page, the system graph with each instance's state and findings."""

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


def render(spec: Any, data: dict[str, Any]) -> str:
    """The page: the graph (instances named with their state), a table of the instances, the findings."""
    states = {i["name"]: i["state"] for i in data["instances"]}
    graph = graph_json(system_graph(Workspace().compile_path(str(spec.file))), _display)
    for c in graph["components"]:
        c["name"] = f"{c['name']} [{states.get(c['name'], '?')}]"
    rows = []
    for i in data["instances"]:
        colour = COLOURS.get(i["state"], "#757575")
        rows.append(
            f"<tr><td>{html.escape(i['name'])}</td><td>{html.escape(i['node'])}</td>"
            f"<td>{html.escape(i['component'])}</td>"
            f"<td><span class=\"state\" style=\"background:{colour}\">{html.escape(i['state'])}</span></td>"
            f"<td>{i['pid']}</td><td>{i['restarts']}</td><td><code>{html.escape(i['interface_hash'])}</code></td>"
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
</style></head>
<body>
<h1>{title}</h1>
<section id="graph">{builtin_svg(graph)}</section>
<table id="instances"><tr><th>instance</th><th>node</th><th>component</th><th>state</th><th>pid</th><th>restarts</th>
<th>interface hash</th><th>last snapshot</th></tr>
{chr(10).join(rows)}
</table>
<h2>Findings</h2>
<ul id="findings">{findings}</ul>
</body></html>
"""
