"""Golden files: compare generated files byte for byte; ``UPDATE_GOLDEN=1`` rewrites them."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from iface.emit.base import GeneratedFile

GOLDEN = Path(__file__).parent / "golden"


def check_golden(target: str, case: str, files: list[GeneratedFile]) -> None:
    """Assert that ``files`` equal tests/emit/golden/<target>/<case>/ exactly (no missing, no extra)."""
    folder = GOLDEN / target / case
    if os.environ.get("UPDATE_GOLDEN") == "1":
        if folder.exists():
            shutil.rmtree(folder)
        for f in files:
            path = folder / f.path
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(f.text.encode("utf-8"))
    expected = {p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*")
                if p.is_file() and "__pycache__" not in p.parts}  # bytecode of a golden .py is not a generated file
    actual = {f.path: f.text.encode("utf-8") for f in files}
    assert sorted(actual) == sorted(expected), f"golden {target}/{case}: file lists differ"
    for path, data in actual.items():
        assert data == expected[path], f"golden {target}/{case}/{path} differs (UPDATE_GOLDEN=1 rewrites it)"


def check_component_golden(target: str, case: str, files: list[GeneratedFile]) -> None:
    """Like :func:`check_golden` for a node target, for the files of the case's own packages only.

    The shared packages are left out: the runtimes are real source (``iface.nodes.runtimes``, copied as
    they are: tests/runtime/test_runtime_packages.py), ``iface_msgs`` has its golden of its own
    (golden/ros2/iface_msgs, tests/runtime/test_shared.py).
    """
    from iface.nodes.shared import PACKAGES

    shared_names = {e.name for e in PACKAGES if target in e.targets}
    found = {f.path.split("/", 1)[0] for f in files}
    assert shared_names <= found, f"{target}/{case}: a shared package is missing"
    check_golden(target, case, [f for f in files if f.path.split("/", 1)[0] not in shared_names])
