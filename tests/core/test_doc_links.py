"""Every link of README.md and docs/*.md resolves: a relative link to a file that exists, an anchor to a heading.

Anchors are GitHub's: a heading's text without its markup, lower-cased, punctuation dropped, spaces as
hyphens, a repeated one numbered (``-1``, ``-2``). Links to the web (``http:``, ``https:``, ``mailto:``) are
not followed. Links inside code (fenced blocks, inline code) are not links.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

FENCE = re.compile(r"^(```|~~~).*?^\1[ \t]*$", re.MULTILINE | re.DOTALL)
INLINE_CODE = re.compile(r"`+[^`\n]*`+")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^(#{1,6})[ \t]+(.+?)[ \t]*#*[ \t]*$", re.MULTILINE)


def prose(text: str) -> str:
    """The text without fenced code blocks and inline code (their brackets are not links)."""
    return INLINE_CODE.sub("", FENCE.sub("", text))


def slug(heading: str) -> str:
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link: its text
    text = re.sub(r"<[^>]+>", "", text).replace("`", "").replace("*", "")
    text = re.sub(r"[^\w\- ]", "", text.strip().lower())
    return text.replace(" ", "-")


def anchors(text: str) -> set[str]:
    """The anchors of a document's headings (repeated ones numbered as GitHub numbers them)."""
    seen: dict[str, int] = {}
    out: set[str] = set()
    for match in HEADING.finditer(FENCE.sub("", text)):
        base = slug(match.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        out.add(base if count == 0 else f"{base}-{count}")
    return out


def links(text: str) -> list[str]:
    """The targets of the document's links (inline links and images)."""
    return LINK.findall(prose(text))


def broken(document: Path) -> list[str]:
    """The links of ``document`` that do not resolve, each with the reason."""
    out = []
    for target in links(document.read_text(encoding="utf-8")):
        if re.match(r"[a-z][a-z0-9+.-]*:", target, re.IGNORECASE):
            continue  # http:, https:, mailto:
        path, _, anchor = target.partition("#")
        file = (document.parent / path).resolve() if path else document
        if not file.exists():
            out.append(f"{target}: no such file")
        elif anchor and file.suffix == ".md" and anchor not in anchors(file.read_text(encoding="utf-8")):
            out.append(f"{target}: no heading '#{anchor}' in {file.name}")
        elif anchor and file.suffix != ".md":
            out.append(f"{target}: an anchor into a file that is not Markdown")
    return out


@pytest.mark.parametrize("document", DOCUMENTS, ids=[str(d.relative_to(ROOT)) for d in DOCUMENTS])
def test_every_link_resolves(document: Path) -> None:
    assert broken(document) == []


def test_slugs_are_githubs() -> None:
    assert slug("rclcpp: the same component in C++") == "rclcpp-the-same-component-in-c"
    assert slug("`ros2 iface`") == "ros2-iface"
    assert slug("State: save and restore (Σ)") == "state-save-and-restore-σ"
    assert slug("Releases: Kilted and Jazzy") == "releases-kilted-and-jazzy"
    assert slug("The [manager](system.md) — and *more*") == "the-manager--and-more"
    assert anchors("# A\n\n## A\n\n```\n## Not\n```\n## A\n") == {"a", "a-1", "a-2"}


def test_a_broken_link_or_anchor_is_found(tmp_path: Path) -> None:
    (tmp_path / "there.md").write_text("# Here it is\n", encoding="utf-8")
    doc = tmp_path / "doc.md"
    doc.write_text("[ok](there.md#here-it-is) [gone](missing.md) [bad](there.md#nowhere) [self](#top)\n"
                   "`[code](ignored.md)`\n\n```\n[block](ignored.md)\n```\n\n# Top\n"
                   "[web](https://example.org/x.md)\n", encoding="utf-8")
    assert links(doc.read_text(encoding="utf-8")) == ["there.md#here-it-is", "missing.md", "there.md#nowhere",
                                                      "#top", "https://example.org/x.md"]
    found = broken(doc)
    assert len(found) == 2 and found[0].startswith("missing.md") and "#nowhere" in found[1], found
