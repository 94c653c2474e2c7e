"""The whole-file fast path: lark's LALR tables driven by one loop, tokens from one regex.

lark's parser feeds each token through ``ParserState.feed_token`` and each
reduction through a chain of tree-builder wrappers; for a clean file this loop
does the same work inline. The tables are lark's, built from grammar.lark, and
each rule's reduction is planned from the same rule options lark's tree builder
reads (which children are kept, which ``_rule`` children are spliced in, ``?rule``
passing a single child through), so the callbacks get exactly the children they
get from lark. Helper rules (``_item``, ``__x_star_N``) become plain lists,
spliced into their parent, instead of trees. Anything unexpected raises
``ScanError``: the caller then parses with lark itself, which recovers.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

from lark import Lark, Token, Tree
from lark.parsers.lalr_analysis import Shift

from .lexer import FastScanner, ScanError

#: One rule's reduction on the parser's stacks (states, values): the state after it.
Reduce = Callable[[list[int], list[Any]], int]


def reducer(rule: Any, transformer: object | None, goto: dict[int, int]) -> Reduce:
    """The reduction of ``rule``: what lark's tree builder and ``transformer`` do, as one function.

    The plan follows ``lark.parse_tree_builder``: a child is kept unless it is a filtered token (an
    anonymous string, ``_SEP``) of a rule without ``!``; a ``_rule`` child is spliced in (here it is a
    list); a ``?rule`` left with one child is that child; else the transformer's method of the rule's
    name (or alias) builds the value, or a ``Tree`` when there is none. ``goto`` maps the state under
    the popped children to the state after the rule.
    """
    expansion = rule.expansion
    options = rule.options
    size = len(expansion)
    name = rule.alias or options.template_source or rule.origin.name
    keep = [(i, not s.is_term and s.name.startswith("_")) for i, s in enumerate(expansion)
            if options.keep_all_tokens or not (s.is_term and s.filter_out)]
    spliced = any(sp for _, sp in keep)
    expand1 = bool(options.expand1 and not rule.alias)
    fn = getattr(transformer, name, None) if transformer is not None else None
    build: Callable[[list[Any]], Any] | None  # None: the list of kept children is the value
    if name.startswith("_"):
        # lark splices a helper rule's tree into its parent; here the helper's value is the list itself
        assert fn is None, f"a helper rule has a callback: {name}"
        build = None
    elif fn is not None:
        build = fn
    else:
        build = partial(Tree, name)
    if expand1 and len(keep) == 1 and not spliced:
        if size == 1:
            return partial(_pass_through, goto)  # a ``?rule`` of one child: the child itself
        return partial(_pick, goto, size, keep[0][0])  # a ``?rule`` that keeps one of its children
    if size == 1 and len(keep) == 1:
        if spliced:
            return partial(_splice_one, goto, expand1, build)  # the children of one ``_rule``
        if not expand1:
            return partial(_wrap_one, goto, build)  # one kept child
    if size == 2 and [sp for _, sp in keep] == [True, False] and build is None and not expand1:
        return partial(_append, goto)  # a helper list and one more item: ``_items: _items item``
    if size == 2 and [sp for _, sp in keep] == [True, True] and build is None and not expand1:
        return partial(_extend, goto)  # two helper lists joined: ``_items: _items _more``
    if not spliced and not expand1 and size > 1 and keep and [i for i, _ in keep] == list(range(len(keep))):
        return partial(_keep_first, goto, size, len(keep), build)  # its first children kept (all, or up to tokens)
    return partial(_reduce, goto, size, tuple(keep), spliced, expand1, build)


def _pass_through(goto: dict[int, int], states: list[int], values: list[Any]) -> int:
    """A rule whose value is its one child: only the state changes."""
    s = states[-1] = goto[states[-2]]
    return s


def _pick(goto: dict[int, int], size: int, index: int, states: list[int], values: list[Any]) -> int:
    """A ``?rule`` whose one kept child (at ``index`` of its ``size``) is its value."""
    value = values[index - size]
    del values[1 - size:]
    del states[1 - size:]
    values[-1] = value
    s = states[-1] = goto[states[-2]]
    return s


def _wrap_one(goto: dict[int, int], build: Callable[[list[Any]], Any] | None, states: list[int],
              values: list[Any]) -> int:
    """A rule of one kept child: the list of it, or what ``build`` makes of that list."""
    k = [values[-1]]
    values[-1] = k if build is None else build(k)
    s = states[-1] = goto[states[-2]]
    return s


def _splice_one(goto: dict[int, int], expand1: bool, build: Callable[[list[Any]], Any] | None,
                states: list[int], values: list[Any]) -> int:
    """A rule whose one child is a ``_rule``: that rule's list is its children (one child of a ``?rule``:
    that child)."""
    k = values[-1]
    if expand1 and len(k) == 1:
        values[-1] = k[0]
    elif build is not None:
        values[-1] = build(k)
    s = states[-1] = goto[states[-2]]
    return s


def _append(goto: dict[int, int], states: list[int], values: list[Any]) -> int:
    """A helper rule of a helper list and one more kept child: the list, grown by it (taken over, as lark does)."""
    item = values.pop()
    values[-1].append(item)
    states.pop()
    s = states[-1] = goto[states[-2]]
    return s


def _extend(goto: dict[int, int], states: list[int], values: list[Any]) -> int:
    """A helper rule of two helper lists: the first, grown by the second (taken over, as lark does)."""
    more = values.pop()
    values[-1] += more
    states.pop()
    s = states[-1] = goto[states[-2]]
    return s


def _keep_first(goto: dict[int, int], size: int, count: int, build: Callable[[list[Any]], Any] | None,
                states: list[int], values: list[Any]) -> int:
    """A rule that keeps the first ``count`` of its ``size`` children as they are (the others are filtered
    tokens): the popped slice is the list."""
    start = len(values) - size
    k = values[start:start + count]
    del values[1 - size:]
    del states[1 - size:]
    values[-1] = k if build is None else build(k)
    s = states[-1] = goto[states[-2]]
    return s


def _reduce(goto: dict[int, int], size: int, keep: tuple[tuple[int, bool], ...], spliced: bool, expand1: bool,
            build: Callable[[list[Any]], Any] | None, states: list[int], values: list[Any]) -> int:
    """Any other rule: the kept children, the lists of ``_rule`` children spliced in."""
    if size:
        children = values[-size:]
        del values[-size:]
        del states[-size:]
    else:
        children = []
    if not spliced:
        k = [children[i] for i, _ in keep]
    else:
        k = []
        for j, (i, splice) in enumerate(keep):
            if not splice:
                k.append(children[i])
            elif j == 0:
                k = children[i]  # like lark: the first spliced list is taken over, not copied
            else:
                k += children[i]
    if expand1 and len(k) == 1:
        value = k[0]
    else:
        value = k if build is None else build(k)
    values.append(value)
    s = goto[states[-1]]
    states.append(s)
    return s


#: Characters read by one ``findall`` (then on to the end of the line).
_WINDOW = 16384


class Driver:
    """Parse a clean text with ``parser``'s LALR tables and ``transformer``'s callbacks, tokens from ``scanner``."""

    def __init__(self, parser: Lark, transformer: object | None, scanner: FastScanner) -> None:
        table = parser.parser.parser.parser.parse_table
        gotos: dict[str, dict[int, int]] = {}
        for state, row in table.states.items():
            for sym, (action, arg) in row.items():
                if not (sym.isupper() or sym == "$END"):
                    assert action is Shift
                    gotos.setdefault(sym, {})[state] = arg
        reducers = {rule: reducer(rule, transformer, gotos.get(rule.origin.name, {})) for rule in parser.rules}
        n = max(table.states) + 1
        #: per state: terminal → the next state (an int: a shift) or the reduction to make
        self.actions: list[dict[str, int | Reduce]] = [{} for _ in range(n)]
        for state, row in table.states.items():
            actions = self.actions[state]
            for sym, (action, arg) in row.items():
                if sym.isupper() or sym == "$END":
                    actions[sym] = arg if action is Shift else reducers[arg]
        self.start = table.start_states["start"]
        self.end = table.end_states["start"]
        self.triples = scanner.triples
        #: the terminal of a punctuation token or a word that is a keyword or a base type
        self.fixed = {**scanner.punct, **scanner.words}
        #: the terminals of words: each is a name where the parser takes a name and not it
        self.contextual = frozenset(scanner.words.values())
        self.first = scanner.first
        self.is_int = scanner.int.fullmatch
        #: a block comment at an offset (a match; None when none starts there or it never closes)
        self.block_comment = scanner.block_comment.match

    def parse(self, text: str) -> Any:
        """The value of ``start`` for ``text``; ``ScanError`` at the first thing not read.

        The text is read a window of lines at a time (``findall`` copies what it matches, the blanks
        and comments too, so a long comment is copied by pieces or not at all; no token spans a line).
        A block comment that runs past its window is stepped over as one match, without a copy.
        """
        actions = self.actions
        fixed = self.fixed
        contextual = self.contextual
        first = self.first
        is_int = self.is_int
        findall = self.triples.findall
        new_str = str.__new__
        states = [self.start]
        values: list[Any] = []
        numbers: dict[str, str] = {}  # the terminal of each number read so far
        push_state = states.append
        push_value = values.append
        row = actions[self.start]
        pos = 0
        n = len(text)
        while pos < n:
            end = text.find("\n", pos + _WINDOW) + 1 if pos + _WINDOW < n else n
            if end <= 0:
                end = n
            for blank, value, bad in findall(text, pos, end):
                start = pos + len(blank)
                if not value:
                    if bad:
                        comment = self.block_comment(text, start) if bad == "/" else None
                        if comment is None:
                            raise ScanError(start)
                        pos = comment.end()  # a block comment longer than the rest of the window
                    else:
                        pos = start  # the blanks and comments up to the window's end
                    break
                pos = start + len(value)
                kind = fixed.get(value)
                if kind is None:
                    kind = first[value[0]]
                    if kind is None:
                        kind = numbers.get(value)
                        if kind is None:
                            kind = numbers[value] = "INT" if is_int(value) else "DOUBLE"
                elif kind in contextual and kind not in row and "IDENTIFIER" in row:
                    kind = "IDENTIFIER"  # a keyword is a name where the parser takes a name and not the keyword
                tok = new_str(Token, value)
                tok.type = kind
                tok.value = value
                tok.start_pos = start
                tok.end_pos = pos
                tok.line = tok.column = tok.end_line = tok.end_column = None
                act = row.get(kind)
                while type(act) is not int:
                    if act is None:
                        raise ScanError(start)
                    row = actions[act(states, values)]
                    act = row.get(kind)
                push_state(act)
                push_value(tok)
                row = actions[act]
        while True:
            act = row.get("$END")
            if act is None or type(act) is int:
                raise ScanError(pos)
            state = act(states, values)
            if state == self.end:
                return values[-1]
            row = actions[state]
