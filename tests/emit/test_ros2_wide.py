"""wchar and wstring everywhere (types, constants, defaults, arrays, bounds) through every target.

ROS 2 reads ``wchar`` from ``.idl`` only, so the ros2 target writes such an interface as an
``.idl`` file (judged by rosbags' IDL parser); ``wstring`` alone stays ``.msg`` (judged by rosidl).
uORB has neither: the px4 target refuses each with a code at the member.
"""

from __future__ import annotations

import json

import pytest

from iface.emit import generate

from .helpers import compile_text

WIDE = """component wide
namespace ros2 wide_msgs

message Wide {
    const wchar LETTER = 65,
    const wstring GREETING = "hello",
    wchar letter = 66,
    wstring text = "wide",
    wstring<=5 short_text,
    wstring[3] three,
    wstring[<=4] some,
    wstring<=7[] many,
    wchar[2] pair,
    wchar[<=3] few
}

message Narrow {
    const wstring NAME = "n",
    wstring<=5 label = "abc",
    wstring[<=2] names
}
"""


def _files(target: str) -> dict[str, str]:
    result = generate(compile_text(WIDE, "wide.iface"), target)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return {f.path: f.text for f in result.files}


def test_the_language_bounds_wchar_values() -> None:
    comp = compile_text("message M { wchar c = 70000, const wchar K = -1, wchar d = \"a\", wchar ok = 65535 }\n")
    errors = sorted(d.code for d in comp.all_diagnostics() if d.severity == 1)
    assert errors == ["int-out-of-range", "int-out-of-range", "invalid-default"]


def test_ros2_writes_idl_for_wchar_and_msg_for_wstring() -> None:
    rosbags = pytest.importorskip("rosbags.typesys")
    files = _files("ros2")
    assert "wide_msgs/msg/Wide.idl" in files and "wide_msgs/msg/Wide.msg" not in files
    assert "wide_msgs/msg/Narrow.msg" in files
    assert '"msg/Wide.idl"' in files["wide_msgs/CMakeLists.txt"]
    assert '"msg/Narrow.msg"' in files["wide_msgs/CMakeLists.txt"]
    consts, fields = rosbags.get_types_from_idl(files["wide_msgs/msg/Wide.idl"].replace(">>", "> >"))[
        "wide_msgs/msg/Wide"]
    assert consts == [("LETTER", "wchar", 65), ("GREETING", "wstring", "hello")]
    shown = [(name, _show(desc)) for name, desc in fields]
    assert shown == [("letter", "wchar"), ("text", "wstring"), ("short_text", "wstring<=5"),
                     ("three", "wstring[3]"), ("some", "wstring[<=4]"), ("many", "wstring<=7[]"),
                     ("pair", "wchar[2]"), ("few", "wchar[<=3]")]


def _show(desc: object) -> str:
    node, rest = desc  # type: ignore[misc]
    kind = node.name
    if kind == "ARRAY":
        return f"{_show(rest[0])}[{rest[1]}]"
    if kind == "SEQUENCE":
        return f"{_show(rest[0])}[<={rest[1]}]" if rest[1] else f"{_show(rest[0])}[]"
    return f"{rest[0]}<={rest[1]}" if rest[1] else rest[0]


def test_the_wstring_only_message_reads_back_with_rosidl() -> None:
    parser = pytest.importorskip("mcap_ros2._vendor.rosidl_adapter.parser")
    spec = parser.parse_message_string("wide_msgs", "Narrow", _files("ros2")["wide_msgs/msg/Narrow.msg"])
    assert [(str(f.type), f.name, f.default_value) for f in spec.fields] == [
        ("wstring<=5", "label", "abc"), ("wstring[<=2]", "names", None)]
    assert [(c.type, c.name, c.value) for c in spec.constants] == [("wstring", "NAME", "n")]


def test_idl_json_markdown_and_ardupilot_write_them() -> None:
    idl = _files("idl")["wide_msgs/msg/Wide.idl"]
    assert "const wchar LETTER = 65;" in idl and "wstring<5> short_text;" in idl and "sequence<wchar, 3> few;" in idl
    assert "@default (value=66)\n      wchar letter;" in idl
    (doc,) = [json.loads(t) for p, t in _files("json").items() if p.endswith(".json")]
    assert json.dumps(doc).count('"name": "wchar"') == 4  # letter, pair, few and the constant LETTER
    md = next(t for p, t in _files("markdown").items() if p.endswith(".md"))
    assert "`wchar[<=3]`" in md and "`wstring<=7[]`" in md
    ap = _files("ardupilot")
    assert any("wchar letter;" in t for t in ap.values())


def test_px4_refuses_each_wide_member_with_a_code_at_it() -> None:
    comp = compile_text(WIDE, "wide.iface")
    result = generate(comp, "px4")
    assert result.has_errors and result.files == []
    refused: dict[str, set[str]] = {}
    for d in result.diagnostics:
        if d.severity == 1:
            name = d.message.split("'", 2)[1]  # "field 'x' of message 'M': ..." / "constant 'X' of ..."
            refused.setdefault(name, set()).add(d.code)
    narrow_and_wide = {"LETTER", "GREETING", "letter", "text", "short_text", "three", "some", "many", "pair", "few",
                       "NAME", "label", "names"}
    assert set(refused) == narrow_and_wide, refused
    assert set().union(*refused.values()) <= {"px4-unsupported-type", "px4-variable-array", "px4-default"}
    assert "px4-unsupported-type" in refused["letter"] and "px4-unsupported-type" in refused["pair"]
