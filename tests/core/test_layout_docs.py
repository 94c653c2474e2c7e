"""The layout as documented is the layout on disk: docs/architecture.md (the README links to it).

Every folder of ``server/iface`` that holds a file is named in docs/architecture.md, no folder it names
is gone, the "may import" column is the rule ``test_layering`` enforces, the diagram
has every stage, and every file named under "Where to add…" exists.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

from tests.core.test_layering import ALLOWED, PACKAGE

ROOT = PACKAGE.parents[1]
ARCHITECTURE = ROOT / "docs" / "architecture.md"


def tree_folders(package: Path = PACKAGE) -> set[str]:
    """Folders under ``package`` (relative, with a trailing slash) that hold a committed file.

    The tree is git's (work in progress that is not committed yet is not the layout); outside a
    checkout, every file on disk.
    """
    try:
        listed = subprocess.run(["git", "ls-files", "-z", "--", "."], cwd=package, capture_output=True,
                                check=True, timeout=60).stdout.decode().split("\0")
        files = [package / f for f in listed if f]
    except (OSError, subprocess.SubprocessError):
        files = [p for p in package.rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    return {f.parent.relative_to(package).as_posix() + "/" for f in files if f.parent != package}


def unnamed_folders(doc: str, folders: set[str]) -> list[str]:
    """The folders of ``folders`` that ``doc`` does not name (in backticks), a target's own templates/ aside."""
    missing = []
    for folder in sorted(folders):
        parts = folder.rstrip("/").split("/")
        if parts[-1] == "templates" and len(parts) > 2:
            continue  # a target's own templates: "one package per target, each with its templates/"
        if f"`{folder}`" not in doc:
            missing.append(folder)
    return missing


def named_folders(doc: str) -> set[str]:
    """The folders of ``server/iface`` the table of the stages names (``emit/ros2/``; no placeholders, and not
    ``templates/`` alone: "each with its ``templates/``")."""
    section = doc.split("## The stages", 1)[1].split("\n## ", 1)[0]
    rows = "\n".join(line for line in section.splitlines() if line.startswith("| `"))
    return {f for f in re.findall(r"`([\w/]+/)`", rows) if f != "templates/"}


def test_architecture_names_every_folder() -> None:
    assert unnamed_folders(ARCHITECTURE.read_text(encoding="utf-8"), tree_folders()) == []


def test_architecture_names_no_folder_that_is_gone() -> None:
    named = named_folders(ARCHITECTURE.read_text(encoding="utf-8"))
    assert len(named) >= 20
    assert sorted(f for f in named if not (PACKAGE / f).is_dir()) == [], "named in docs/architecture.md, not on disk"


def test_a_folder_left_out_of_architecture_is_found() -> None:
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    assert "`nodes/rclpy/`" in doc
    assert unnamed_folders(doc.replace("`nodes/rclpy/`", "the rclpy target"), tree_folders()) == ["nodes/rclpy/"]
    assert unnamed_folders(doc, tree_folders() | {"nodes/new_target/"}) == ["nodes/new_target/"]


def _may_import(cell: str, stage: str) -> frozenset[str]:
    if cell.startswith("nothing"):
        return frozenset()
    if cell.startswith("every stage but"):
        return frozenset(ALLOWED) - {stage, *re.findall(r"`(\w+)`", cell)}
    return frozenset(re.findall(r"`(\w+)`", cell))


def test_architecture_table_is_the_enforced_rule() -> None:
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    table: dict[str, frozenset[str]] = {}
    for line in doc.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        m = re.fullmatch(r"`(\w+)/`", cells[0]) if len(cells) == 3 else None
        if m:
            table[m.group(1)] = _may_import(cells[2], m.group(1))
    assert table == ALLOWED


def test_architecture_diagram_draws_every_stage() -> None:
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    diagram = doc.split("```mermaid", 1)[1].split("```", 1)[0]
    assert sorted(s for s in ALLOWED if f'"{s}/' not in diagram) == []


def test_where_to_add_names_files_that_exist() -> None:
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    section = doc.split("## Where to add", 1)[1].split("\n## ", 1)[0]
    named = [p for p in re.findall(r"`([\w./-]+\.(?:py|iface|toml))`", section) if "<" not in p]
    assert len(named) >= 8
    missing = [p for p in named if not any((base / p).exists() for base in (PACKAGE, ROOT, ROOT / "tests" / "lsp",
                                                                            ROOT / "tests" / "core" / "data" / "invalid"))]
    assert missing == []


CORE = ("model", "syntax", "semantics")


def _modules(package: str) -> list[str]:
    return sorted(p.stem for p in (PACKAGE / package).glob("*.py") if p.stem != "__init__")


def test_core_package_docstrings_name_every_module_and_no_gone_one() -> None:
    for package in CORE:
        doc = (PACKAGE / package / "__init__.py").read_text(encoding="utf-8").split('"""')[1]
        named = set(re.findall(r"``(\w+)``", doc))
        assert [mod for mod in _modules(package) if mod not in named] == [], package
        assert [w for w in ("oldgen", "SpanTable") if w in doc] == [], package


def test_architecture_names_every_core_module_and_no_gone_one() -> None:
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    rows = {line.split("|")[1].strip(): line for line in doc.splitlines() if line.startswith("| `")}
    for package in CORE:
        row = rows[f"`{package}/`"]
        assert [mod for mod in _modules(package) if f"`{mod}`" not in row] == [], package
    assert [w for w in ("oldgen", "SpanTable") if w in doc] == []


def test_where_to_add_a_check_names_every_rule_registry() -> None:
    from iface.semantics import validate
    doc = ARCHITECTURE.read_text(encoding="utf-8")
    section = doc.split("## Where to add", 1)[1].split("\n## ", 1)[0]
    decorators = [n for n in ("rule", "local_rule", "definition_rule", "wiring_rule") if callable(getattr(validate, n))]
    registries = [n for n in dir(validate) if n.endswith("RULES") and isinstance(getattr(validate, n), list)]
    assert len(registries) == len(decorators) == 4
    assert [d for d in decorators if f"`@{d}" not in section] == []
