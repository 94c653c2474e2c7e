"""Markdown (CommonMark/GFM) escaping: untrusted text stays text, in paragraphs and in table cells."""

from __future__ import annotations

import re

from ..text import CONTROL

_INLINE = re.compile(r"([\\`*_\[\]#|~!])")
_LINE_START = re.compile(r"^(\s*)([-+=]|\d+[.)])")


def _inline(text: str) -> str:
    text = CONTROL.sub(" ", text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return _INLINE.sub(r"\\\1", text)


def _block_start(text: str) -> str:
    """Escape what would start a list or a heading underline at the start of a block."""
    return _LINE_START.sub(lambda mt: mt.group(1) + "\\" + mt.group(2) if not mt.group(2)[0].isdigit()
                           else mt.group(1) + mt.group(2)[:-1] + "\\" + mt.group(2)[-1], text, count=1)


def md(text: str | None) -> str:
    """Text for a table cell or a list item: one line, every Markdown and HTML special character escaped."""
    if not text:
        return ""
    return " ".join(_inline(line.strip()) for line in text.splitlines() if line.strip())


def paragraphs(text: str | None) -> list[str]:
    """A doc comment as escaped paragraphs (blank lines separate paragraphs)."""
    if not text:
        return []
    out: list[str] = []
    current: list[str] = []
    for line in text.splitlines() + [""]:
        if line.strip():
            current.append(line.strip())
        elif current:
            out.append(_block_start(md("\n".join(current))))
            current = []
    return out


def code(text: str | None) -> str:
    """An identifier or type in a code span; text a code span cannot hold is escaped instead."""
    if not text:
        return ""
    if "`" in text or CONTROL.search(text) or any(c in text for c in "\n\r\u2028\u2029"):
        return md(text)
    return "`" + text.replace("|", "\\|") + "`"
