"""Quick fixes for habits brought from ROS 2: a constant written as a field, a ``pkg/Type`` path.

Helpers of ``code_actions`` (no handler of their own): each adds its actions to a ``Fixes``.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from lsprotocol import types as lsp

    from .code_actions import Fixes


def constant(fixes: Fixes, diag: lsp.Diagnostic, data: dict[str, Any]) -> None:
    """``uint8 MODE_A = 1`` read as a field → the constant it means (``ros-constant-as-field``)."""
    from .code_actions import QUICKFIX

    start, end = data.get("start"), data.get("end")
    if not isinstance(start, int) or not isinstance(end, int):
        return
    new = str(data["replacement"])
    fixes.add(f"Make it a constant: `{new}`", QUICKFIX, fixes.edit(start, end, new), diag, preferred=True)


def ros_type(fixes: Fixes, diag: lsp.Diagnostic, start: int, end: int, package: str, replacement: str) -> None:
    """``std_msgs/Header`` → ``std_msgs.Header``, with the include or external that provides it."""
    iface = fixes.view.iface
    declared = iface is not None and (any(e.name == package for e in iface.externals) or any(
        os.path.basename(i.path) == f"{package}.iface" for i in iface.includes))
    changes = [(start, end, replacement)]
    if declared:
        fixes.multi(f"Write '{replacement}'", changes, diag, preferred=True)
        return
    at, template = _header_end(fixes)
    lines = [f'include "{package}.iface"', f"external {package}"]
    if not _find_include(fixes, f"{package}.iface"):
        lines.reverse()
    for i, line in enumerate(lines):
        fixes.multi(f"Write '{replacement}' and add `{line}`", [(at, at, template.format(line=line)), *changes],
                    diag, preferred=i == 0)


def _header_end(fixes: Fixes) -> tuple[int, str]:
    """Where a new ``include``/``external`` line goes: after the last header line, else at the top."""
    from ...model import nodes as m

    iface = fixes.view.iface
    header = [x for x in (iface.items if iface is not None else [])
              if isinstance(x, (m.ComponentDecl, m.Namespace, m.Include, m.External))]
    if not header:
        return 0, "{line}\n"
    return max(x.span.end for x in header), "\n{line}"


def _find_include(fixes: Fixes, name: str) -> bool:
    """True when an included file ``name`` would be found (beside the file or on the include paths)."""
    view = fixes.view
    folders = [os.path.dirname(view.ver.path), *view.project.workspace().include_paths]
    return any(os.path.isfile(os.path.join(f, name)) for f in folders)
