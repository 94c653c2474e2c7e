"""The quick fix for missing package metadata (``ros2-package-metadata-missing``): license and maintainer.

A helper of ``code_actions`` (no handler of its own): it adds its action to a ``Fixes``.
"""

from __future__ import annotations

import os
import subprocess
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from lsprotocol import types as lsp

    from .code_actions import Fixes

#: The license the metadata fix proposes: ROS 2's own packages use it (the title shows it, so it is a choice).
LICENSE = "Apache-2.0"
KEYS = ("license", "maintainer", "maintainer_email")


def add_metadata(fixes: Fixes, diag: lsp.Diagnostic, missing: list[str]) -> None:
    """Add ``license`` and ``maintainer`` (with an e-mail) to the component, creating its line if needed."""
    from .code_actions import QUICKFIX

    view = fixes.view
    iface = view.iface
    if iface is None:
        return
    comp = iface.component
    have = {a.key for a in comp.annotations} if comp is not None else set()
    name, email = git_identity(os.path.dirname(view.ver.path))
    values = {"license": LICENSE, "maintainer": name, "maintainer_email": email}
    wanted = set(missing) | ({"maintainer_email"} if "maintainer" in missing else set())
    keys = [k for k in KEYS if k in wanted and k not in have]
    if not keys:
        return
    pairs = [f'{k} = "{values[k]}"' for k in keys]
    text = view.ver.text
    if comp is None:
        at, insert = 0, f"component {iface.name} ({', '.join(pairs)})\n"
    elif comp.annotations:
        at = comp.annotations[-1].span.end
        sep = ",\n    " if "\n" in text[comp.annotations[0].span.start:at] else ", "
        insert = "".join(sep + p for p in pairs)
    else:
        at, insert = comp.span.end, f" ({', '.join(pairs)})"
    shown = ", ".join(pairs[:2] if "license" in keys else pairs[:1])
    fixes.add(f"Add {shown} to the component", QUICKFIX, fixes.edit(at, at, insert), diag, preferred=True)


def git_identity(folder: str) -> tuple[str, str]:
    """The user's name and e-mail from git's configuration, as ``ros2 pkg create`` uses them; placeholders without."""

    def get(key: str) -> str:
        try:
            done = subprocess.run(["git", "config", "--get", key], cwd=folder or None, capture_output=True,
                                  text=True, timeout=5, check=False)
        except (OSError, subprocess.SubprocessError):
            return ""
        return done.stdout.strip() if done.returncode == 0 else ""

    return get("user.name") or "Your Name", get("user.email") or "you@example.com"
