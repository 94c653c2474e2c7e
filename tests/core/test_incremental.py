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
