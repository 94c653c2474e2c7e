"""Find grammar.lark and build the LALR parser once."""

from __future__ import annotations

import threading
from importlib import resources
from pathlib import Path

from lark import Lark

_lock = threading.Lock()


def grammar_text() -> str:
    """The text of grammar.lark: the packaged copy, else the repository root."""
    packaged = resources.files("iface").joinpath("grammar.lark")
    if packaged.is_file():
        return packaged.read_text(encoding="utf-8")
    root = Path(__file__).resolve().parents[3] / "grammar.lark"
    return root.read_text(encoding="utf-8")


def build_parser(transformer: object | None = None) -> Lark:
    """A new LALR parser with the contextual lexer, running ``transformer`` inline if given.

    The parse tables are cached on disk by lark (keyed by the grammar's hash), which
    makes a second start about five times faster; without a writable cache it still works.
    """
    options = dict(parser="lalr", lexer="contextual", transformer=transformer,
                   maybe_placeholders=False, propagate_positions=False)
    with _lock:
        try:
            return Lark(grammar_text(), cache=True, **options)
        except OSError:
            return Lark(grammar_text(), **options)


_descriptions: dict[str, str] = {}


def terminal_descriptions(parser: Lark) -> dict[str, str]:
    """A readable description for every terminal name ``parser`` uses."""
    if _descriptions:
        return _descriptions
    names = {"IDENTIFIER": "a name", "INT": "an integer", "DOUBLE": "a number",
             "LITERAL": "a string", "BASE_TYPE": "a type", "_SEP": "','", "$END": "end of file"}
    out: dict[str, str] = {}
    for term in parser.terminals:
        if term.name in names:
            out[term.name] = names[term.name]
        elif term.pattern.type == "str":
            out[term.name] = f"'{term.pattern.value}'"
        else:
            out[term.name] = term.name.lower()
    out["$END"] = names["$END"]
    _descriptions.update(out)
    return out
