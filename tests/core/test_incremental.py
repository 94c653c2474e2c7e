"""The incremental path (chunk cache, moved spans) gives exactly what a fresh compile gives."""

from __future__ import annotations

import json
import random

from iface.forms.dump import dump_interface
from iface.model.source import Source
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
