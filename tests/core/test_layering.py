"""Architecture rules: only the LSP layer imports pygls/lsprotocol; emitters read only the model."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "server" / "iface"


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out.add(node.module.split(".")[0])
    return out


def test_only_the_lsp_layer_imports_pygls() -> None:
    offenders = []
    for path in PACKAGE.rglob("*.py"):
        if "lsp" in path.relative_to(PACKAGE).parts[:1]:
            continue
        if _imports(path) & {"pygls", "lsprotocol"}:
            offenders.append(str(path.relative_to(PACKAGE)))
    assert offenders == []


def test_grammar_file_is_the_packaged_one() -> None:
    root = PACKAGE.parents[1] / "grammar.lark"
    assert (PACKAGE / "grammar.lark").read_text() == root.read_text()
