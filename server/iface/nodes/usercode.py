"""Does a user module still match the interface? Read without running it (``generate --check``).

The generated node makes the same check when it starts (``interface_problems``); this one needs
no ROS and reports at the line of the user's code.
"""

from __future__ import annotations

import ast

from ..model.diagnostics import Diagnostic, Severity
from ..model.source import Source, Span
from .codes import diag
from .component import HANDLER_PREFIXES, RESERVED, ComponentSpec


def _span(source: Source, node: ast.AST) -> Span:
    line = getattr(node, "lineno", 1) - 1
    col = getattr(node, "col_offset", 0)
    starts = source.line_starts
    start = (starts[line] if line < len(starts) else len(source.text)) + col
    return Span(start, start + len(getattr(node, "name", "")))


def _accepts(fn: ast.FunctionDef | ast.AsyncFunctionDef, count: int) -> bool:
    a = fn.args
    if a.vararg is not None:
        return True
    positional = [*a.posonlyargs, *a.args][1:]  # self
    needed = len(positional) - len(a.defaults)
    kw_needed = [k for k, d in zip(a.kwonlyargs, a.kw_defaults) if d is None]
    return needed <= count <= len(positional) and not kw_needed


def check_user_module(spec: ComponentSpec, path: str, text: str, *, strict: bool) -> list[Diagnostic]:
    """Where the class of ``text`` (the user module of ``spec``) does not match the interface.

    ``strict`` makes the findings errors (``generate --check``); otherwise they are warnings.
    """
    source = Source(path, text)
    base = f"{spec.class_name}Base"

    def found(message: str, node: ast.AST | None) -> Diagnostic:
        d = diag("runtime-user-code", message, source, _span(source, node) if node is not None else Span(0, 0))
        if strict:
            d.severity = Severity.ERROR
        return d

    try:
        tree = ast.parse(text, filename=path)
    except SyntaxError as e:
        line = (e.lineno or 1) - 1
        start = source.line_starts[min(line, len(source.line_starts) - 1)] + max((e.offset or 1) - 1, 0)
        d = diag("runtime-user-code", f"the user module does not parse: {e.msg}", source, Span(start, start))
        if strict:
            d.severity = Severity.ERROR
        return [d]
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef)
               and any(isinstance(b, ast.Name) and b.id == base or isinstance(b, ast.Attribute) and b.attr == base
                       for b in n.bases)]
    if not classes:
        return [found(f"no class derives from {base}: the node cannot start (expected class {spec.class_name}"
                      f"({base}))", None)]
    cls = classes[0]
    methods = {n.name: n for n in cls.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
    ignored: set[str] = set()
    for n in cls.body:
        if isinstance(n, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "NOT_HANDLERS" for t in n.targets):
            try:
                ignored = set(ast.literal_eval(n.value))
            except ValueError:
                pass
    out = []
    handlers = {h.name: (h, x) for h, x in spec.handlers()}
    for name, (h, x) in handlers.items():
        fn = methods.get(name)
        args = ", ".join(("self", *h.args))
        if fn is None:
            if h.required:
                out.append(found(f"{cls.name} has no {name}({args}), which handles '{x.what}' of "
                                 f"{spec.source_name}", cls))
        elif not _accepts(fn, len(h.args)):
            out.append(found(f"{cls.name}.{name} cannot be called with ({', '.join(h.args)}), as '{x.what}' "
                             "calls it", fn))
    known = RESERVED
    for name, fn in methods.items():
        if name.startswith(HANDLER_PREFIXES) and name not in handlers and name not in ignored and name not in known:
            out.append(found(f"{cls.name}.{name} handles nothing in {spec.source_name} (was its member renamed or "
                             "removed? list helper methods with such names in NOT_HANDLERS)", fn))
    return out
