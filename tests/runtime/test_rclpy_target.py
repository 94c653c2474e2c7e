"""The rclpy target without ROS: goldens, the generation gap, the user-code check, the parsers' view."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from iface.emit import generate, get_target
from iface.emit.base import GeneratedFile
from iface.nodes import protocol, remap
from iface.semantics.compile import Workspace
from tests.emit.golden_util import check_component_golden
from tests.emit.oracles import catkin_package, load_yaml, rosbags_parse, rosidl_parse

from ..ros_harness.ros import DATA, ROOT

CASES = {
    "robot_arm": ROOT / "examples" / "robot_arm.iface",
    "every_member": DATA / "every_member.iface",
    "listing1": ROOT / "examples" / "listing1.iface",
}
_INTERFACE = re.compile(r"^([a-z0-9_]+)/(msg|srv|action)/([A-Za-z0-9]+)\.(msg|srv|action)$")


def files_of(case: str) -> list[GeneratedFile]:
    result = generate(Workspace().compile_path(str(CASES[case])), "rclpy")
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return result.files


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True, timeout=120,
                          cwd=cwd, check=False)


def component_of(files: dict[str, str]) -> str:
    """The component package among the generated ones (the shared runtime has a setup.py too)."""
    return next(p.split("/")[0] for p in files if p.endswith("/setup.py") and not p.startswith("iface_runtime_py/"))


def test_found_through_the_entry_point() -> None:
    target = get_target("rclpy")
    assert target is not None and target.name == "rclpy"
    assert "rclpy" in cli("targets").stdout


@pytest.mark.parametrize("case", sorted(CASES))
def test_golden(case: str) -> None:
    check_component_golden("rclpy", case, files_of(case))


@pytest.mark.parametrize("case", sorted(CASES))
def test_byte_identical_across_runs(case: str) -> None:
    assert [(f.path, f.text) for f in files_of(case)] == [(f.path, f.text) for f in files_of(case)]


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_file_passes_its_parser(case: str) -> None:
    """Python compiles, package.xml validates, YAML loads, every interface file passes rosidl and rosbags."""
    files = {f.path: f.text for f in files_of(case)}
    component = component_of(files)
    for path, text in files.items():
        m = _INTERFACE.match(path)
        if m:
            pkg, kind, name = m.groups()[:3]
            specs = rosidl_parse(text, pkg, kind, name)
            bags = rosbags_parse(text, pkg, kind, name)
            assert len(specs) == len(bags)
        elif path.endswith(".py"):
            compile(text, path, "exec")
        elif path.endswith("package.xml"):
            pkg_xml = catkin_package(text)
            if path.startswith(component + "/"):
                assert pkg_xml.get_build_type() == "ament_python"
                depends = {d.name for d in pkg_xml.exec_depends}
                assert {"rclpy", "iface_runtime_py", "iface_msgs"} <= depends
            elif path.startswith("iface_runtime_py/"):
                assert pkg_xml.get_build_type() == "ament_python"
                depends = {d.name for d in pkg_xml.exec_depends}
                assert {"rclpy", "iface_msgs", "diagnostic_msgs", "lifecycle_msgs", "rcl_interfaces"} <= depends
        elif path.endswith(".yaml"):
            assert "ros__parameters" in next(iter(load_yaml(text).values()))


def test_the_protocol_services_are_in_iface_msgs_and_no_runtime_file_is_copied() -> None:
    files = {f.path: f.text for f in files_of("robot_arm")}
    cmake = files["iface_msgs/CMakeLists.txt"]
    for service in protocol.SERVICES:
        assert f"robot_arm_msgs/srv/{service.type_name}.srv" not in files
        text = files[f"iface_msgs/srv/{service.type_name}.srv"]
        request, response = rosidl_parse(text, "iface_msgs", "srv", service.type_name)
        assert [f.name for f in request.fields] == [f.name for f in service.request]
        assert [f.name for f in response.fields] == [f.name for f in service.response]
        assert f'"srv/{service.type_name}.srv"' in cmake
    control = rosidl_parse(files["iface_msgs/srv/ComponentControl.srv"], "iface_msgs", "srv",
                           "ComponentControl")[0]
    assert {c.name: c.value for c in control.constants} == {"STATUS": 0, "PAUSE": 1, "RESUME": 2, "SAVE": 3}
    component = {p: t for p, t in files.items() if p.startswith("robot_arm/")}
    assert not any(p.endswith(("runtime.py", "state.py")) for p in component)
    assert "from iface_runtime_py.runtime import" in component["robot_arm/robot_arm/base.py"]
    for name in ("runtime.py", "state.py"):
        body = files[f"iface_runtime_py/iface_runtime_py/{name}"].split("\n", 1)[1]
        assert not any(body in text for text in component.values())


def test_the_interface_package_is_the_ros2_targets() -> None:
    comp = Workspace().compile_path(str(CASES["robot_arm"]))
    ros2 = {f.path: f.text for f in generate(comp, "ros2").files}
    rclpy = {f.path: f.text for f in generate(comp, "rclpy").files if f.path.startswith("robot_arm_msgs/")}
    assert rclpy == ros2


# ---- the generation gap -------------------------------------------------------------------------------


def test_an_interface_package_gets_no_node_of_nothing(tmp_path: Path) -> None:
    """A package `import --from ros2` wrote: both node targets write the interface package only, and say so."""
    msgs = tmp_path / "robot_geometry"
    for rel, text in (("msg/Point.msg", "float64 x\nfloat64 y\n"), ("srv/Locate.srv", "string name\n---\nPoint at\n"),
                      ("action/Go.action", "Point to\n---\nbool ok\n---\nfloat64 left\n")):
        (msgs / rel).parent.mkdir(parents=True, exist_ok=True)
        (msgs / rel).write_text(text)
    assert cli("import", "--from", "ros2", str(msgs), "--out", str(tmp_path / "in")).returncode == 0
    (model,) = (tmp_path / "in").glob("*.iface")
    expected = cli("generate", str(model), "--target", "ros2", "--out", str(tmp_path / "ros2"), "-q")
    assert expected.returncode == 0, expected.stderr
    wanted = {p.relative_to(tmp_path / "ros2"): p.read_bytes() for p in (tmp_path / "ros2").rglob("*") if p.is_file()}
    for target in ("rclpy", "rclcpp"):
        out = tmp_path / target
        r = cli("generate", str(model), "--target", target, "--out", str(out))
        assert r.returncode == 0, r.stderr
        assert {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()} == wanted
        (info,) = [line for line in r.stderr.splitlines() if "runtime-interface-package" in line]
        assert "robot_geometry.iface:3:11: information[runtime-interface-package]" in info
        assert "only robot_geometry/ is written" in info


def test_the_user_module_is_written_once_and_survives_regeneration_and_force(tmp_path: Path) -> None:
    iface = str(CASES["robot_arm"])
    assert cli("generate", iface, "--target", "rclpy", "--out", str(tmp_path)).returncode == 0
    node = tmp_path / "robot_arm" / "robot_arm" / "node.py"
    base = tmp_path / "robot_arm" / "robot_arm" / "base.py"
    assert "generated by iface" not in node.read_text()
    assert "generated by iface (iface-text-hash:" in base.read_text().splitlines()[0]
    mine = (DATA / "robot_arm_node.py").read_text()
    node.write_text(mine)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and p != node}
    again = cli("generate", iface, "--target", "rclpy", "--out", str(tmp_path))
    assert again.returncode == 0, again.stderr
    assert "0 written" in again.stderr and "1 kept (yours)" in again.stderr
    assert node.read_text() == mine
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and p != node} == before
    base.write_text(base.read_text() + "# edited\n")
    refused = cli("generate", iface, "--target", "rclpy", "--out", str(tmp_path))
    assert refused.returncode == 1 and "base.py was edited by hand" in refused.stderr
    forced = cli("generate", iface, "--target", "rclpy", "--out", str(tmp_path), "--force")
    assert forced.returncode == 0, forced.stderr
    assert "# edited" not in base.read_text()
    assert node.read_text() == mine
    check = cli("generate", iface, "--target", "rclpy", "--out", str(tmp_path), "--check")
    assert check.returncode == 0, check.stdout + check.stderr


def _changed(tmp_path: Path, old: str, new: str) -> Path:
    text = CASES["robot_arm"].read_text()
    assert old in text
    path = tmp_path / "src" / "robot_arm.iface"
    path.parent.mkdir()
    path.write_text(text.replace(old, new))
    (path.parent / "arm_common.iface").write_text((ROOT / "examples" / "arm_common.iface").read_text())
    return path


def test_a_member_added_to_the_interface_is_a_missing_handler_in_check(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out)).returncode == 0
    changed = _changed(tmp_path, 'provides MoveToPose on "/arm/move_to_pose"',
                       'provides MoveToPose on "/arm/move_to_pose"\nsubscribes JointCommand on "/arm/nudge"')
    regenerated = cli("generate", str(changed), "--target", "rclpy", "--out", str(out))
    assert regenerated.returncode == 0, regenerated.stderr
    assert "warning[runtime-user-code]" in regenerated.stderr
    assert "on_nudge(self, msg)" in regenerated.stderr
    check = cli("generate", str(changed), "--target", "rclpy", "--out", str(out), "--check")
    assert check.returncode == 1
    line = next(x for x in check.stdout.splitlines() if "runtime-user-code" in x)
    assert re.match(r".*robot_arm/robot_arm/node\.py:\d+:\d+: error\[runtime-user-code\]: RobotArm has no "
                    r"on_nudge\(self, msg\), which handles 'subscribes JointCommand on /arm/nudge'", line), line


def test_a_member_removed_from_the_interface_is_a_handler_that_handles_nothing(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out)).returncode == 0
    changed = _changed(tmp_path, 'subscribes JointCommand on "/arm/joint_command" (qos.depth = 10)\n', "")
    check = cli("generate", str(changed), "--target", "rclpy", "--out", str(out), "--check")
    assert check.returncode == 1
    assert "RobotArm.on_joint_command handles nothing in robot_arm.iface" in check.stdout


def test_a_handler_with_other_arguments_is_reported_at_its_line(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out)).returncode == 0
    node = out / "robot_arm" / "robot_arm" / "node.py"
    text = node.read_text().replace("def on_joint_command(self, msg: JointCommand)",
                                    "def on_joint_command(self, msg: JointCommand, extra)")
    node.write_text(text)
    line = 1 + text[:text.index("def on_joint_command")].count("\n")
    check = cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out), "--check")
    assert check.returncode == 1
    assert f"node.py:{line}:5: error[runtime-user-code]: RobotArm.on_joint_command cannot be called with (msg)" \
        in check.stdout


def test_a_user_module_that_does_not_parse_is_reported_not_raised(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out)).returncode == 0
    (out / "robot_arm" / "robot_arm" / "node.py").write_text("class RobotArm(:\n")
    check = cli("generate", str(CASES["robot_arm"]), "--target", "rclpy", "--out", str(out), "--check")
    assert check.returncode == 1 and "Traceback" not in check.stderr
    assert "error[runtime-user-code]: the user module does not parse" in check.stdout


# ---- names, annotations, clashes -------------------------------------------------------------------------


def _generated(text: str, tmp_path: Path) -> tuple[dict[str, str], list[str]]:
    path = tmp_path / "c.iface"
    path.write_text(text)
    result = generate(Workspace().compile_path(str(path)), "rclpy")
    return {f.path: f.text for f in result.files}, [d.format() for d in result.diagnostics]


HEAD = "component c\nnamespace ros2 c_msgs\nmessage M { i32 x }\n"


def test_handlers_of_one_kind_with_one_last_segment_use_the_whole_name(tmp_path: Path) -> None:
    files, diags = _generated(HEAD + 'subscribes M on "/a/x"\nsubscribes M on "/b/x"\npublishes M on "/x"\n'
                              'subscribes M on "/configure"\n', tmp_path)
    base = files["c/c/base.py"]
    for name in ("def on_a_x(self, msg: M)", "def on_b_x(self, msg: M)", "def publish_x(self, msg: M)"):
        assert name in base, name
    assert "def on_configure(self, msg" not in base
    assert "def on_configure_subscription(self, msg: M)" in base


def test_a_definition_named_like_a_protocol_service_is_its_own(tmp_path: Path) -> None:
    """The protocol's SaveState is iface_msgs/srv/SaveState, so the interface package may have one of its own."""
    files, diags = _generated(HEAD + "service SaveState { request {} response { bool mine } }\n"
                              'publishes M on "/x"\n', tmp_path)
    assert not any("runtime-name-clash" in d for d in diags)
    own = files["c_msgs/srv/SaveState.srv"]
    assert "bool mine" in own and "bool mine" not in files["iface_msgs/srv/SaveState.srv"]


@pytest.mark.parametrize(("annotation", "rate"), [("rate = 4", 4.0), ('rate = "500ms"', 2.0), ('rate = "10 Hz"', 10.0)])
def test_the_diagnostics_rate_comes_from_the_file(annotation: str, rate: float, tmp_path: Path) -> None:
    files, _ = _generated(HEAD + f"service diagnostics {{ request {{}} response {{}} }} ({annotation})\n", tmp_path)
    assert f"DIAGNOSTICS_RATE = {rate!r}" in files["c/c/base.py"]


def test_bad_runtime_annotations_are_errors_at_the_annotation(tmp_path: Path) -> None:
    _, diags = _generated(HEAD + 'service diagnostics { request {} response {} } (rate = "fast")\n'
                          'configuration p { i32 a = 1 (read_only = "maybe") }\n', tmp_path)
    errors = [d for d in diags if "runtime-annotation" in d]
    assert len(errors) == 2 and all(re.match(r".*c\.iface:\d+:\d+: error", d) for d in errors)


def test_parameters_become_declarations_with_their_checks(tmp_path: Path) -> None:
    files, _ = _generated(DATA.joinpath("every_member.iface").read_text(), tmp_path)
    base = files["every_member/every_member/base.py"]
    assert ("ParamSpec('retries', kind='integer', default=3, description='retries', constraints='range: 0..10', "
            "low=0, high=10)") in base
    assert "ParamSpec('priority', kind='integer', default=5, description='priority', low=0, high=255)" in base
    assert "choices=(('IDLE', 0), ('RUNNING', 1), ('FAULT', 2))" in base
    assert "read_only=True" in base
    assert "size=3, size_kind='fixed'" in base and "size=4, size_kind='bounded'" in base


# ---- the launch file --------------------------------------------------------------------------------------


def _launch_constants(text: str) -> dict[str, object]:
    tree = ast.parse(text)
    return {t.id: ast.literal_eval(n.value) for n in tree.body if isinstance(n, ast.Assign)
            for t in n.targets if isinstance(t, ast.Name) and t.id.isupper()}


def _setup(text: str) -> tuple[list[str], list[tuple[str, list[str]]]]:
    """(console scripts, data files) of a generated setup.py, read from its syntax tree."""
    call = next(n for n in ast.walk(ast.parse(text)) if isinstance(n, ast.Call) and getattr(n.func, "id", "") == "setup")
    kwargs = {k.arg: k.value for k in call.keywords}
    package = next(n.value.value for n in ast.parse(text).body if isinstance(n, ast.Assign)
                   and isinstance(n.value, ast.Constant) and n.targets[0].id == "PACKAGE")  # type: ignore[attr-defined]
    scripts = ast.literal_eval(kwargs["entry_points"])["console_scripts"]
    data = []
    for item in kwargs["data_files"].elts:  # type: ignore[attr-defined]
        folder = eval(compile(ast.Expression(item.elts[0]), "setup.py", "eval"), {"PACKAGE": package})
        names = eval(compile(ast.Expression(item.elts[1]), "setup.py", "eval"), {"PACKAGE": package})
        data.append((folder, names))
    return scripts, data


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_launch_file_names_the_entry_point_the_parameter_file_and_every_wired_name(case: str) -> None:
    files = {f.path: f.text for f in files_of(case)}
    component = component_of(files)
    launch_path = next(p for p in files if p.startswith(f"{component}/launch/"))
    launch = files[launch_path]
    consts = _launch_constants(launch)
    scripts, data = _setup(files[f"{component}/setup.py"])
    assert scripts == [f"{consts['EXECUTABLE']} = {component}.__main__:main"]
    assert (f"share/{component}/config", [f"config/{consts['PARAMS_FILE']}"]) in data
    assert (f"share/{component}/launch", [launch_path.split("/", 1)[1]]) in data
    assert f"{component}/config/{consts['PARAMS_FILE']}" in files
    comp = Workspace().compile_path(str(CASES[case]))
    from iface.emit.ros2.lower import lower_run
    from iface.nodes.component import describe

    pkg, _, run = lower_run(comp)
    assert pkg is not None
    spec, _ = describe(comp, pkg, run)
    wired = {m.name for m in spec.all_members() if not m.name.startswith("~")}
    assert {name for name, _, _ in consts["REMAPPINGS"]} == wired  # type: ignore[union-attr]
    actions = {m.name for m in spec.all_members() if m.kind in ("action_server", "action_client")}
    assert {name for name, _, action in consts["REMAPPINGS"] if action} == actions  # type: ignore[union-attr]
    assert consts["ACTION_PARTS"] == remap.ACTION_PARTS
    # what `ros2 launch` makes of it: tests/runtime/test_launch.py runs it


def test_an_action_is_remapped_by_its_name_and_its_five_parts() -> None:
    assert remap.rules("/a/t", "/b/t") == [("/a/t", "/b/t")]
    assert remap.arguments("/station/travel", "/peer/travel", action=True) == [
        "-r", "/station/travel:=/peer/travel",
        "-r", "/station/travel/_action/send_goal:=/peer/travel/_action/send_goal",
        "-r", "/station/travel/_action/cancel_goal:=/peer/travel/_action/cancel_goal",
        "-r", "/station/travel/_action/get_result:=/peer/travel/_action/get_result",
        "-r", "/station/travel/_action/feedback:=/peer/travel/_action/feedback",
        "-r", "/station/travel/_action/status:=/peer/travel/_action/status",
    ]


# ---- QoS values ROS 2 has no setting for -------------------------------------------------------------

QOS_DOWNGRADED = """component q
message M { i32 x }
service S { request { i32 a } response { i32 b } }
publishes M on "/kept" (qos.durability = "transient")
subscribes M on "/in" (qos.durability = "persistent", qos.liveliness = "MANUAL_BY_NODE")
provides S on "/s" (qos.durability = "transient_local", qos.liveliness = "manual_by_topic")
"""
#: (line, column, what) of each runtime-qos-downgraded warning for QOS_DOWNGRADED: not the values ROS 2 has.
QOS_WARNINGS = [("4", "25", "qos.durability = transient"), ("5", "24", "qos.durability = persistent"),
                ("5", "55", "qos.liveliness = manual_by_node")]


def downgrade_warnings(stderr: str) -> list[tuple[str, str, str]]:
    """(line, column, what) of each runtime-qos-downgraded warning ``generate`` printed for q.iface."""
    return re.findall(r"^(?:.*[/\\])?q\.iface:(\d+):(\d+): warning\[runtime-qos-downgraded\]: (qos\.\w+ = \w+): ",
                      stderr, re.M)


def test_qos_values_ros2_lacks_are_downgraded_with_a_warning_at_the_annotation(tmp_path: Path) -> None:
    (tmp_path / "q.iface").write_text(QOS_DOWNGRADED)
    proc = cli("generate", "q.iface", "--target", "rclpy", "--out", "out", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert downgrade_warnings(proc.stderr) == QOS_WARNINGS, proc.stderr
    assert "the generated node asks for transient_local" in proc.stderr
    base = (tmp_path / "out" / "q_node" / "q_node" / "base.py").read_text()
    assert "self._publisher(M, '/kept', {'durability': 'transient_local'})" in base
    assert "'/in', 'on_in', {'durability': 'transient_local', 'liveliness': 'manual_by_topic'})" in base
    assert (tmp_path / "out" / "q" / "msg" / "M.msg").is_file()
    # the values ROS 2 has are given as written, without a warning
    (tmp_path / "ok").mkdir()
    (tmp_path / "ok" / "q.iface").write_text(QOS_DOWNGRADED.replace('"transient"', '"transient_local"').replace(
        '"persistent"', '"volatile"').replace("MANUAL_BY_NODE", "automatic"))
    ok = cli("generate", "q.iface", "--target", "rclpy", "--out", "out", cwd=tmp_path / "ok")
    assert ok.returncode == 0 and "runtime-qos-downgraded" not in ok.stderr, ok.stderr
    assert "'/in', 'on_in', {'durability': 'volatile', 'liveliness': 'automatic'})" in \
        (tmp_path / "ok" / "out" / "q_node" / "q_node" / "base.py").read_text()


def test_check_warns_at_the_annotation_as_generate_does(tmp_path: Path) -> None:
    """`check` says of the QoS values rmw lacks what generate says, at the same place (qos-not-in-rmw)."""
    (tmp_path / "q.iface").write_text(QOS_DOWNGRADED)
    generated = cli("generate", "q.iface", "--target", "rclpy", "--out", "out", "--dry-run", cwd=tmp_path)
    checked = cli("check", "q.iface", cwd=tmp_path)
    assert checked.returncode == 0, checked.stdout
    said = re.findall(r"^q\.iface:(\d+):(\d+): warning\[runtime-qos-downgraded\]: (.*)$", generated.stderr, re.M)
    found = re.findall(r"^q\.iface:(\d+):(\d+): warning\[qos-not-in-rmw\]: (.*)$", checked.stdout, re.M)
    assert found == said and [w[:2] for w in found] == [w[:2] for w in QOS_WARNINGS], checked.stdout
    assert checked.stdout.splitlines()[-1] == "ok: 1 file, 2 definitions, 3 warnings"


# ---- versions and the shared runtime ----------------------------------------------------------------


def test_a_thermostat_sized_component_package_is_thin(tmp_path: Path) -> None:
    """3 parameters, 3 state variables, a subscription, a publication, a service, an action, Δ: at most 300 lines
    of code (the interface file it installs for ~/describe is data: the json target's file)."""
    result = generate(Workspace().compile_path(str(DATA / "thermostat.iface")), "rclpy")
    files = {f.path: f.text for f in result.files}
    package = {p: t for p, t in files.items() if p.startswith("thermostat/") and not p.endswith("/node.py")
               and p != "thermostat/thermostat.json"}
    lines = sum(t.count("\n") for t in package.values())
    assert lines <= 300, f"{lines} lines"
    assert not any(p.endswith(("runtime.py", "state.py")) for p in package)
    assert {p.split("/")[0] for p in files} == {"iface_msgs", "iface_runtime_py", "thermostat", "thermostat_msgs"}


def test_two_components_speak_the_protocol_through_one_type() -> None:
    """No component has a protocol type of its own: the shared runtime serves iface_msgs' for all of them."""
    runtime = next(f.text for f in files_of("robot_arm") if f.path == "iface_runtime_py/iface_runtime_py/runtime.py")
    assert "from iface_msgs.srv import ComponentControl, Describe, RestoreState, SaveState" in runtime
    assert 'self.create_service(SaveState, "~/save_state"' in runtime
    for case in ("robot_arm", "every_member"):
        files = files_of(case)
        assert not any(f.path.endswith("/srv/SaveState.srv") and not f.path.startswith("iface_msgs/") for f in files)
        assert [f.text for f in files if f.path.startswith("iface_runtime_py/")] == [
            f.text for f in files_of("listing1") if f.path.startswith("iface_runtime_py/")]


def test_describe_answers_the_json_targets_file_installed_with_the_package(tmp_path: Path) -> None:
    """The component package installs the json target's file (share/<package>/), the base class names
    it, and what generate writes there is the json target's file byte for byte (what ~/describe answers)."""
    files = {f.path: f.text for f in files_of("robot_arm")}
    assert "INTERFACE_FILE = 'robot_arm.json'" in files["robot_arm/robot_arm/base.py"]
    assert """("share/" + PACKAGE, ["package.xml", 'robot_arm.json']),""" in files["robot_arm/setup.py"]
    for target in ("json", "rclpy"):
        done = cli("generate", str(CASES["robot_arm"]), "--target", target, "--out", str(tmp_path / target), "-q")
        assert done.returncode == 0, done.stderr
    assert (tmp_path / "rclpy" / "robot_arm" / "robot_arm.json").read_bytes() == \
        (tmp_path / "json" / "robot_arm.json").read_bytes()
