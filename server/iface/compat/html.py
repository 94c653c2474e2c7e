"""The compatibility report as one self-contained HTML page.

The verdict comes first, then a table of the seven sets (and the other areas
that have findings), then the findings of each set with links to the lines in
NEW and OLD, then the state hand-over. The page has no script and loads
nothing: its style is inline, so it reads the same offline, as a CI artifact or
attached to a review. Links are the paths as the text report shows them
(relative to the working directory, so a page written there with
``> report.html`` links to the files), or ``file://`` URIs for paths outside it.
"""

from __future__ import annotations

from html import escape
from pathlib import Path
from urllib.parse import quote

from ..model.diagnostics import Severity
from .findings import Finding, Location, Report
from .report import Display, verdict_reason
from .rules import RULES

#: area of a rule -> heading, in the order of the page
AREAS: dict[str, str] = {
    "M": "M — subscribed topics",
    "N": "N — published topics",
    "M/N": "M, N — topics",
    "S": "S — services",
    "A": "A — actions",
    "P": "P — parameters",
    "Σ": "Σ — state",
    "Δ": "Δ — diagnostics",
    "types": "Types",
    "fields": "Fields",
    "services": "Service functions",
    "headers": "Namespaces",
    "system": "The system",
    "any": "Other changes",
}
SETS = ("M", "N", "S", "A", "P", "Σ", "Δ")
_LABEL = {Severity.ERROR: "breaking", Severity.WARNING: "to review", Severity.INFORMATION: "compatible",
          Severity.HINT: "compatible"}
_CLASS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFORMATION: "info", Severity.HINT: "info"}
_VERDICT_CLASS = {"equivalent": "ok", "replaceable": "ok", "replaceable-if-unused": "maybe", "incompatible": "bad"}

_STYLE = """
:root { color-scheme: light dark; --fg: #1f2328; --muted: #59636e; --bg: #ffffff; --line: #d1d9e0;
  --red: #cf222e; --amber: #9a6700; --green: #1a7f37; --blue: #0969da; --chip: #f6f8fa; }
@media (prefers-color-scheme: dark) { :root { --fg: #e6edf3; --muted: #9198a1; --bg: #0d1117;
  --line: #3d444d; --red: #f85149; --amber: #d29922; --green: #3fb950; --blue: #4493f8; --chip: #151b23; } }
body { font: 15px/1.5 -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; color: var(--fg);
  background: var(--bg); max-width: 64rem; margin: 2rem auto; padding: 0 1.5rem; }
a { color: var(--blue); }
code, .where { font-family: ui-monospace, "SF Mono", Menlo, Consolas, monospace; font-size: 0.88em; }
.verdict { border: 2px solid var(--line); border-radius: 8px; padding: 1rem 1.25rem; margin-bottom: 1.5rem; }
.verdict.ok { border-color: var(--green); } .verdict.maybe { border-color: var(--amber); }
.verdict.bad { border-color: var(--red); }
.verdict h1 { margin: 0; font-size: 1.6rem; }
.verdict.ok h1 { color: var(--green); } .verdict.maybe h1 { color: var(--amber); }
.verdict.bad h1 { color: var(--red); }
.verdict p { margin: 0.35rem 0 0; }
.muted, .hash { color: var(--muted); } .hash { font-size: 0.8em; word-break: break-all; }
table { border-collapse: collapse; margin: 0.5rem 0 1.5rem; }
th, td { text-align: left; padding: 0.25rem 0.9rem 0.25rem 0; border-bottom: 1px solid var(--line); }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
td.n.error, td.lost { color: var(--red); font-weight: 600; } td.n.warning { color: var(--amber); font-weight: 600; }
td.n.zero { color: var(--muted); }
h2 { font-size: 1.15rem; margin: 1.75rem 0 0.5rem; border-bottom: 1px solid var(--line); padding-bottom: 0.2rem; }
ul.findings { list-style: none; padding: 0; margin: 0; }
ul.findings li { border-left: 4px solid var(--line); padding: 0.35rem 0 0.35rem 0.75rem; margin: 0.5rem 0; }
li.error { border-left-color: var(--red) !important; } li.warning { border-left-color: var(--amber) !important; }
li.info { border-left-color: var(--green) !important; }
.badge { display: inline-block; font-size: 0.75em; font-weight: 600; border-radius: 1em; padding: 0 0.6em;
  background: var(--chip); border: 1px solid var(--line); margin-right: 0.4em; }
li.error .badge.sev { color: var(--red); border-color: var(--red); }
li.warning .badge.sev { color: var(--amber); border-color: var(--amber); }
li.info .badge.sev { color: var(--green); border-color: var(--green); }
.detail { margin: 0.15rem 0 0; } .where { margin-top: 0.15rem; color: var(--muted); }
footer { margin-top: 2.5rem; color: var(--muted); font-size: 0.85em; }
"""


def _e(text: object) -> str:
    return escape(str(text), quote=True)


def _href(path: str, line: int) -> str:
    if Path(path).is_absolute():
        return f"{Path(path).as_uri()}#L{line}"
    return f"{quote(path.replace(chr(92), '/'))}#L{line}"


def _link(loc: Location, display: Display) -> str:
    line, col, _, _ = loc.position()
    path = display(loc.source.path)
    return f'<a href="{_e(_href(path, line))}">{_e(path)}:{line}:{col}</a>'


def _area(f: Finding) -> str:
    rule = RULES.get(f.rule)
    return rule.area if rule is not None and rule.area in AREAS else "any"


def _finding(f: Finding, display: Display) -> list[str]:
    cls = _CLASS[f.severity]
    out = [f'<li class="{cls}">',
           f'<div><span class="badge sev">{_LABEL[f.severity]}</span><code>{_e(f.rule)}</code> '
           f"<strong>{_e(f.subject)}</strong></div>",
           f'<div class="detail">{_e(f.message)}</div>']
    extra = [("breaks", f.breaks), ("affects", ", ".join(f.components)), ("provided by", ", ".join(f.satisfied_by))]
    out.extend(f'<div class="detail"><span class="muted">{name}:</span> {_e(text)}</div>' for name, text in extra if text)
    out.append(f'<div class="where">new {_link(f.new, display)} · old {_link(f.old, display)}</div>')
    out.append("</li>")
    return out


def render_html(report: Report, display: Display, version: str) -> str:
    """The report as a self-contained HTML page."""
    old, new = display(report.old.path), display(report.new.path)
    verdict = report.verdict
    counts = {s: report.count(s) for s in (Severity.ERROR, Severity.WARNING, Severity.INFORMATION)}
    by_area: dict[str, list[Finding]] = {}
    for f in report.findings:
        by_area.setdefault(_area(f), []).append(f)
    out = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
           '<meta name="viewport" content="width=device-width, initial-scale=1">',
           f"<title>{_e(verdict)}: can {_e(Path(new).name)} replace {_e(Path(old).name)}? — iface compat</title>",
           f"<style>{_STYLE}</style>", "</head>", "<body>",
           f'<section class="verdict {_VERDICT_CLASS.get(verdict, "bad")}">',
           f"<h1>{_e(verdict)}</h1>",
           f"<p>Can <strong>{_e(new)}</strong> replace <strong>{_e(old)}</strong>? {_e(verdict_reason(report))}.</p>",
           f'<p class="muted">{counts[Severity.ERROR]} breaking, {counts[Severity.WARNING]} to review, '
           f"{counts[Severity.INFORMATION]} compatible · exit code {report.exit_code}"
           + (f" · system: {_e(', '.join(display(c.path) for c in report.system))}" if report.system else "")
           + "</p>",
           f'<p class="hash">old {_e(report.old_hash)}<br>new {_e(report.new_hash)}</p>',
           "</section>",
           "<table>", "<thead><tr><th>set</th><th>breaking</th><th>to review</th><th>compatible</th></tr></thead>",
           "<tbody>"]
    for area in [*SETS, *(a for a in AREAS if a not in SETS and a in by_area)]:
        found = by_area.get(area, [])
        cells = []
        for sev, cls in ((Severity.ERROR, "error"), (Severity.WARNING, "warning"), (Severity.INFORMATION, "info")):
            n = sum(1 for f in found if f.severity == sev)
            cells.append(f'<td class="n {cls if n else "zero"}">{n}</td>')
        name = f'<a href="#set-{_e(area)}">{_e(AREAS[area])}</a>' if found else _e(AREAS[area])
        out.append(f"<tr><td>{name}</td>{''.join(cells)}</tr>")
    out.extend(["</tbody>", "</table>"])
    if not report.findings:
        out.append('<p class="muted">No differences: every set has the same elements of the same types.</p>')
    for area, heading in AREAS.items():
        if area not in by_area:
            continue
        out.append(f'<h2 id="set-{_e(area)}">{_e(heading)}</h2>')
        out.append('<ul class="findings">')
        for f in by_area[area]:
            out.extend(_finding(f, display))
        out.append("</ul>")
    h = report.handover
    if h.carried or h.new or h.lost:
        out.extend(['<h2 id="handover">State hand-over</h2>', "<table>",
                    "<thead><tr><th>state variable</th><th>type</th><th>on hand-over</th></tr></thead>", "<tbody>"])
        for v in h.carried:
            out.append(f"<tr><td><code>{_e(v.name)}</code></td><td><code>{_e(v.type)}"
                       f"{' → ' + _e(v.new_type) if v.new_type else ''}</code></td><td>carried over</td></tr>")
        for v in h.new:
            what = "new, needs an initial value" if v.initial is None else f"new, starts at {_e(v.initial)}"
            out.append(f"<tr><td><code>{_e(v.name)}</code></td><td><code>{_e(v.type)}</code></td><td>{what}</td></tr>")
        for v in h.lost:
            out.append(f'<tr><td><code>{_e(v.name)}</code></td><td><code>{_e(v.type)}</code></td>'
                       f'<td class="lost">lost</td></tr>')
        out.extend(["</tbody>", "</table>"])
    out.extend([f"<footer>iface-lsp {_e(version)} compat · rules: docs/compat.md</footer>", "</body>", "</html>"])
    return "\n".join(out) + "\n"
