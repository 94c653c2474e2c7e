"""The VS Code grammar colours every base type name of the language, and no other (wchar was once missing)."""

from __future__ import annotations

import re
from pathlib import Path

from iface.model.nodes import BASE_ALIASES

EXTENSION = Path(__file__).resolve().parents[1] / "vscode-extension"


def _array(source: str, name: str) -> list[str]:
    """The string items of ``export const <name> = [...]`` in a JavaScript/TypeScript source."""
    found = re.search(rf"export const {name} = \[(.*?)\];", source, re.S)
    assert found, name
    return re.findall(r"'([^']+)'", found.group(1))


def test_the_grammar_and_its_tests_list_every_base_type_name() -> None:
    grammar = _array((EXTENSION / "scripts" / "grammar.mjs").read_text(encoding="utf-8"), "BUILTIN_TYPES")
    tested = _array((EXTENSION / "test" / "unit" / "manifest.test.ts").read_text(encoding="utf-8"), "BUILTIN_TYPES")
    assert sorted(grammar) == sorted(tested) == sorted(BASE_ALIASES)
    generated = (EXTENSION / "syntaxes" / "iface.tmLanguage.json").read_text(encoding="utf-8")
    assert "|char|wchar|octet|string|wstring)" in generated


def test_every_keyword_of_the_language_is_coloured_and_tested() -> None:
    """Every keyword of grammar.lark is in the extension's keyword list, which its unit tests hold the grammar
    tests to (``system`` and ``instance`` were once missing)."""
    lark = (EXTENSION.parent / "grammar.lark").read_text(encoding="utf-8")
    rules = "\n".join(line for line in lark.splitlines() if not line.lstrip().startswith("//"))
    keywords = set(re.findall(r'"([a-z_]+)"', rules))
    listed = set(_array((EXTENSION / "test" / "unit" / "manifest.test.ts").read_text(encoding="utf-8"), "KEYWORDS"))
    assert keywords - listed == set()
    generated = (EXTENSION / "syntaxes" / "iface.tmLanguage.json").read_text(encoding="utf-8")
    for word in sorted(keywords):
        assert re.search(rf"\b{word}\b", generated), f"the grammar never matches {word}"
