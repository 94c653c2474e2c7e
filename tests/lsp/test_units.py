"""Units of the server layer that need no client: positions, edit mapping, completion context, settings."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from iface.lsp.context import context_at
from iface.lsp.convert import UTF8, UTF16, UTF32, LineIndex
from iface.lsp.documents import EditLog, map_back, map_forward, path_to_uri, uri_to_path
from iface.lsp.settings import Settings


@pytest.mark.parametrize("encoding, column", [(UTF16, 4), (UTF32, 3), (UTF8, 7)])
def test_columns_in_each_encoding(encoding: str, column: int) -> None:
    text = "ab\r\nx𝔸é!\rlast"
    index = LineIndex(text, encoding)
    assert index.line_count == 3
    offset = text.index("!")
    assert index.position(offset) == (1, column)
    assert index.offset(1, column) == offset
    assert index.position(len(text)) == (2, 4)


def test_a_position_inside_a_surrogate_pair_or_past_the_line_is_clamped() -> None:
    index = LineIndex("𝔸x\nyz", UTF16)
    assert index.offset(0, 1) == 0  # inside 𝔸
    assert index.offset(0, 99) == 2  # end of line 0, before the newline
    assert index.offset(9, 0) == len("𝔸x\nyz")


def test_an_edited_line_index_equals_one_made_from_the_new_text() -> None:
    """Edits across blocks, adding more than a block of lines, and blocks longer than 64 KiB (4-byte starts)."""
    import random

    rnd = random.Random(7)
    text = "\n".join("x" * rnd.choice([0, 3, 40, 200, 70000 if rnd.random() < 0.002 else 9]) for _ in range(4000))
    index = LineIndex(text, UTF16)
    for _ in range(60):
        start = rnd.randrange(len(text) + 1)
        end = min(len(text), start + rnd.choice([0, 1, 30, 5000, 90000]))
        new = rnd.choice(["", "y", "\n", "ab\ncd\n", "\n" * 1500, "z" * 70000 + "\n"])
        text = text[:start] + new + text[end:]
        index = index.edited(start, end, new, text)
        fresh = LineIndex(text, UTF16)
        assert index.starts == fresh.starts == [0, *(i + 1 for i, c in enumerate(text) if c == "\n")]
        for offset in (0, start, start + len(new), len(text), rnd.randrange(len(text) + 1)):
            assert index.position(offset) == fresh.position(offset)


@pytest.mark.parametrize("lines", [0, 1, 1023, 1024, 1025, 2048, 5000])
@pytest.mark.parametrize("breaks", ["\n", "\r\n", "\r", "mixed"])
def test_line_starts_across_blocks_with_every_line_break(lines: int, breaks: str) -> None:
    import random

    rnd = random.Random(lines)
    texts = ["x" * rnd.choice([0, 2, 30]) for _ in range(lines + 1)]
    text = "".join(t + (rnd.choice(["\n", "\r\n", "\r"]) if breaks == "mixed" else breaks) for t in texts[:-1])
    text += texts[-1]
    index = LineIndex(text, UTF16)
    starts = [0, *(m.end() for m in re.finditer(r"\r\n|\r|\n", text))]
    assert index.starts == starts and index.line_count == len(starts)  # "\r" then "\n" is one break
    for offset in range(0, len(text) + 1, 13):
        line, column = index.position(offset)
        assert starts[line] <= offset < (starts[line + 1] if line + 1 < len(starts) else len(text) + 1)
        assert column == offset - starts[line]


def test_offsets_map_through_edits_both_ways() -> None:
    edits = [(2, 4, 3), (0, 0, 1)]  # "abcdef" → "abXYZef" → "_abXYZef"
    assert map_back(edits, 0) == 0 and map_back(edits, 1) == 0 and map_back(edits, 7) == 5
    assert map_back(edits, 4) is None  # inside the inserted "XYZ"
    assert map_forward(edits, 5) == 7 and map_forward(edits, 3) is None and map_forward(edits, 1) == 2


def test_an_edit_log_says_what_its_edits_kept_of_a_text() -> None:
    log = EditLog()
    for edit in [(2, 4, 3), (0, 0, 1), (7, 8, 0)]:  # "abcdef" → "abXYZef" → "_abXYZef" → "_abXYZe"
        log.append(edit)
    assert log.kept(0, 1, 6) == (2, 2)  # "ab" … "ef"
    assert log.kept(0, 3, 6) is None  # nothing kept that the edits tell: the texts are compared
    assert log.kept(1, 2, 7) == (0, 7) and log.kept(2, 2, 8) == (8, 8)
    log.forget_before(2)
    assert log.kept(1, 3, 7) is None and log.kept(2, 3, 8) == (7, 0) and log.kept(2, 4, 8) is None
    log.append((0, 7, 9))  # the whole text sent again
    assert log.kept(3, 4, 7) is None


def test_uris_and_paths() -> None:
    assert uri_to_path("file:///tmp/a%20b.iface") == "/tmp/a b.iface"
    assert path_to_uri("/tmp/a b.iface") == "file:///tmp/a%20b.iface"
    virtual = uri_to_path("untitled:Untitled-1")
    assert virtual.endswith(".iface") and path_to_uri(virtual) == "untitled:Untitled-1"


@pytest.mark.parametrize("text, where", [
    ("message A {\n    u8 a\n}\n|", "top"),
    ("message A {\n    |", "member"),
    ("message A {\n    u8 |", "member-name"),
    ("message A {\n    list<|", "type"),
    ("message A {\n    u8 a (|", "annotation-key"),
    ("message A {\n    Mode m = |", "value"),
    ("publishes |", "wiring-type"),
    ("publishes A |", "wiring-on"),
    ('publishes A on "/a|', "topic"),
    ("typedef |", "type"),
    ("namespace |", "namespace-scope"),
    ("/* message A { */\n|", "top"),
])
def test_completion_context(text: str, where: str) -> None:
    at = text.index("|")
    assert context_at(text.replace("|", ""), at).where == where


def test_settings_keep_old_values_on_bad_input() -> None:
    s = Settings().updated({"iface": {"output": {"folder": "out"}, "targets": ["ros2"], "diagnosticsDelay": 5}})
    assert (s.output_folder, s.targets, s.diagnostics_delay) == ("out", ("ros2",), 0.005)
    bad = s.updated({"targets": "ros2", "output": {"folder": 3}})
    assert (bad.output_folder, bad.targets) == ("out", ("ros2",)) and len(bad.problems) == 2


def test_nothing_outside_the_server_layer_imports_pygls_or_lsprotocol() -> None:
    package = Path(__file__).resolve().parents[2] / "server" / "iface"
    pattern = re.compile(r"^\s*(from|import)\s+(pygls|lsprotocol)\b", re.M)
    offenders = [str(p.relative_to(package)) for p in package.rglob("*.py")
                 if p.relative_to(package).parts[0] != "lsp" and pattern.search(p.read_text(encoding="utf-8"))]
    assert offenders == []
