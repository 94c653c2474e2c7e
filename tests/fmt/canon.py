"""What must not change when a text is formatted: its model and its tokens."""

from __future__ import annotations

import dataclasses
from typing import Any

from iface.model.source import Span
from iface.syntax.parse import parse_text
from iface.text.formatter.lex import kept_tokens, parse_strict

#: Fields that say where something was written, not what it means.
_POSITIONS = frozenset({"span", "name_span", "id_span", "target"})


def canonical(x: Any) -> Any:
    """A position-free, comparable form of a model object."""
    if isinstance(x, Span):
        return None
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return (type(x).__name__, tuple((f.name, canonical(getattr(x, f.name)))
                                        for f in dataclasses.fields(x) if f.name not in _POSITIONS))
    if isinstance(x, (list, tuple)):
        return tuple(canonical(v) for v in x)
    if isinstance(x, dict):
        return tuple(sorted((k, canonical(v)) for k, v in x.items()))
    return x


def model_of(text: str) -> Any:
    """The canonical model of every item of ``text`` and its syntax problem codes."""
    result = parse_text(text)
    return canonical(result.items), sorted(p.code for p in result.problems)


def tokens_of(text: str) -> list[str] | None:
    """The non-separator tokens of a text that parses, else None."""
    tree = parse_strict(text)
    return None if tree is None else [str(t) for t in kept_tokens(tree)]


def comments_of(text: str) -> list[tuple[str, ...]]:
    """The words of every comment of a text that parses, in order."""
    from iface.text.formatter.document import signature

    sig = signature(text)
    assert sig is not None, "the text does not parse"
    return [key[1:] for key in sig if key[0] == "comment"]
