"""``compat --format html``: one self-contained page, verdict first, findings per set with links."""

from __future__ import annotations

import json
from pathlib import Path

import html5lib
import pytest
from compat_support import DATA, cached, run_main

from iface.compat import compare
from iface.compat.html import AREAS, render_html
from iface.compat.rules import RULES

XHTML = "{http://www.w3.org/1999/xhtml}"
CASES = [("verdicts/arm_v1.iface", "verdicts/arm_v4.iface"), ("thrift/many/old.thrift", "thrift/many/new.thrift"),
         ("verdicts/arm_v1.iface", "verdicts/arm_v3.iface")]


def _parse(text: str):  # type: ignore[no-untyped-def]
    """Parse as a browser would, failing on any HTML parse error."""
    return html5lib.HTMLParser(strict=True, namespaceHTMLElements=True).parse(text)


def _text(el) -> str:  # type: ignore[no-untyped-def]
    return " ".join("".join(el.itertext()).split())


@pytest.mark.parametrize(("old", "new"), CASES)
def test_page_has_the_verdict_first_and_every_finding_in_its_set_with_links(old: str, new: str) -> None:
    page = run_main("compat", old, new, "--format", "html")
    data = json.loads(run_main("compat", old, new, "--format", "json").stdout)
    assert page.returncode == data["exit_code"]
    assert page.stdout == run_main("compat", old, new, "--format", "html").stdout  # byte-identical
    root = _parse(page.stdout)
    body = root.find(f"{XHTML}body")
    first = next(el for el in body.iter() if el.tag.startswith(XHTML + "h"))
    assert first.tag == f"{XHTML}h1" and _text(first) == data["verdict"]
    sections = {}
    current = None
    for el in body:
        if el.tag == f"{XHTML}h2":
            current = el.get("id")
        elif el.tag == f"{XHTML}ul" and current is not None:
            sections[current] = el.findall(f"{XHTML}li")
    findings = data["findings"]
    assert sum(len(items) for items in sections.values()) == len(findings)
    for f in findings:
        area = RULES[f["rule"]].area
        items = [_text(li) for li in sections[f"set-{area}"]]
        new_at = f"{f['new']['file']}:{f['new']['line']}:{f['new']['column']}"
        old_at = f"{f['old']['file']}:{f['old']['line']}:{f['old']['column']}"
        assert any(f["rule"] in t and f["message"] in t and f"new {new_at}" in t and f"old {old_at}" in t
                   for t in items), (f, items)
    links = [(a.get("href"), _text(a)) for a in body.iter(f"{XHTML}a") if not a.get("href", "").startswith("#")]
    for href, text in links:
        path, line, _ = text.rsplit(":", 2)
        assert href == f"{path}#L{line}" and (DATA / path).is_file()
    # the summary table names the seven sets, whether or not they have findings
    table = _text(body.find(f"{XHTML}table"))
    for area in ("M", "N", "S", "A", "P", "Σ", "Δ"):
        assert AREAS[area] in table


def test_page_is_self_contained() -> None:
    text = run_main("compat", *CASES[0], "--format", "html").stdout
    root = _parse(text)
    for el in root.iter():
        assert el.tag not in (f"{XHTML}script", f"{XHTML}link", f"{XHTML}img", f"{XHTML}iframe")
        assert el.get("src") is None
        assert not (el.get("href") or "").startswith(("http:", "https:", "//"))
    assert "url(" not in text and "@import" not in text


def test_equivalent_page(tmp_path: Path) -> None:
    same = DATA / "verdicts" / "arm_v1.iface"
    page = render_html(compare(cached(same), cached(same)), str, "0")
    root = _parse(page)
    assert _text(root.find(f".//{XHTML}h1")) == "equivalent"
    assert "No differences" in _text(root.find(f"{XHTML}body"))
    assert root.find(f".//{XHTML}ul") is None


def test_text_is_escaped_and_absolute_paths_are_file_uris(tmp_path: Path) -> None:
    from iface.semantics.compile import Workspace

    old = tmp_path / "old.iface"
    new = tmp_path / "new.iface"
    old.write_text('component c\nmessage M { string<=32 s }\npublishes M on "/x"\n')
    new.write_text('component c\nmessage M { string<=64 s }\npublishes M on "/x"\n')
    ws = Workspace()
    page = render_html(compare(ws.compile_path(str(old)), ws.compile_path(str(new))), str, "0")
    root = _parse(page)
    body = _text(root.find(f"{XHTML}body"))
    assert "string<=32" in body and "string<=64" in body
    hrefs = [a.get("href") for a in root.iter(f"{XHTML}a") if not a.get("href", "").startswith("#")]
    assert hrefs and all(h.startswith((new.as_uri() + "#L", old.as_uri() + "#L")) for h in hrefs)
