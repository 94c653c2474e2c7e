"""Generated Python a linter accepts: pyflakes (PyPI) finds nothing in any generated ``.py`` file.

Over every example and test component's rclpy package, the system launch files and the shared runtime:
no unused import, no undefined name, no redefinition — what a user's CI linter would flag in code they
did not write.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from pyflakes.api import check
from pyflakes.reporter import Reporter

from iface.emit import generate
from iface.semantics.compile import Workspace

from ..ros_harness.ros import DATA, ROOT

INTERFACES = sorted([*ROOT.glob("examples/*.iface"), *DATA.glob("*.iface"), *DATA.glob("live/*.iface")])


class _Collect(Reporter):
    def __init__(self) -> None:
        self.found: list[str] = []

    def unexpectedError(self, filename: str, msg: str) -> None:  # noqa: N802 (pyflakes' name)
        self.found.append(f"{filename}: {msg}")

    def syntaxError(self, filename: str, msg: str, lineno: int, offset: int, text: str) -> None:  # noqa: N802
        self.found.append(f"{filename}:{lineno}: {msg}")

    def flake(self, message: object) -> None:
        self.found.append(str(message))


def _flakes(iface: Path, target: str) -> list[str]:
    result = generate(Workspace().compile_path(str(iface)), target)
    if result.has_errors:
        return []  # a file the target refuses writes nothing
    reporter = _Collect()
    for f in result.files:
        if f.path.endswith(".py"):
            check(f.text, f.path, reporter)
    return reporter.found


@pytest.mark.parametrize("target", ["rclpy", "launch"])
@pytest.mark.parametrize("iface", INTERFACES, ids=[p.stem for p in INTERFACES])
def test_generated_python_has_no_flakes(iface: Path, target: str) -> None:
    assert _flakes(iface, target) == []


def test_the_checker_finds_an_unused_import() -> None:
    reporter = _Collect()
    check("import os\n", "x.py", reporter)
    assert reporter.found and "imported but unused" in reporter.found[0]
