"""Find grammar.lark and build the LALR parser once."""

from __future__ import annotations

import threading
from functools import lru_cache
from importlib import resources
from pathlib import Path

from lark import Lark

_lock = threading.Lock()


def grammar_text() -> str:
    """The text of grammar.lark: the packaged copy, else the repository root."""
    packaged = resources.files("iface").joinpath("grammar.lark")
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    root = Path(__file__).resolve().parents[2] / "grammar.lark"
    return root.read_text(encoding="utf-8")


def build_parser(transformer: object | None = None) -> Lark:
    """A new LALR parser with the contextual lexer, running ``transformer`` inline if given."""
    with _lock:
        return Lark(
            grammar_text(),
            parser="lalr",
            lexer="contextual",
            transformer=transformer,
            maybe_placeholders=False,
            propagate_positions=False,
        )


@lru_cache(maxsize=None)
def terminal_descriptions() -> dict[str, str]:
    """A readable description for every terminal name the parser uses."""
    parser = build_parser()
    names = {"IDENTIFIER": "a name", "INT": "an integer", "DOUBLE": "a number",
             "LITERAL": "a string", "BASE_TYPE": "a type", "$END": "end of file"}
    out: dict[str, str] = {}
    for term in parser.terminals:
        if term.name in names:
            out[term.name] = names[term.name]
        elif term.pattern.type == "str":
            out[term.name] = f"'{term.pattern.value}'"
        else:
            out[term.name] = term.name.lower()
    out["$END"] = names["$END"]
    return out
