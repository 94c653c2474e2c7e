"""The library is plain Python: no code made from strings at run time (``exec``, ``eval``, the builtin
``compile``), no hooks into the garbage collector."""

from __future__ import annotations

import ast
from pathlib import Path

import iface

PACKAGE = Path(iface.__file__).parent
_BANNED_CALLS = frozenset({"exec", "eval", "compile", "__import__"})
_BANNED_GC = frozenset({"freeze", "unfreeze", "callbacks"})


def offences(source: str, name: str) -> list[str]:
    """``file:line: what`` for each banned construct in ``source``."""
    found = []
    for node in ast.walk(ast.parse(source, name)):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _BANNED_CALLS:
            found.append(f"{name}:{node.lineno}: {node.func.id}()")
        elif (isinstance(node, ast.Attribute) and node.attr in _BANNED_GC and isinstance(node.value, ast.Name)
              and node.value.id == "gc"):
            found.append(f"{name}:{node.lineno}: gc.{node.attr}")
    return found


def test_no_library_module_runs_code_made_from_strings() -> None:
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        found += offences(path.read_text(encoding="utf-8"), str(path.relative_to(PACKAGE)))
    assert found == []


def test_the_check_finds_what_it_bans() -> None:
    source = "import gc\nexec('x = 1')\ny = eval('2')\nz = re.compile('a')\ngc.freeze()\nast.literal_eval('3')\n"
    assert offences(source, "m.py") == ["m.py:2: exec()", "m.py:3: eval()", "m.py:5: gc.freeze"]
