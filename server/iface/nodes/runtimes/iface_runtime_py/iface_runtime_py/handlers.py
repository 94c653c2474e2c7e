"""The user's class against its generated base: the handlers it must write, and the ones that handle nothing."""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Any


class InterfaceMismatch(Exception):
    """The user's class does not match the interface the base class was generated from."""


@dataclass(frozen=True)
class HandlerSpec:
    """A method the user writes: the arguments it is called with, the member it handles."""

    args: tuple[str, ...]
    member: str
    required: bool = True


def _accepts(func: Any, count: int) -> bool:
    try:
        signature = inspect.signature(func)
    except (TypeError, ValueError):
        return True
    params = list(signature.parameters.values())[1:]  # self
    if any(p.kind == p.VAR_POSITIONAL for p in params):
        return True
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    needed = [p for p in positional if p.default is p.empty]
    others = [p for p in params if p.kind == p.KEYWORD_ONLY and p.default is p.empty]
    return len(needed) <= count <= len(positional) and not others


def handler_problems(cls: type, base: type, handlers: dict[str, HandlerSpec], prefixes: tuple[str, ...],
                     source: str) -> list[str]:
    """Where the user's class ``cls`` does not match the handlers of its generated ``base``."""
    problems = []
    for name, spec in handlers.items():
        mine = getattr(cls, name, None)
        if mine is None or mine is getattr(base, name, None):
            if spec.required:
                args = ", ".join(("self", *spec.args))
                problems.append(f"{cls.__name__} has no {name}({args}), which handles '{spec.member}' of {source}")
            continue
        if not _accepts(mine, len(spec.args)):
            problems.append(f"{cls.__name__}.{name} cannot be called with ({', '.join(spec.args)}), as "
                            f"'{spec.member}' calls it")
    ignored = set(getattr(cls, "NOT_HANDLERS", ()))
    for klass in cls.__mro__:
        if klass is base or issubclass(base, klass):
            break
        for name in vars(klass):
            if name.startswith(prefixes) and name not in handlers and name not in ignored and not hasattr(base, name):
                problems.append(f"{klass.__name__}.{name} handles nothing in {source} (was its member renamed or "
                                "removed? list helper methods with such names in NOT_HANDLERS)")
    return problems
