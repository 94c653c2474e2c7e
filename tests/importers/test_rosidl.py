"""The .msg/.srv/.action line parser reads files exactly as rosidl does."""

from __future__ import annotations

import pytest

from iface.importers.rosidl import clean_comments, parse_file

from .helpers import BROKEN, ROBOT_GEOMETRY, ROBOT_MSGS, ros_files

parser = pytest.importorskip("mcap_ros2._vendor.rosidl_adapter.parser")


def _rosidl_parts(kind: str, package: str, name: str, text: str) -> list:
    if kind == "msg":
        return [parser.parse_message_string(package, name, text)]
    if kind == "srv":
        s = parser.parse_service_string(package, name, text)
        return [s.request, s.response]
    a = parser.parse_action_string(package, name, text)
    return [a.goal, a.result, a.feedback]


@pytest.mark.parametrize("path", ros_files(ROBOT_MSGS, ROBOT_GEOMETRY), ids=lambda p: p.name)
def test_same_elements_values_and_comments_as_rosidl(path):
    package = path.parents[1].name
    kind = path.suffix[1:]
    text = path.read_text(encoding="utf-8")
    ours = parse_file(kind, package, path.stem, text)
    assert ours.problems == []
    theirs = _rosidl_parts(kind, package, path.stem, text)
    assert len(ours.parts) == len(theirs)
    for part, spec in zip(ours.parts, theirs):
        fields = [e for e in part.elements if e.kind == "field"]
        consts = [e for e in part.elements if e.kind == "constant"]
        assert [f.name for f in fields] == [f.name for f in spec.fields]
        assert [f.value for f in fields] == [f.default_value for f in spec.fields]
        assert [c.name for c in consts] == [c.name for c in spec.constants]
        assert [c.value for c in consts] == [c.value for c in spec.constants]
        for ours_e, spec_e in zip(fields, spec.fields):
            t = ours_e.type
            full = t.text() if t.primitive or t.package else f"{package}/{t.text()}"
            assert full == str(spec_e.type)
            if "comment" in spec_e.annotations and "unit" not in spec_e.annotations:
                assert (clean_comments(ours_e.comments) or "") == "\n".join(spec_e.annotations["comment"])


def test_comment_attachment():
    text = "# doc of the message\n\n# before a\nint32 a # after a\n  # indented: still a\nint32 b\n"
    part = parse_file("msg", "p", "M", text).parts[0]
    assert clean_comments(part.comments) == "doc of the message"
    a, b = part.elements
    assert clean_comments(a.comments) == "before a\nafter a\nindented: still a"
    assert b.comments == []


def test_string_values_both_quote_styles():
    text = "string a \"x'y\"\nstring b 'x\\'y'\nstring c x y\nstring D=\"q\"\nstring E=a=b\n"
    elements = parse_file("msg", "p", "M", text).parts[0].elements
    assert [e.value for e in elements] == ["x'y", "x'y", "x y", "q", "a=b"]


def test_every_malformed_line_is_reported_with_its_number():
    problems = parse_file("msg", "broken_msgs", "Bad", (BROKEN / "msg" / "Bad.msg").read_text()).problems
    assert [line for line, _ in problems] == [2, 3, 4]
    assert "no name" in problems[0][1]
    assert "flaot32" in problems[1][1]
    assert "does not fit in int8" in problems[2][1]


@pytest.mark.parametrize("text, words", [
    ("int32 a\n---\nint32 b\n---\n", "separator"),
    ("string<=0 s\n", "bound"),
    ("int32[0] a\n", "size"),
    ("time t\n", "builtin_interfaces/Time"),
    ("int32 Bad_Name\n", "field name"),
    ("int32 bad=1\n", "constant name"),
    ("int32[] A=1\n", "primitive"),
    ("Msg m 1\n", "default"),
    ("int32[2] a [1]\n", "exactly 2"),
    ("bool b yes\n", "bool"),
    ("int32 a\nint32 a\n", "already"),
])
def test_refusals(text, words):
    kind = "srv" if "---" in text else "msg"
    problems = parse_file(kind, "p", "M", text).problems
    assert problems, text
    if words != "separator":
        assert words in problems[0][1]
