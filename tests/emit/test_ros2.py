"""The ros2 target: every file passes ROS 2's own parser, rosbags, catkin_pkg and YAML; goldens."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from iface.emit.ros2.lower import lower

from .golden_util import check_golden
from .helpers import CASES, ROOT, codes, compile_file, compile_text, run
from .oracles import catkin_package, load_yaml, rosbags_parse, rosidl_parse

_INTERFACE = re.compile(r"^([a-z0-9_]+)/(msg|srv|action)/([A-Za-z0-9]+)\.(msg|srv|action)$")


def generated(case: str) -> dict[str, str]:
    result = run("ros2", compile_file(CASES[case]))
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return {f.path: f.text for f in result.files}


def parsed(files: dict[str, str]) -> dict[str, list]:
    """rosidl's specifications of every interface file, by ``kind/Name``."""
    out = {}
    for path, text in files.items():
        m = _INTERFACE.match(path)
        if m:
            out[f"{m.group(2)}/{m.group(3)}"] = rosidl_parse(text, m.group(1), m.group(2), m.group(3))
    return out


def fields(spec) -> list[tuple[str, str, object]]:
    return [(f.name, str(f.type), f.default_value) for f in spec.fields]


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_file_passes_the_oracles(case: str) -> None:
    files = generated(case)
    interfaces = 0
    for path, text in files.items():
        m = _INTERFACE.match(path)
        if m:
            interfaces += 1
            pkg, kind, name = m.group(1), m.group(2), m.group(3)
            specs = rosidl_parse(text, pkg, kind, name)
            bags = rosbags_parse(text, pkg, kind, name)
            for spec, bag in zip(specs, bags):
                (consts, bag_fields), = bag.values()
                assert [f.name for f in spec.fields] == [f[0] for f in bag_fields]
                assert [c.name for c in spec.constants] == [c[0] for c in consts]
        elif path.endswith("package.xml"):
            pkg = catkin_package(text)
            assert pkg.package_format == 3
            assert [d.name for d in pkg.buildtool_depends] == ["ament_cmake", "rosidl_default_generators"]
            assert "rosidl_default_runtime" in [d.name for d in pkg.exec_depends]
            assert [g.name for g in pkg.member_of_groups] == ["rosidl_interface_packages"]
        elif path.endswith(".yaml"):
            data = load_yaml(text)
            assert list(data) and "ros__parameters" in next(iter(data.values()))
        elif path.endswith("CMakeLists.txt"):
            listed = re.findall(r'^  "((?:msg|srv|action)/[A-Za-z0-9]+\.(?:msg|srv|action))"$', text, re.M)
            assert sorted(listed) == sorted(p.split("/", 1)[1] for p in files if _INTERFACE.match(p))
    assert interfaces > 0


@pytest.mark.parametrize("case", sorted(CASES))
def test_golden(case: str) -> None:
    check_golden("ros2", case, run("ros2", compile_file(CASES[case])).files)


@pytest.mark.parametrize("case", sorted(CASES))
def test_byte_identical_across_runs(case: str) -> None:
    first = run("ros2", compile_file(CASES[case])).files
    second = run("ros2", compile_file(CASES[case])).files
    assert [(f.path, f.text) for f in first] == [(f.path, f.text) for f in second]


def test_listing1_maps_every_set() -> None:
    files = generated("listing1")
    specs = parsed(files)
    assert sorted(specs) == ["action/Action1", "action/Action2", "msg/Listing1State", "msg/Message1",
                             "msg/Message2", "srv/Diagnostics", "srv/Service1", "srv/Service2"]
    assert fields(specs["msg/Message1"][0]) == [("str", "string", None), ("i", "int16", None)]
    request, response = specs["srv/Service1"]
    assert fields(request) == [("str", "string", None), ("i", "int32", None)]
    assert fields(response) == [("result", "string", None)]
    goal, result, feedback = specs["action/Action2"]
    assert fields(goal) == [("par1", "float64", None), ("par2", "float32", None)]
    assert fields(result) == [("result", "int16", None)]
    assert fields(feedback) == [("f", "string", None)]
    assert [f[0] for f in fields(specs["msg/Listing1State"][0])] == ["position", "velocity", "acceleration", "mode"]
    params = load_yaml(files["listing1/config/listing1.params.yaml"])
    assert params == {"listing1": {"ros__parameters": {}}}
    assert "# param1 (string): no default, so not set here" in files["listing1/config/listing1.params.yaml"]


def _without_docs(case: str) -> dict[str, str]:
    """The files of ``case`` generated from its text with every doc comment removed."""
    bare = re.sub(r"/\*\*.*?\*/", "", CASES[case].read_text(encoding="utf-8"), flags=re.S)
    result = run("ros2", compile_text(bare, CASES[case].name))
    assert not result.has_errors
    return {f.path: f.text for f in result.files}


def test_part_docs_are_the_parts_own_comments_for_rosidl() -> None:
    specs = parsed(generated("section_docs"))
    _, response = specs["srv/SetGrip"]
    assert response.annotations["comment"] == ["What happened."]
    _, ping_response = specs["srv/Ping"]
    assert ping_response.annotations["comment"] == ["Nothing comes back."]
    _, result, feedback = specs["action/MoveTo"]
    assert result.annotations["comment"] == ["Reached or not."]
    assert feedback.annotations["comment"] == ["Progress so far: 0..1.", "Sent at 10 Hz."]
    # the part's doc is the part's, not its first field's
    assert not result.fields[0].annotations.get("comment") and not feedback.fields[0].annotations.get("comment")


def test_request_doc_stands_at_the_top_after_the_definition_doc() -> None:
    text = generated("section_docs")["section_docs_msgs/srv/SetGrip.srv"]
    top = text.split("\nuint8 MAX_RETRIES", 1)[0]
    assert top.endswith("# Sets the gripper opening.\n\n# What to do.\n#\n# The width is clamped to the "
                        "gripper's range.\n")


def test_part_docs_change_no_field_or_constant() -> None:
    with_docs, without = parsed(generated("section_docs")), parsed(_without_docs("section_docs"))
    assert sorted(with_docs) == sorted(without)
    for key, specs in with_docs.items():
        for spec, bare in zip(specs, without[key], strict=True):
            assert fields(spec) == fields(bare)
            assert [(c.name, c.type, c.value) for c in spec.constants] == \
                [(c.name, c.type, c.value) for c in bare.constants]


def test_listing1_names_are_converted_with_warnings() -> None:
    result = run("ros2", compile_file(CASES["listing1"]))
    renamed = [d for d in result.diagnostics if d.code == "ros-naming"]
    assert any("'message1'" in d.message and "'Message1'" in d.message for d in renamed)
    first = next(d for d in renamed if "'message1'" in d.message)
    assert first.location()[:2] == (1, 9)


def test_robot_arm_fields_match_the_model() -> None:
    files = generated("robot_arm")
    specs = parsed(files)
    assert fields(specs["msg/PoseTarget"][0]) == [
        ("frame_id", "string<=64", "base_link"),
        ("pose", "geometry_msgs/Pose", None),
        ("tolerance", "float64[3]", [0.001, 0.001, 0.001]),
        ("joint_hint", "float64[<=6]", None),
        ("tags", "string[]", None),
        ("request_id", "uint8[16]", None),
    ]
    assert [(c.name, c.type, c.value) for c in specs["msg/PoseTarget"][0].constants] == [
        ("DEFAULT_FRAME", "string", "base_link")]
    state = specs["msg/JointState"][0]
    assert ("mode", "int32", None) in fields(state)
    assert ("position", "float32[6]", None) in fields(state)
    assert {(c.name, c.value) for c in state.constants} >= {("JOINTS", 6), ("ARM_MODE_FAULT", 3),
                                                            ("STOP_REASON_EMERGENCY_STOP", 1)}
    goal, result, _ = specs["action/FollowTrajectory"]
    assert fields(goal) == [("points", "robot_arm_msgs/TrajectoryPoint[<=1000]", None), ("checksum", "uint8[]", None)]
    get_request, get_response = specs["srv/JointLimitsServiceGetLimits"]
    assert fields(get_request) == [("joint", "uint8", None)]
    assert fields(get_response) == [("result", "robot_arm_msgs/JointLimits", None)]
    clear_request, clear_response = specs["srv/JointLimitsServiceClearFault"]
    assert fields(clear_request) == [] and fields(clear_response) == []
    assert [(c.name, c.value) for c in specs["msg/RobotArmConstants"][0].constants] == [("JOINT_COUNT", 6)]
    assert fields(specs["msg/RobotArmState"][0])[0] == ("mode", "int32", 0)
    pkg = catkin_package(files["robot_arm_msgs/package.xml"])
    assert (pkg.name, pkg.version) == ("robot_arm_msgs", "1.2.0")
    assert [d.name for d in pkg.build_depends] == ["action_msgs", "builtin_interfaces", "geometry_msgs"]
    assert "DEPENDENCIES action_msgs builtin_interfaces geometry_msgs" in files["robot_arm_msgs/CMakeLists.txt"]
    params = load_yaml(files["robot_arm_msgs/config/robot_arm.params.yaml"])
    assert params == {"robot_arm": {"ros__parameters": {"rate_hz": 250.0, "max_speed": 1.5, "watchdog_ms": 100}}}


def test_injection_values_survive_exactly() -> None:
    comp = compile_file(CASES["injection"])
    files = generated("injection")
    model = {f.name: f.default.value for f in comp.interface.symbols["Inject"].fields}
    spec = parsed(files)["msg/Inject"][0]
    got = {f.name: f.default_value for f in spec.fields}
    for name in ("quoted", "path", "angle"):
        assert got[name] == model[name]
    assert got["words"] == ["a b", "c-d", "<e>", "*/"]
    assert got["number"] == -5 and got["ratio"] == 1e-5 and got["flag"] is True
    assert {c.name: c.value for c in spec.constants} == {"CLOSE": '*/ "quoted" a=b', "LT": "<tag>"}
    text = files["injection_pkg/msg/Inject.msg"]
    for line in text.splitlines():
        assert line == "" or line.startswith("#") or re.match(r"^[a-z0-9<=\[\]]+ [A-Za-z_]", line), line
    params = load_yaml(files["injection_pkg/config/injector.params.yaml"])["injector"]["ros__parameters"]
    assert params == {"colon": "a: b # c", "multi": "line1\nline2\ttab", "quotes": 'it\'s "q" \\ back',
                      "yes_word": "yes", "empty": "", "on": 1, "big": 1e20, "list_values": [1.0, 2.5],
                      "names": ["x", "y # z"], "enabled": False}


REFUSED = [
    ('message M { string s = "a#b" }', "ros2-hash-in-string"),
    ('message M { const string C = "x # y" }', "ros2-hash-in-string"),
    ('message M { string s = "a\\nb" }', "ros2-unwritable-string"),
    ('message M { string s = "a=b" }', "ros2-unwritable-string"),
    ('message M { string[] s = [" a"] }', "ros2-unwritable-string"),
    ("union U { 1: i32 a, 2: string b }", "ros2-unsupported"),
    ("message M { map<string, i32> m }", "ros2-unsupported"),
    ("message M { set<i32> s }", "ros2-unsupported"),
    ('senum S { "a", "b" }', "ros2-unsupported"),
    ("message M { i32[][] grid }", "ros2-unsupported"),
    ("message M { binary[] blobs }", "ros2-unsupported"),
    ("exception E { 1: string why }\nservice S { i32 f(1: i32 a) throws (1: E e) }", "ros2-unsupported"),
    ("message foo_bar { i32 a }\nmessage FooBar { i32 a }", "ros2-name-clash"),
    ("message M { i32 maxSpeed, i32 max_speed }", "ros2-name-clash"),
    ('namespace ros2 "../evil"\nmessage M { i32 a }', "ros-name-invalid"),
    ("message M { i32 a }\nconfiguration P { M nested }", "ros2-param-type"),
]


@pytest.mark.parametrize(("text", "code"), REFUSED)
def test_what_ros2_cannot_hold_is_an_error(text: str, code: str) -> None:
    comp = compile_text(text)
    assert not comp.has_errors, [d.format() for d in comp.diagnostics]
    result = run("ros2", comp)
    assert code in codes(result)
    assert result.has_errors and result.files == []
    located = [d for d in result.diagnostics if d.code == code]
    assert all(d.path == comp.path for d in located)


def test_ros2_codes_are_documented() -> None:
    from iface.emit.ros2 import CODES

    used = {code for _, code in REFUSED} - {"ros-name-invalid"}
    assert used <= set(CODES)


def test_included_file_of_another_package_becomes_a_dependency(tmp_path: Path) -> None:
    (tmp_path / "common.iface").write_text("namespace ros2 common_msgs\nmessage Point3 { double x }\n")
    (tmp_path / "main.iface").write_text('include "common.iface"\nnamespace ros2 main_pkg\n'
                                         "message Path { common.Point3[] points }\n")
    result = run("ros2", compile_file(tmp_path / "main.iface"))
    assert not result.has_errors
    files = {f.path: f.text for f in result.files}
    assert "main_pkg/msg/Point3.msg" not in files
    spec = rosidl_parse(files["main_pkg/msg/Path.msg"], "main_pkg", "msg", "Path")[0]
    assert fields(spec) == [("points", "common_msgs/Point3[]", None)]
    assert [d.name for d in catkin_package(files["main_pkg/package.xml"]).build_depends] == ["common_msgs"]
    assert "DEPENDENCIES common_msgs" in files["main_pkg/CMakeLists.txt"]


def test_package_name_defaults_to_the_file_stem(tmp_path: Path) -> None:
    (tmp_path / "My-Robot.iface").write_text("message M { i32 a }\n")
    result = run("ros2", compile_file(tmp_path / "My-Robot.iface"))
    assert {f.path.split("/")[0] for f in result.files} == {"my_robot"}
    assert "ros-naming" in codes(result)


def test_lowering_reports_no_errors_for_the_examples() -> None:
    for case in ("listing1", "robot_arm"):
        pkg, diags = lower(compile_file(CASES[case]))
        assert pkg is not None and not [d for d in diags if d.severity == 1]


def test_template_folder_can_be_overridden(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "msg.j2").write_text("{{ header }}\n# custom {{ interface.name }}\n")
    monkeypatch.setenv("IFACE_TEMPLATES_ROS2", str(tmp_path))
    files = {f.path: f.text for f in run("ros2", compile_file(CASES["listing1"])).files}
    assert files["listing1/msg/Message1.msg"].endswith("# custom Message1\n")
    assert files["listing1/srv/Service1.srv"].count("---") == 1


@pytest.mark.parametrize("target", ["ros2", "idl", "ardupilot"])
def test_an_external_package_rosidl_refuses_is_an_error_at_the_type(target: str) -> None:
    text = "external geometryMsgs\nmessage M { geometryMsgs.Pose p }\n"
    comp = compile_text(text)
    assert not comp.has_errors
    result = run(target, comp)
    found = [d for d in result.diagnostics if d.code == "ros-name-invalid"]
    assert len(found) == 1 and result.files == []
    assert "'geometryMsgs' is not a ROS 2 package name" in found[0].message
    assert text[found[0].span.start:found[0].span.end] == "geometryMsgs.Pose"


def test_names_rosidl_checks_are_the_ones_lowering_enforces() -> None:
    """The vendored rosidl parser's name patterns accept exactly what the lowering writes."""
    from mcap_ros2._vendor.rosidl_adapter import parser as rosidl

    from iface.model.naming import is_ros_constant, is_ros_field, is_ros_type

    samples = ["a", "a1", "a_b", "a__b", "a_", "_a", "A", "Ab", "AB", "A_B", "A__B", "A_", "1a", "aB", "a1_2"]
    for s in samples:
        assert is_ros_field(s) == rosidl.is_valid_field_name(s) == rosidl.is_valid_package_name(s), s
        assert is_ros_constant(s) == rosidl.is_valid_constant_name(s), s
        assert is_ros_type(s) == rosidl.is_valid_message_name(s), s


def test_the_diagnostics_service_is_converted_without_a_warning() -> None:
    src = ("component probe\n/** Health of the probe. */\n"
           "service diagnostics { request { bool verbose } response { string report } }\n"
           "service other_thing { request { i32 a } response { i32 b } }\n")
    comp = compile_text(src, "probe.iface")
    # the core checks exempt the diagnostics service and convert other_thing with a warning, like the target
    assert [d.code for d in comp.all_diagnostics() if d.code.startswith("ros-")] == ["ros-naming"]
    result = run("ros2", comp)
    assert not result.has_errors
    assert "srv/Diagnostics.srv" in {f.path.split("/", 1)[1] for f in result.files}
    warned = [comp.interface.source.text[d.span.start:d.span.end] for d in result.diagnostics
              if d.code == "ros-naming"]
    assert warned == ["other_thing"]  # any other name is still converted with a warning
    specs = parsed({f.path: f.text for f in result.files})
    assert [f.name for f in specs["srv/Diagnostics"][0].fields] == ["verbose"]


def test_the_docs_example_generates_without_warnings(tmp_path: Path) -> None:
    src = (ROOT / "docs" / "language.md").read_text()
    block = src[src.index("\nservice diagnostics {") + 1:]
    block = block[:block.index("\n}\n") + 3]
    comp = compile_text('component robot (license = "MIT", maintainer = "R. Obot", maintainer_email = "r@example.com")\n'
                        + block, "robot.iface", tmp_path)
    assert not comp.has_errors, [d.format() for d in comp.diagnostics]
    result = run("ros2", comp)
    assert not result.has_errors and [f.path for f in result.files if "/srv/" in f.path] == [
        "robot/srv/Diagnostics.srv"]
    assert [d.format() for d in result.diagnostics] == []
