"""Architecture rules: dependencies point down the pipeline; only the LSP layer imports pygls/lsprotocol.

The layer order is written once, here, and drawn in docs/architecture.md:
model → syntax → semantics → text → forms → emit → importers; compat beside them;
nodes (generating node packages) above emit and compat; live (reading the graph) and operate (running a
system) above nodes, operate above live; commands and lsp on top, neither importing the other.
Generation never imports the code that reads or runs a live system. ``ros2_command`` (``ros2 iface``) is the only
importer of ros2cli, and nothing imports it: the ``ros2`` command loads it through the entry points.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "server" / "iface"

#: Each stage and the stages it may import (its own modules always).
ALLOWED: dict[str, frozenset[str]] = {
    "model": frozenset(),
    "syntax": frozenset({"model"}),
    "semantics": frozenset({"model", "syntax"}),
    "text": frozenset({"model", "syntax"}),
    "forms": frozenset({"model", "syntax", "semantics", "text"}),
    "emit": frozenset({"model", "syntax", "semantics", "text", "forms"}),
    "importers": frozenset({"model", "syntax", "semantics", "text", "forms", "emit"}),
    "compat": frozenset({"model", "syntax", "semantics"}),
    "nodes": frozenset({"model", "syntax", "semantics", "text", "forms", "emit", "compat"}),
    "live": frozenset({"model", "syntax", "semantics", "text", "forms", "compat", "nodes"}),
    "operate": frozenset({"model", "syntax", "semantics", "text", "forms", "compat", "nodes", "live"}),
    "commands": frozenset({"model", "syntax", "semantics", "text", "forms", "emit", "importers", "compat",
                           "nodes", "live", "operate"}),
    "lsp": frozenset({"model", "syntax", "semantics", "text", "forms", "emit", "importers", "compat", "nodes",
                      "live", "operate"}),
}
#: Modules at the top of the package: the entry points, which may import every stage.
TOP = frozenset({"__init__", "__main__", "cli", "ros2_command"})
EDITOR_PROTOCOL = frozenset({"pygls", "lsprotocol"})
#: ros2cli's packages: only where ROS 2 is sourced, so only the ``ros2 iface`` entry point imports them.
ROS2CLI = frozenset({"ros2cli", "ros2node"})
ROS2_ENTRY = "ros2_command"


def _stage(path: Path, root: Path = PACKAGE) -> str:
    rel = path.relative_to(root)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _imports(path: Path, root: Path = PACKAGE) -> list[tuple[int, str]]:
    """(line, absolute module) of every import in ``path`` (a module under ``root``), relative ones resolved."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = ["iface", *path.relative_to(root).with_suffix("").parts][:-1]
    out: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.extend((node.lineno, a.name) for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                mod = ".".join([*base, *([node.module] if node.module else [])])
            else:
                mod = node.module or ""
            if node.module is None or mod in ("iface", *("iface." + s for s in ALLOWED)):
                out.extend((node.lineno, f"{mod}.{a.name}") for a in node.names)
            else:
                out.append((node.lineno, mod))
    return out


def _modules() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def _upward(path: Path, root: Path = PACKAGE) -> list[str]:
    """The imports of ``path`` that break the layer order."""
    stage = _stage(path, root)
    if stage in TOP:
        return []
    out = []
    for line, mod in _imports(path, root):
        parts = mod.split(".")
        if parts[0] != "iface" or len(parts) < 2:
            continue
        target = parts[1]
        if target not in ALLOWED and target not in TOP:
            continue  # a name defined in iface/__init__.py (e.g. __version__)
        if target != stage and target not in ALLOWED[stage]:
            out.append(f"{path.relative_to(root)}:{line}: {stage} imports {mod}")
    return out


def test_every_module_belongs_to_a_known_stage() -> None:
    unknown = sorted({_stage(p) for p in _modules()} - set(ALLOWED) - TOP)
    assert unknown == [], "a new top-level package needs a place in ALLOWED and in docs/architecture.md"


def test_imports_point_down_the_pipeline() -> None:
    offenders = [o for path in _modules() for o in _upward(path)]
    assert offenders == []


def test_the_rule_catches_upward_imports(tmp_path: Path) -> None:
    (tmp_path / "model").mkdir()
    probe = tmp_path / "model" / "probe.py"
    probe.write_text("from ..commands import common\nfrom ..lsp.server import X\nimport iface.cli\n"
                     "from . import walk\nfrom .. import __version__\n", encoding="utf-8")
    assert _upward(probe, tmp_path) == ["model/probe.py:1: model imports iface.commands.common",
                                        "model/probe.py:2: model imports iface.lsp.server",
                                        "model/probe.py:3: model imports iface.cli"]


def test_only_the_lsp_layer_imports_pygls() -> None:
    offenders = []
    for path in _modules():
        if _stage(path) == "lsp":
            continue
        if {mod.split(".")[0] for _, mod in _imports(path)} & EDITOR_PROTOCOL:
            offenders.append(str(path.relative_to(PACKAGE)))
    assert offenders == []


def test_only_the_ros2_entry_point_imports_ros2cli_and_nothing_imports_it() -> None:
    """``ros2_command`` is loaded by ``ros2`` through its entry points alone: ros2cli is not there without ROS 2."""
    importers, users = [], []
    for path in _modules():
        mods = {mod for _, mod in _imports(path)}
        if path.stem != ROS2_ENTRY and {m.split(".")[0] for m in mods} & ROS2CLI:
            importers.append(str(path.relative_to(PACKAGE)))
        if any(m == f"iface.{ROS2_ENTRY}" or m.startswith(f"iface.{ROS2_ENTRY}.") for m in mods):
            users.append(str(path.relative_to(PACKAGE)))
    assert importers == [] and users == []
    root = PACKAGE.parents[1]
    entry_points = (root / "pyproject.toml").read_text(encoding="utf-8")
    assert f'"iface.{ROS2_ENTRY}:IfaceCommand"' in entry_points


def test_every_package_says_what_it_holds_and_may_import() -> None:
    missing = []
    for init in sorted(PACKAGE.rglob("__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
        if "May import" not in doc:
            missing.append(str(init.relative_to(PACKAGE)))
    assert missing == []


def test_grammar_file_is_the_packaged_one() -> None:
    root = PACKAGE.parents[1] / "grammar.lark"
    assert (PACKAGE / "grammar.lark").read_text() == root.read_text()


#: Imports known not to resolve, each reported to its area's owner; remove an entry once it is fixed.
KNOWN_UNRESOLVED: frozenset[str] = frozenset()


def _unresolved(path: Path, root: Path = PACKAGE) -> list[str]:
    """The iface imports of ``path`` naming no module and no name of an existing module (moved code)."""
    out = []
    for _, mod in _imports(path, root):
        parts = mod.split(".")
        if parts[0] != "iface" or len(parts) < 2:
            continue
        if importlib.util.find_spec(mod.rsplit(".", 1)[0]) is None:
            out.append(f"{path.relative_to(root)}: {mod}")
        elif importlib.util.find_spec(mod) is None and not hasattr(importlib.import_module(mod.rsplit(".", 1)[0]),
                                                                    parts[-1]):
            out.append(f"{path.relative_to(root)}: {mod}")
    return out


def test_every_import_names_something_that_exists() -> None:
    found = {u for path in _modules() for u in _unresolved(path)}
    assert sorted(found - KNOWN_UNRESOLVED) == []


def test_unresolved_imports_are_found(tmp_path: Path) -> None:
    (tmp_path / "lsp").mkdir()
    probe = tmp_path / "lsp" / "probe.py"
    probe.write_text("from ..grammar import x\nfrom ..model.nosuch import x\nfrom ..model import nodes\n"
                     "from ..semantics.compile import Compilation\n", encoding="utf-8")
    assert _unresolved(probe, tmp_path) == ["lsp/probe.py: iface.grammar", "lsp/probe.py: iface.model.nosuch"]
