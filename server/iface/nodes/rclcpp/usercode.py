"""Does the user's ``src/node.cpp`` still match the interface? Read without compiling it (``generate --check``).

The compiler says the same when the package is built (a missing handler leaves the class
abstract; a stale one marked ``override`` overrides nothing); this reports at the user's line
without ROS. It reads the class that derives from the generated base, as the template writes it.
"""

from __future__ import annotations

import re

from ...model.diagnostics import Diagnostic, Severity
from ...model.source import Source, Span
from ..codes import diag
from ..component import HANDLER_PREFIXES, RESERVED, ComponentSpec

_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.DOTALL)
_METHOD = re.compile(r"\b(?P<name>[A-Za-z_][A-Za-z0-9_]*)\s*\(")


def _blank(text: str) -> str:
    """The text with comments and string literals replaced by spaces (offsets kept)."""
    def spaces(m: re.Match[str]) -> str:
        return re.sub(r"[^\n]", " ", m.group(0))

    text = re.sub(r'"(?:\\.|[^"\\\n])*"', spaces, text)
    return _COMMENT.sub(spaces, text)


def _class_body(text: str, base: str) -> tuple[str, int, int] | None:
    """(class name, body start, body end) of the class deriving from ``base``."""
    found = re.search(r"\b(?:class|struct)\s+(?P<name>[A-Za-z_]\w*)[^;{]*?:\s*[^;{]*\b" + re.escape(base) + r"\b[^{;]*\{",
                      text)
    if found is None:
        return None
    depth, i = 1, found.end()
    while i < len(text) and depth:
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        i += 1
    return found.group("name"), found.end(), i - 1


def _top_level(body: str) -> str:
    """The body with nested braces' contents (method bodies) blanked."""
    out, depth = [], 0
    for ch in body:
        if ch == "}":
            depth -= 1
        out.append(ch if depth == 0 or ch == "\n" else " ")
        if ch == "{":
            depth += 1
    return "".join(out)


def check_user_source(spec: ComponentSpec, path: str, text: str, *, strict: bool) -> list[Diagnostic]:
    """Where the user's class in ``text`` does not match the interface; errors when ``strict``."""
    source = Source(path, text)
    base = f"{spec.class_name}Base"

    def found(message: str, start: int, length: int) -> Diagnostic:
        d = diag("runtime-user-code", message, source, Span(start, start + length))
        if strict:
            d.severity = Severity.ERROR
        return d

    clean = _blank(text)
    cls = _class_body(clean, base)
    if cls is None:
        return [found(f"no class derives from {base}: the node cannot be built (expected class {spec.class_name} "
                      f": public {base})", 0, 0)]
    name, start, end = cls
    body = _top_level(clean[start:end])
    methods: dict[str, int] = {}
    for m in _METHOD.finditer(body):
        methods.setdefault(m.group("name"), start + m.start("name"))
    out = []
    handlers = {h.name: (h, x) for h, x in spec.handlers()}
    for hname, (h, x) in handlers.items():
        if hname not in methods and h.required:
            out.append(found(f"{name} has no {hname}({', '.join(h.args)}), which handles '{x.what}' of "
                             f"{spec.source_name}", start, 0))
    for mname, offset in methods.items():
        if mname.startswith(HANDLER_PREFIXES) and mname not in handlers and mname not in RESERVED:
            out.append(found(f"{name}::{mname} handles nothing in {spec.source_name} (was its member renamed or "
                             "removed?)", offset, len(mname)))
    return out
