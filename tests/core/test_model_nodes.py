"""Model nodes are plain dataclasses: every span of a parsed file is a span of its text (a name's span covers
the name), and every node class copies, deep-copies, pickles and is ``dataclasses.replace``d like any other."""

from __future__ import annotations

import copy
import dataclasses
import pickle
from pathlib import Path
from typing import Any

import pytest

from iface.model import nodes as m
from iface.model.source import Span
from iface.semantics.compile import Workspace

TESTS = Path(__file__).parent.parent
FILES = sorted(p for p in TESTS.rglob("*") if p.suffix in (".iface", ".thrift") and p.stat().st_size < 200_000)
#: Fields that point elsewhere (cross references, derived data) rather than to the node's own parts.
_NOT_PARTS = ("target", "source", "included", "spliced", "final", "_index")
#: A file with a node of every class the parser makes.
EVERY_CLASS = '''include "other.iface"
namespace ros2 demo_pkg (tag = "x")
component demo version "1.0"
external geometry_msgs
const i32 LIMIT = 3
typedef float64 Meters
enum Mode { IDLE = 0, RUN = 1 }
senum Names { "a", "b" }
/** A pose. */
message Pose {
    float64 x = 1.5 (unit = "m")
    u8[] raw
    u8[4] quad
    list<string> names
    set<i32> ids
    map<string, i32> counts
    const u8 MAX = 2
}
service Query {
    request {
        u32 count
    }
    response {
        bool ok
    }
}
service Thrifty {
    i32 add(1: i32 a, 2: i32 b) throws (1: Pose oops)
}
action Move {
    goal {
        float64 distance
    }
    result {
        bool done
    }
    feedback {
        float64 left
    }
}
publishes Pose on "/pose"
'''
#: The classes of a system file (a file is a system or a component, never both).
EVERY_SYSTEM_CLASS = '''/** A home. */
system home version "1.0"
include "other.iface"
instance a : other (restart = "never")
'''


def _nodes(node: Any, out: list[Any]) -> list[Any]:
    """Every model node under ``node``; cross references are not followed."""
    stack = [node]
    while stack:
        x = stack.pop()
        if isinstance(x, (list, tuple)):
            stack.extend(x)
        elif isinstance(x, m.Node):
            out.append(x)
            stack.extend(getattr(x, f.name) for f in dataclasses.fields(x) if f.name not in _NOT_PARTS)
    return out


def _every_class() -> dict[type, Any]:
    found: dict[type, Any] = {}
    for name, text in (("/every.iface", EVERY_CLASS), ("/home.iface", EVERY_SYSTEM_CLASS)):
        comp = Workspace([]).compile_text(name, text)
        for node in _nodes(comp.interface.items, []):
            found.setdefault(type(node), node)
    return found


def _node_classes() -> set[type]:
    classes, todo = set(), [m.Node]
    while todo:
        for sub in todo.pop().__subclasses__():
            classes.add(sub)
            todo.append(sub)
    return classes


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(TESTS)))
def test_every_span_of_a_parsed_file_is_a_span_of_its_text(path: Path) -> None:
    text = path.read_text(encoding="utf-8", errors="replace")
    comp = Workspace([]).compile_text(str(path), text)
    nodes = _nodes(comp.interface.items, [])
    assert nodes or not comp.interface.items
    for node in nodes:
        for f in dataclasses.fields(node):
            if not f.name.endswith("span"):
                continue
            span = getattr(node, f.name)
            if span is None and f.name != "span":
                continue
            where = f"{type(node).__name__}.{f.name} in {path.name}"
            assert isinstance(span, Span), where
            assert 0 <= span.start <= span.end <= len(text), where
            if f.name == "name_span" and not getattr(node, "implicit", False):  # an implicit section has no name
                assert text[span.start:span.end] == node.name, where


def test_the_file_of_every_class_has_every_node_class() -> None:
    assert set(_every_class()) == _node_classes()


def test_every_node_class_copies_deep_copies_pickles_and_replaces() -> None:
    for cls, node in _every_class().items():
        name = cls.__name__
        shallow = copy.copy(node)
        assert type(shallow) is cls and shallow is not node, name
        for f in dataclasses.fields(node):
            assert getattr(shallow, f.name) is getattr(node, f.name), f"{name}.{f.name}"
        for twin in (copy.deepcopy(node), pickle.loads(pickle.dumps(node))):
            assert type(twin) is cls and repr(twin) == repr(node), name
            assert (twin.span.start, twin.span.end) == (node.span.start, node.span.end), name
        replaced = dataclasses.replace(node, span=Span(1, 2))
        assert (replaced.span.start, replaced.span.end) == (1, 2), name
        assert (node.span.start, node.span.end) != (1, 2) or node.span == Span(1, 2), name
        others = [f.name for f in dataclasses.fields(node) if f.name != "span"]
        assert all(getattr(replaced, n) is getattr(node, n) for n in others), name


def test_a_span_read_from_a_parsed_node_moves_with_its_chunk() -> None:
    ws = Workspace([])
    text = "message A {\n    u8 a\n}\n\nmessage B {\n    u8 b\n}\n"
    b = ws.compile_text("/t.iface", text).interface.definitions[1]
    span = b.name_span
    assert text[span.start:span.end] == "B"
    longer = "// one more line\n" + text
    again = ws.compile_text("/t.iface", longer).interface.definitions[1]
    assert again is b  # the chunk was kept and moved
    assert longer[span.start:span.end] == longer[b.name_span.start:b.name_span.end] == "B"


def test_node_constructors_are_the_dataclass_ones_with_fresh_defaults() -> None:
    a = m.Service("A", Span(0, 1), Span(2, 3))
    b = m.Service("B", Span(4, 5), name_span=Span(6, 7), form="flat", doc="d")
    assert a.functions == [] and a.functions is not b.functions and a.consts is not b.consts
    a.functions.append(None)  # type: ignore[arg-type]
    assert b.functions == [] and (b.form, b.doc, b.name_span.start) == ("flat", "d", 6)
    f = m.Field("x", m.BaseType("u8", Span(0, 2)), Span(0, 4), Span(3, 4), 7, reference=True)
    assert (f.id, f.reference, f.requiredness, f.annotations) == (7, True, None, ())
    assert repr(f).startswith("Field(name='x', type=BaseType(name='u8', span=Span(0, 2)")
