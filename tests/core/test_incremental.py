"""The incremental path (chunk cache, moved spans) gives exactly what a fresh compile gives."""

from __future__ import annotations

import functools
import json
import os
import random
from dataclasses import fields, is_dataclass

from iface.forms.dump import dump_interface
from iface.model.source import Source, Span
from iface.semantics.compile import Workspace, compile_source

from .helpers import DATA

SNIPPETS = ["struct Extra {\n    1: i32 e\n}\n", "message M2 {\n    float64 v\n}\n", "}", "{", "\n",
            "  1: Unknown u,\n", "const i32 K = 7\n", "/** doc */\n", "publishes M2 on \"/m2\"\n", "é", "\"",
            "service S9 {\n    request {}\n    response {}\n}\n"]


def _fingerprint(comp) -> str:
    diags = sorted((d.path, d.span.start, d.span.end, d.code, d.message) for d in comp.diagnostics)
    return json.dumps([dump_interface(comp.interface), diags], default=str)


def test_random_edits_match_fresh_compiles() -> None:
    rng = random.Random(11)
    text = (DATA / "valid" / "ros_types.iface").read_text() + (DATA / "valid" / "mini_robot.iface").read_text()
    editor = Workspace()
    path = "/virtual/doc.iface"
    for step in range(150):
        pos = rng.randrange(len(text) + 1)
        if rng.random() < 0.4 and len(text) > 10:
            end = min(len(text), pos + rng.randint(1, 40))
            text = text[:pos] + text[end:]
        else:
            text = text[:pos] + rng.choice(SNIPPETS) + text[pos:]
        incremental = editor.compile_text(path, text)
        fresh = Workspace().compile_text(path, text)
        whole = compile_source(Source(path, text))
        assert _fingerprint(incremental) == _fingerprint(fresh) == _fingerprint(whole), f"step {step}"


def test_common_prefix_and_suffix_of_long_texts_are_found_across_blocks() -> None:
    """The common prefix and suffix of an edit are found a block at a time, then by halving the block
    that differs: the same lengths as comparing character by character, for edits anywhere in texts
    longer than several blocks (at block edges too)."""
    import os.path

    from iface.syntax.chunks import _common_prefix, _common_suffix

    rng = random.Random(3)
    base = "".join(rng.choice("ab\n") for _ in range(70_000))
    places = [0, 1, 31, 32, 33, 1 << 15, (1 << 15) - 1, (1 << 15) + 1, 1 << 16, 69_999, 70_000]
    places += [rng.randrange(70_001) for _ in range(40)]
    for at in places:
        for new in ("", "c", "ab", "x" * 40_000):
            cut = min(len(base), at + rng.choice((0, 1, 5, 3000)))
            edited = base[:at] + new + base[cut:]
            head = _common_prefix(base, edited)
            assert head == len(os.path.commonprefix([base, edited])), (at, len(new))
            tail = _common_suffix(base, edited, head)
            naive = len(os.path.commonprefix([base[head:][::-1], edited[head:][::-1]]))
            assert tail == naive, (at, len(new))


def test_cutting_again_only_around_an_edit_gives_the_chunks_of_cutting_it_all() -> None:
    """``split(text, previous)`` keeps the chunks before an edit and moves those after it: the same chunks
    (bounds, doc comments, an unclosed comment) as cutting the whole new text, over 3,000 random edits."""
    from iface.syntax.chunks import split

    tokens = ["message ", "struct A {", "}", "\n", "/** d */", "/*", "*/", "// c", "# h\n", "enum E {",
              "const i32 X = 1\n", "\nmessage M {\n u8 a\n}\n", "\n/** doc */\nmessage D {}\n", "  ", "x", '"s"',
              'include "a.iface"\n', "\n\n"]
    rng = random.Random(17)
    base = (DATA / "valid" / "ros_types.iface").read_text() + (DATA / "valid" / "mini_robot.iface").read_text()

    def shape(chunks: list) -> list:
        return [(c.start, c.end, c.docs, c.unterminated) for c in chunks]

    for trial in range(100):
        text = base if trial % 3 else "".join(rng.choice(tokens) for _ in range(rng.randint(0, 40)))
        chunks = split(text)
        for step in range(30):
            a = rng.randint(0, len(text))
            b = min(len(text), a + rng.choice([0, 0, 1, 3, 10, 50]))
            new = text[:a] + "".join(rng.choice(tokens) for _ in range(rng.randint(0, 3))) + text[b:]
            again = split(new, (text, chunks))
            assert shape(again) == shape(split(new)), f"trial {trial} step {step}: {new[max(0, a - 40):a + 60]!r}"
            text, chunks = new, again


#: A file whose findings come from every part of the per-definition edit path: typedef chains, an
#: ``extends`` cycle, a recursive message, duplicate definitions and wirings, Δ, the seven sets.
RICH = '''namespace ros2 demo
/** Doc. */
message A {
    B b
    u8 x = 3
    Mode m = Mode.RUN
}
message B {
    A[] back
    T t
}
typedef C T
typedef list<C> TL
struct C {
    1: i32 v = LIMIT
}
const i32 LIMIT = 7
const i32 LIMIT = 8
enum Mode {
    IDLE = 0,
    RUN = 1,
}
service diagnostics {
    request { u8 q }
    response { bool ok }
}
service S extends R {
    request { A a }
    response { B b }
}
service R extends S {
}
action Go {
    goal { A a }
    result { bool ok }
    feedback { float64 d }
}
configuration Params {
    float64 speed = 1.5 (range = "0..3")
    u32 n
}
publishes A on "/a"
publishes A on "/a"
subscribes B on "/a"
provides S on "/s"
calls diagnostics on "/d"
publishes Mode on "/m"
'''
LINES = ["message D {\n    A a\n}", "typedef A T", "struct C {\n    1: i32 w\n}", "    D d", "    Q q",
         "publishes D on \"/d\"", "provides Go on \"/go\"", "const u8 LIMIT = 300", "enum Mode {\n    X = 1,\n}",
         "}", "message A {", "    u8 y = 1.5", "service diagnostics {\n}", "component demo version \"1\"",
         "message E {\n    E e\n}", "typedef T C2", "    T2 z", "typedef C2 T2"]


def test_line_edits_of_a_file_with_cycles_and_duplicates_match_fresh_compiles() -> None:
    rng = random.Random(5)  # a seed that meets, within 600 edits, chunks that swap their objects
    editor = Workspace()
    path = "/virtual/rich.iface"
    text = RICH
    for step in range(int(os.environ.get("IFACE_SOAK_EDITS", "600"))):
        lines = text.split("\n")
        roll = rng.random()
        at = rng.randrange(len(lines) + 1)
        if roll < 0.4 and len(lines) > 3:
            del lines[min(at, len(lines) - 1)]
        elif roll < 0.8:
            lines.insert(at, rng.choice(LINES))
        elif roll < 0.9:
            lines = RICH.split("\n")
        else:  # two lines swap places: chunks found again by their text, in another order
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        text = "\n".join(lines)
        got = editor.compile_text(path, text)
        fresh = compile_source(Source(path, text))
        assert _fingerprint(got) == _fingerprint(fresh), f"step {step}:\n{text}"
        assert list(got.interface.symbols) == list(fresh.interface.symbols), f"step {step}"


#: Fields not followed by ``_spans``: cross references, and the table a parsed node keeps its spans in (where its
#: chunk starts, not a span of the node).
_NOT_FOLLOWED = ("target", "source", "included", "spliced", "_t")


@functools.cache
def _followed(cls: type) -> tuple[str, ...]:
    """The fields of a model class that ``_spans`` looks into (none for a class that is no dataclass)."""
    return tuple(f.name for f in fields(cls) if f.name not in _NOT_FOLLOWED) if is_dataclass(cls) else ()


def _spans(node: object, out: list[tuple[str, int, int]], path: str = "", depth: int = 0) -> list:
    """Every span under a model node (name spans too), by where it is; cross references are not followed."""
    if isinstance(node, Span):
        out.append((path, node.start, node.end))
    elif isinstance(node, (list, tuple)):
        for i, x in enumerate(node):
            _spans(x, out, f"{path}[{i}]", depth + 1)
    elif depth < 40:
        for name in _followed(type(node)):
            _spans(getattr(node, name), out, f"{path}.{name}", depth + 1)
    return out


def test_edits_whose_place_the_editor_tells_match_fresh_compiles() -> None:
    """An editor says what its edits kept (``compile_text(..., edited=(last text, head, tail))``), exactly or
    less than that (several edits in one change): the texts are not compared, and the compile is still a
    fresh one's. What is said about another text than the last one compiled is not used."""
    rng = random.Random(5)
    text = (DATA / "valid" / "ros_types.iface").read_text() + (DATA / "valid" / "mini_robot.iface").read_text()
    editor = Workspace()
    path = "/virtual/told.iface"
    editor.compile_text(path, text)
    for step in range(150):
        pos = rng.randrange(len(text) + 1)
        end = min(len(text), pos + rng.randint(0, 30))
        new = text[:pos] + rng.choice(SNIPPETS) + text[end:]
        head, tail = pos, len(text) - end
        if rng.random() < 0.3:  # what a change of several edits says: less than what was kept
            head, tail = rng.randint(0, head), rng.randint(0, tail)
        last = text if rng.random() < 0.9 else "".join(list(text))  # an equal text, not the one compiled
        got = editor.compile_text(path, new, (last, head, tail))
        text = new
        assert _fingerprint(got) == _fingerprint(compile_source(Source(path, text))), f"step {step}"


def test_edits_of_a_long_file_move_every_span_as_a_fresh_parse_places_it() -> None:
    """Chunks after an edit move by blocks (``EditCache``): over 150 edits of a file of 240 chunks,
    near each other and far apart, every span of the model (names, types, members) is where a fresh
    parse puts it, also across the re-blocking that happens every few dozen edits."""
    rng = random.Random(23)
    lines: list[str] = []
    for i in range(120):
        lines += [f"/** Reading {i}. */", f"message Reading{i} {{", "    u8 count", f"    Mode{i} mode",
                  "    string<=8 label (unit = \"m\")", "}", f"enum Mode{i} {{", "    IDLE = 0,", "}", ""]
    editor = Workspace()
    path = "/virtual/long.iface"
    at = len(lines) // 2
    for step in range(150):
        at = rng.randrange(len(lines)) if rng.random() < 0.3 else max(0, min(len(lines) - 1, at + rng.randint(-5, 5)))
        roll = rng.random()
        if roll < 0.45:
            lines.insert(at, rng.choice(["    u8 extra", "/** doc */", "message X {", "}", "", "const u8 K = 1"]))
        elif roll < 0.9 and len(lines) > 10:
            del lines[at]
        else:
            lines[at] = lines[at] + " "
        text = "\n".join(lines)
        got = editor.compile_text(path, text)
        fresh = compile_source(Source(path, text))
        assert _spans(got.interface.definitions, []) == _spans(fresh.interface.definitions, []), f"step {step}"
        assert _fingerprint(got) == _fingerprint(fresh), f"step {step}"
