"""The rclcpp target without ROS: goldens, the generation gap, the user-code check, the parsers' view."""

from __future__ import annotations

import ast
import re
import subprocess
from pathlib import Path

import pytest

from iface.emit import generate, get_target
from iface.emit.base import GeneratedFile
from iface.semantics.compile import Workspace
from tests.conftest import run_main
from tests.emit.golden_util import check_component_golden
from tests.emit.oracles import catkin_package, load_yaml

from ..ros_harness.ros import DATA, ROOT

CASES = {
    "robot_arm": ROOT / "examples" / "robot_arm.iface",
    "every_member": DATA / "every_member.iface",
    "counter_v2": ROOT / "examples" / "counter_v2.iface",
}


def files_of(case: str, target: str = "rclcpp") -> list[GeneratedFile]:
    result = generate(Workspace().compile_path(str(CASES[case])), target)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return result.files


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    """``iface-lsp ARGS``, run in this process."""
    return run_main(*args)


def test_found_through_the_entry_point() -> None:
    target = get_target("rclcpp")
    assert target is not None and target.name == "rclcpp"
    assert re.search(r"^rclcpp\s", cli("targets").stdout, re.MULTILINE)


@pytest.mark.parametrize("case", sorted(CASES))
def test_golden(case: str) -> None:
    check_component_golden("rclcpp", case, files_of(case))


@pytest.mark.parametrize("case", sorted(CASES))
def test_byte_identical_across_runs(case: str) -> None:
    assert [(f.path, f.text) for f in files_of(case)] == [(f.path, f.text) for f in files_of(case)]


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_interface_package_is_the_rclpy_targets(case: str) -> None:
    """One interface package for both languages: a C++ node and a Python node talk through the same types."""
    cpp = {f.path: f.text for f in files_of(case)}
    py = {f.path: f.text for f in files_of(case, "rclpy")}
    interface = next(p.split("/")[0] for p in py if p.endswith("/srv/SaveState.srv"))
    assert {p: t for p, t in cpp.items() if p.startswith(interface + "/")} == \
        {p: t for p, t in py.items() if p.startswith(interface + "/")}


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_file_passes_its_parser(case: str) -> None:
    """package.xml validates as ament_cmake with its dependencies, YAML loads, the launch file compiles,
    every C++ file has balanced braces and includes only what the package and its dependencies hold."""
    files = {f.path: f.text for f in files_of(case)}
    component = next(p.split("/")[0] for p in files if p.endswith("/src/main.cpp"))
    pkg_xml = catkin_package(files[f"{component}/package.xml"])
    assert pkg_xml.get_build_type() == "ament_cmake"
    depends = {d.name for d in pkg_xml.build_depends} & {d.name for d in pkg_xml.exec_depends}
    assert {"iface_runtime_cpp", "rclcpp", "rclcpp_lifecycle", "rclcpp_action", "rclcpp_components"} <= depends
    cmake = files[f"{component}/CMakeLists.txt"]
    for dep in depends:
        assert f"find_package({dep} REQUIRED)" in cmake, dep
    for path in re.findall(r"^\s+(src/\S+\.cpp)$", cmake, re.MULTILINE):
        assert f"{component}/{path}" in files, path
    params = load_yaml(files[next(p for p in files if p.startswith(f"{component}/config/"))])
    assert "ros__parameters" in params["/**"]
    compile(files[next(p for p in files if p.startswith(f"{component}/launch/"))], "launch.py", "exec")
    shared = catkin_package(files["iface_runtime_cpp/package.xml"])
    deps_of = {component: depends, "iface_runtime_cpp": {d.name for d in shared.build_depends}}
    for path, text in files.items():
        if not path.endswith((".cpp", ".hpp")):
            continue
        owner = path.split("/")[0]
        code = re.sub(r'R"\((?:.|\n)*?\)"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\])\'|//[^\n]*', "", text)
        assert code.count("{") == code.count("}") and code.count("(") == code.count(")"), path
        for header in re.findall(r'^#include "([^"]+)"', text, re.MULTILINE):
            if "/" not in header:  # a file beside it (the runtime's tests: check.hpp)
                assert f"{path.rsplit('/', 1)[0]}/{header}" in files, (path, header)
                continue
            package = header.split("/")[0]
            assert package == owner or package in deps_of[owner] or package == "rosidl_runtime_cpp", (path, header)


def test_the_machinery_is_one_shared_package_the_components_link() -> None:
    """iface_runtime_cpp is the same for every component, exports its library target and serves the protocol
    with iface_msgs' types; a component package holds no runtime file, builds a component library registered
    with rclcpp_components (under its package and under package@version) and keeps its executable."""
    runtimes = []
    for case in sorted(CASES):
        files = {f.path: f.text for f in files_of(case)}
        runtimes.append({p: t for p, t in files.items() if p.startswith("iface_runtime_cpp/")})
        component = next(p.split("/")[0] for p in files if p.endswith("/src/main.cpp"))
        assert not [p for p in files if p.startswith(f"{component}/") and "iface_runtime" in p.rsplit("/", 1)[1]]
        cmake = files[f"{component}/CMakeLists.txt"]
        base = files[f"{component}/include/{component}/base.hpp"]
        version = catkin_package(files[f"{component}/package.xml"]).version
        cls = re.search(r"^class (\w+)Base : public iface_runtime::ComponentNode", base, re.MULTILINE).group(1)
        plugin = f"{component}::{cls}"
        assert re.search(r"rclcpp_components_register_node\(\$\{PROJECT_NAME\}_component\s+PLUGIN \"" + plugin +
                         r"\"\s+EXECUTABLE \$\{PROJECT_NAME\}_node", cmake), cmake
        assert f"ament_index_register_resource(rclcpp_components PACKAGE_NAME {component}@{version}" in cmake
        assert f'CONTENT "{plugin};lib/$<TARGET_FILE_NAME:${{PROJECT_NAME}}_component>\\n"' in cmake
        assert "add_executable(${PROJECT_NAME} src/main.cpp)" in cmake
        assert "iface_runtime_cpp::iface_runtime_cpp" in cmake and "CXX_VISIBILITY_PRESET hidden" in cmake
        assert "RCLCPP_COMPONENTS_REGISTER_NODE(Class)" in base and f'== "{plugin}"' in base
    assert runtimes[0] and all(r == runtimes[0] for r in runtimes)
    shared = runtimes[0]
    xml = catkin_package(shared["iface_runtime_cpp/package.xml"])
    assert xml.get_build_type() == "ament_cmake" and {d.name for d in xml.build_depends} >= {"iface_msgs", "rclcpp"}
    cmake = shared["iface_runtime_cpp/CMakeLists.txt"]
    container = "src/container.cpp"  # iface_container's main: an executable of the package, not the library
    sources = sorted(p.split("/", 1)[1] for p in shared if p.startswith("iface_runtime_cpp/src/"))
    assert container in sources
    assert re.search(r"add_library\(\$\{PROJECT_NAME\} SHARED\n" + "".join(f"  {s}\n" for s in sources
                                                                    if s != container) + r"\)", cmake), cmake
    assert f"add_executable(iface_container {container})" in cmake
    assert "install(TARGETS iface_container DESTINATION lib/${PROJECT_NAME})" in cmake
    assert "ament_export_targets(export_${PROJECT_NAME} HAS_LIBRARY_TARGET)" in cmake
    served = shared["iface_runtime_cpp/src/node.cpp"]
    for srv in ("SaveState", "RestoreState", "ComponentControl", "Describe"):
        assert f"using iface_msgs::srv::{srv};" in served


def test_the_state_document_is_the_python_nodes() -> None:
    """Schema, message field tables and names as the rclpy node writes them (the hand-over's common ground)."""
    files = {f.path: f.text for f in files_of("every_member")}
    py = {f.path: f.text for f in files_of("every_member", "rclpy")}
    base_py = py["every_member/every_member/base.py"]
    found = re.search(r"STATE_SCHEMA = (\{.*?\n    \})", base_py, re.DOTALL)
    assert found is not None
    schema = ast.literal_eval(found.group(1))
    base_cpp = files["every_member/src/base.cpp"]
    block = base_cpp[base_cpp.index("i.state_schema = {"):]
    block = block[:block.index("};")]
    assert dict(re.findall(r'\{"([^"]+)", "([^"]+)"\}', block)) == schema
    assert '{"every_member_msgs/Waypoint", {' in base_cpp
    assert '{"name", "string"}' in base_cpp or '{"name", "string<=' in base_cpp
    runtime = files["iface_runtime_cpp/include/iface_runtime_cpp/protocol.hpp"]
    assert 'STATE_FORMAT = "iface-state/1"' in runtime
    served = files["iface_runtime_cpp/src/node.cpp"]
    for name in ("~/save_state", "~/restore_state", "~/control", "~/describe"):
        assert f'"{name}"' in served and f'"{name}"' not in base_cpp
    assert 'DIAGNOSTICS_TOPIC = "/diagnostics"' in runtime


def test_parameters_become_descriptors_and_checks() -> None:
    base = next(f.text for f in files_of("every_member") if f.path.endswith("/src/base.cpp"))
    assert 'p.name = "retries";' in base and 'p.constraints = "range: 0..10";' in base
    assert 'p.low = iface_runtime::Bound{0.0, int64_t{0}, "0"};' in base
    assert 'p.choices.emplace_back("RUNNING", 1);' in base
    assert "p.read_only = true;" in base
    assert 'p.size_kind = "fixed";' in base and 'p.size_kind = "bounded";' in base


# ---- the generation gap -------------------------------------------------------------------------------


def test_the_user_file_is_written_once_and_survives_regeneration_and_force(tmp_path: Path) -> None:
    iface = str(CASES["counter_v2"])
    assert cli("generate", iface, "--target", "rclcpp", "--out", str(tmp_path)).returncode == 0
    node = tmp_path / "counter" / "src" / "node.cpp"
    base = tmp_path / "counter" / "include" / "counter" / "base.hpp"
    assert "generated by iface" not in node.read_text()
    assert "generated by iface (iface-text-hash:" in base.read_text().splitlines()[0]
    mine = (DATA / "counter_v2_node.cpp").read_text()
    node.write_text(mine)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and p != node}
    again = cli("generate", iface, "--target", "rclcpp", "--out", str(tmp_path))
    assert again.returncode == 0, again.stderr
    assert "0 written" in again.stderr and "1 kept (yours)" in again.stderr
    assert node.read_text() == mine
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and p != node} == before
    base.write_text(base.read_text() + "// edited\n")
    refused = cli("generate", iface, "--target", "rclcpp", "--out", str(tmp_path))
    assert refused.returncode == 1 and "base.hpp was edited by hand" in refused.stderr
    forced = cli("generate", iface, "--target", "rclcpp", "--out", str(tmp_path), "--force")
    assert forced.returncode == 0, forced.stderr
    assert "// edited" not in base.read_text()
    assert node.read_text() == mine
    check = cli("generate", iface, "--target", "rclcpp", "--out", str(tmp_path), "--check")
    assert check.returncode == 0, check.stdout + check.stderr


def test_a_changed_interface_is_reported_at_the_users_lines(tmp_path: Path) -> None:
    """A member added: its handler is missing; a member removed: its handler handles nothing."""
    out = tmp_path / "out"
    assert cli("generate", str(CASES["counter_v2"]), "--target", "rclcpp", "--out", str(out)).returncode == 0
    node = out / "counter" / "src" / "node.cpp"
    node.write_text((DATA / "counter_v2_node.cpp").read_text())
    text = CASES["counter_v2"].read_text()
    changed = tmp_path / "counter_v2.iface"
    changed.write_text(text.replace('provides Reset on "/counter/reset"\n', 'subscribes Count on "/nudge"\n'))
    warned = cli("generate", str(changed), "--target", "rclcpp", "--out", str(out))
    assert warned.returncode == 0, warned.stderr
    assert "warning[runtime-user-code]" in warned.stderr
    check = cli("generate", str(changed), "--target", "rclcpp", "--out", str(out), "--check")
    assert check.returncode == 1
    line = 1 + node.read_text()[:node.read_text().index("handle_reset")].count("\n")
    assert re.search(rf"node\.cpp:{line}:\d+: error\[runtime-user-code\]: Counter::handle_reset handles nothing "
                     r"in counter_v2\.iface", check.stdout), check.stdout
    assert re.search(r"node\.cpp:\d+:\d+: error\[runtime-user-code\]: Counter has no on_nudge\(msg\), which "
                     r"handles 'subscribes Count on /nudge'", check.stdout), check.stdout
    assert "Traceback" not in check.stderr


def test_the_compile_time_check_names_the_interface() -> None:
    """The generated macro stops the build of a class that does not match, with the reason."""
    base = next(f.text for f in files_of("counter_v2") if f.path.endswith("/include/counter/base.hpp"))
    assert "#define COUNTER_COMPONENT(Class)" in base
    assert "static_assert(" in base and "!std::is_abstract_v<Class>" in base
    assert "does not implement every handler of counter_v2.iface" in base
    assert "virtual void handle_reset(const Reset::Request & request, Reset::Response & response) = 0;" in base
    node = next(f for f in files_of("counter_v2") if f.path.endswith("/src/node.cpp"))
    assert node.once and "COUNTER_COMPONENT(counter::Counter)" in node.text and " override" in node.text


def test_a_state_with_a_message_of_another_package_is_refused_with_a_reason(tmp_path: Path) -> None:
    (tmp_path / "common.iface").write_text("namespace ros2 common_msgs\nstruct Point { float64 x }\n")
    path = tmp_path / "c.iface"
    path.write_text('include "common.iface"\ncomponent c\nnamespace ros2 c_msgs\nstate s { common.Point p }\n')
    done = cli("generate", str(path), "--target", "rclcpp", "--out", str(tmp_path / "out"))
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert re.search(r"c\.iface:4:\d+: error\[runtime-unsupported\]: the state uses common_msgs/Point from another "
                     "package", done.stdout), done.stdout
    assert not (tmp_path / "out").exists()
    assert cli("generate", str(path), "--target", "rclpy", "--out", str(tmp_path / "py")).returncode == 0


def test_qos_values_ros2_lacks_are_downgraded_with_a_warning_at_the_annotation(tmp_path: Path) -> None:
    from .test_rclpy_target import QOS_DOWNGRADED, QOS_WARNINGS, downgrade_warnings

    (tmp_path / "q.iface").write_text(QOS_DOWNGRADED)
    proc = cli("generate", str(tmp_path / "q.iface"), "--target", "rclcpp", "--out", str(tmp_path / "out"))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert downgrade_warnings(proc.stderr) == QOS_WARNINGS, proc.stderr
    base = (tmp_path / "out" / "q_node" / "src" / "base.cpp").read_text()
    assert 'make_publisher<M>("/kept", {{"durability", "transient_local"}})' in base, base
    assert '{{"durability", "transient_local"}, {"liveliness", "manual_by_topic"}}' in base
    assert "persistent" not in base and "manual_by_node" not in base
    assert (tmp_path / "out" / "q_node" / "src" / "node.cpp").is_file()
