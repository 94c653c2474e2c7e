"""From a component description to the text of the rclpy package: Python literals, names, imports."""

from __future__ import annotations

import keyword
import math
from dataclasses import dataclass
from typing import Any

from ...emit.text import comment_lines, one_line
from ..component import ComponentSpec, ParamSpec, RosRef
from ..layout import WIDTH, wrap
from ..qosmap import node_qos
from ..template_data import MemberView, NodeView, type_aliases

#: Names the generated modules define, import or use themselves (the builtins their code raises or imports).
_TAKEN = frozenset({"Any", "ComponentNode", "HandlerSpec", "ParamSpec", "DEFAULT_TIMEOUT_SEC", "annotations",
                    "sys", "main", "run", "ImportError", "NotImplementedError", "RuntimeError", "TimeoutError"})


def py(value: Any) -> str:
    """A Python literal for plain data (None, bool, int, float, str, list, tuple, dict)."""
    if value is None or isinstance(value, (bool, int)):
        return repr(value)
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else f'float("{value}")'
    if isinstance(value, str):
        return repr(value)
    if isinstance(value, tuple):
        inner = ", ".join(py(v) for v in value)
        return f"({inner},)" if len(value) == 1 else f"({inner})"
    if isinstance(value, list):
        return "[" + ", ".join(py(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{py(k)}: {py(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no Python literal for {type(value).__name__}")


def doc_text(line: str) -> str:
    """A line for a docstring: backslashes and quotes escaped, so nothing ends the string."""
    return line.replace("\\", "\\\\").replace('"', '\\"')


def doc(text: str | None) -> list[str]:
    """Docstring-safe lines of a doc comment."""
    return [doc_text(line) for line in comment_lines(text)]


def docstring(lines: list[str] | str, indent: int = 8, width: int = WIDTH) -> str:
    """A docstring from escaped lines: the first on the opening line, the others as paragraphs below it; a line
    longer than ``width`` allows wrapped."""
    lines = [lines] if isinstance(lines, str) else list(lines)
    pad = " " * indent
    head = wrap(lines[0] if lines else "", indent + 6, width=width)  # the quotes that open and close it
    if len(lines) <= 1 and len(head) == 1:
        return f'"""{head[0]}"""'
    out = [head[0], *(pad + line for line in head[1:])]
    if len(lines) > 1:
        out.append("")
        for line in lines[1:]:
            if line:
                out.extend(pad + part for part in wrap(line, indent, width=width))
            else:
                out.append("")
    return '"""' + "\n".join(out) + f'\n{pad}"""'


def qos_literal(qos: dict[str, str]) -> str:
    """The member's QoS for ``qos_profile``: depth as a number, durations in seconds."""
    return py(dict(node_qos(qos)))


@dataclass
class PyPackage(NodeView[MemberView]):
    """Everything the templates of the component package need."""

    client_library = "rclpy"

    def comment(self, text: str) -> str:
        """One line, safe inside a docstring."""
        return doc_text(one_line(text))

    def imports(self, refs: list[RosRef]) -> list[str]:
        """``from pkg.kind import A, B as C`` lines for ``refs``, sorted."""
        by_module: dict[str, set[str]] = {}
        for ref in refs:
            alias = self.aliases[ref]
            by_module.setdefault(ref.module, set()).add(ref.name if alias == ref.name else f"{ref.name} as {alias}")
        out = []
        for module, names in sorted(by_module.items()):
            line = f"from {module} import {', '.join(sorted(names))}"
            if len(line) > 100:
                line = f"from {module} import (\n" + "".join(f"    {n},\n" for n in sorted(names)) + ")"
            out.append(line)
        return out

    def user_refs(self) -> list[RosRef]:
        """The types the user module's handler signatures name."""
        return sorted({v.m.type for v in self.members if v.m.kind in ("subscription", "server", "diagnostics",
                                                                         "action_server")},
                      key=lambda r: (r.package, r.kind, r.name))

    def handlers_literal(self) -> list[str]:
        """Lines of the HANDLERS mapping."""
        out = []
        for h, x in self.spec.handlers():
            req = "" if h.required else ", required=False"
            out.append(f"{py(h.name)}: HandlerSpec({py(h.args)}, {py(x.what)}{req}),")
        return out

    def param_literal(self, p: ParamSpec) -> str:
        """The ParamSpec(...) constructor of a parameter."""
        args: list[tuple[str, Any]] = [("kind", p.kind), ("default", p.default), ("description", p.description),
                                       ("constraints", p.constraints), ("unit", p.unit), ("low", p.low),
                                       ("high", p.high), ("read_only", p.read_only),
                                       ("choices", tuple(tuple(c) for c in p.choices)),
                                       ("max_length", p.max_length), ("size", p.size), ("size_kind", p.size_kind)]
        def given(value: Any) -> bool:
            return not (value is None or value is False or value == () or value == "")

        shown = ", ".join(f"{k}={py(v)}" for k, v in args if given(v) or k == "kind")
        return f"ParamSpec({py(p.name)}, {shown})"

    def param_cast(self, p: ParamSpec) -> str:
        """The expression of a typed accessor."""
        value = f"self._node._parameter({py(p.name)})"
        if p.kind == "double":
            return f"float({value})"
        if p.kind.endswith("_array"):
            return f"list({value})"
        return value


def build(spec: ComponentSpec) -> PyPackage:
    """The view of ``spec`` the templates render."""
    view = PyPackage(spec, spec.source_name, type_aliases(spec, _TAKEN, keyword.iskeyword))
    view.members = [MemberView(x, view.aliases[x.type], qos_literal(x.qos), doc("\n".join(x.doc)), view.comment(x.what))
                    for x in spec.all_members()]
    return view
