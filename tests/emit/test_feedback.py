"""Issue 16's feedback: what generation tells the user, and the small wrong answers it gave.

Every file written is named; a refused file says whether it was edited by hand or was never
iface's; package.xml placeholders are a warning; the parameter YAML states every default as a
key and says why a parameter is absent; ``ap.name`` with its prefix is not doubled; PX4's own
message and topic names are warned about, naming the PX4 release.
"""

from __future__ import annotations

import json
from pathlib import Path

import yaml

from iface.emit import generate
from iface.semantics.compile import Workspace
from tests.conftest import ROOT, run_main

from .oracles import load_yaml

ARM = ROOT / "examples" / "robot_arm.iface"


def _generate(text: str, target: str, tmp: Path, name: str = "snippet.iface"):  # type: ignore[no-untyped-def]
    path = tmp / name
    path.write_text(text)
    return generate(Workspace().compile_path(str(path)), target)


def test_every_file_written_is_named_and_quiet_silences(tmp_path: Path) -> None:
    done = run_main("generate", str(ARM), "-t", "json", "-o", str(tmp_path))
    assert done.returncode == 0
    assert f"wrote {tmp_path / 'robot_arm.json'}" in done.stderr  # one file: named too
    assert done.stderr.splitlines()[-1] == "1 written, 0 unchanged"
    md = run_main("generate", str(ARM), "-t", "markdown", "-o", str(tmp_path))
    assert f"wrote {tmp_path / 'robot_arm.md'}" in md.stderr
    assert run_main("generate", str(ARM), "-t", "markdown", "-o", str(tmp_path), "--force", "-q").stderr == ""


def test_a_refused_file_says_whether_it_was_edited_or_never_iface_s(tmp_path: Path) -> None:
    assert run_main("generate", str(ARM), "-t", "px4", "-o", str(tmp_path), "-q").returncode == 0
    edited = tmp_path / "msg" / "JointState.msg"
    edited.write_text(edited.read_text() + "# a note\n")
    foreign = tmp_path / "msg" / "JointCommand.msg"
    foreign.write_text("# PX4's own file, written by hand\nuint64 timestamp\n")
    done = run_main("generate", str(ARM), "-t", "px4", "-o", str(tmp_path))
    assert done.returncode == 1
    lines = {line.split(": ", 1)[1].split(" ", 1)[0]: line for line in done.stderr.splitlines()
             if line.startswith("iface-lsp generate: ")}
    assert "was edited by hand since it was generated" in lines[str(edited)]
    assert "exists and was not written by iface" in lines[str(foreign)]
    assert "edited by hand" not in lines[str(foreign)]


def test_placeholder_package_metadata_is_a_warning_on_the_component(tmp_path: Path) -> None:
    result = _generate('component lidar version "1.0"\nnamespace ros2 lidar\nmessage Scan { u32 n }\n'
                       'publishes Scan on "/scan"\n', "ros2", tmp_path)
    (d,) = [d for d in result.diagnostics if d.code == "ros2-package-metadata-missing"]
    assert d.severity.label == "warning" and d.location()[:2] == (1, 11) and d.data == {"missing": [
        "license", "maintainer"]}
    xml = next(f.text for f in result.files if f.path.endswith("package.xml"))
    assert "<license>TODO</license>" in xml
    done = generate(Workspace().compile_path(str(ARM)), "ros2")
    assert not [x for x in done.diagnostics if x.code == "ros2-package-metadata-missing"]
    half = _generate('component half (license = "MIT")\nmessage M { u8 a }\n', "ros2", tmp_path, "half.iface")
    (h,) = [x for x in half.diagnostics if x.code == "ros2-package-metadata-missing"]
    assert h.data == {"missing": ["maintainer"]} and "license" not in h.message.split(":")[0]


def test_parameter_yaml_has_every_default_as_a_key_and_says_why_one_is_absent(tmp_path: Path) -> None:
    result = _generate('component c (license = "MIT", maintainer = "M")\nconfiguration p {\n'
                       '  /** Gain. */ float64 gain = 1.0 (unit = "dB"),\n  string name,\n  i32[] ids = [],\n'
                       '  i32 n = 2\n}\n', "ros2", tmp_path)
    text = next(f.text for f in result.files if f.path.endswith(".params.yaml"))
    assert load_yaml(text) == {"c": {"ros__parameters": {"gain": 1.0, "n": 2}}}
    assert "    # name (string): no default, so not set here: every launch must set it\n" in text
    assert "    # ids (int32[]): not set here: ROS 2 cannot load an empty list from YAML" in text
    assert text.index("gain: 1.0") < text.index("# name") < text.index("# ids") < text.index('"n": 2')


def test_parameter_yaml_without_any_default_explains_the_empty_map(tmp_path: Path) -> None:
    result = _generate("component c\nconfiguration p { string a, float64 b }\n", "ros2", tmp_path)
    text = next(f.text for f in result.files if f.path.endswith(".params.yaml"))
    body = text.split("\n", 1)[1]
    assert body == ("c:\n  # a (string): no default, so not set here: every launch must set it\n"
                    "  # b (float64): no default, so not set here: every launch must set it\n"
                    "  # (an empty map: ROS 2 refuses ros__parameters without one)\n  ros__parameters: {}\n")
    assert yaml.safe_load(text) == {"c": {"ros__parameters": {}}}


def test_ap_name_given_with_its_prefix_is_not_doubled(tmp_path: Path) -> None:
    result = _generate('component arm\nconfiguration p {\n  1: float max_speed = 1.0 (ap.name = "ARM_SPD"),\n'
                       '  2: float gain = 2.0 (ap.name = "GAIN")\n} (ap.prefix = "ARM")\n', "ardupilot", tmp_path)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    cpp = next(f.text for f in result.files if f.path.endswith(".cpp"))
    assert 'AP_GROUPINFO("SPD", 1,' in cpp and 'AP_GROUPINFO("GAIN", 2,' in cpp
    assert "ARM_ARM" not in cpp and "ARM_SPD" not in cpp.replace("// @Param: SPD", "")
    doc = (ROOT / "docs" / "targets-px4-ardupilot.md").read_text()
    assert '(ap.name = "SPD")' in doc and "not added\na second time" in doc


PX4_NAV = """component nav
namespace px4 nav
external px4_msgs
message VehicleStatus { u64 timestamp, u8 mode }
message Health { u64 timestamp, u8 level } (px4.topics = "battery_status")
publishes VehicleStatus on "/status"
publishes Health on "/fmu/out/vehicle_attitude"
subscribes px4_msgs.SensorGps on "/fmu/out/vehicle_gps_position"
"""


def test_px4_names_of_px4_s_own_messages_and_topics_are_warned_about(tmp_path: Path) -> None:
    result = _generate(PX4_NAV, "px4", tmp_path, "nav.iface")
    from iface.emit.px4.upstream import upstream

    found = sorted((d.location()[0], d.message) for d in result.diagnostics if d.code == "px4-upstream-name")
    version = upstream().version
    assert [line for line, _ in found] == [4, 5, 7]
    assert f"PX4's own uORB message VehicleStatus (PX4 {version})" in found[0][1]
    assert f"PX4's own topic of BatteryStatus (PX4 {version})" in found[1][1]
    assert "PX4's own topic of VehicleAttitude" in found[2][1]
    assert all(d.severity.label == "warning" for d in result.diagnostics if d.code == "px4-upstream-name")
    assert not result.has_errors  # PX4's own message on its own topic (SensorGps) is not reported


def test_px4_s_own_message_set_is_not_warned_about(tmp_path: Path) -> None:
    result = _generate("component px4_msgs\nmessage VehicleStatus { u64 timestamp, u8 mode }\n", "px4", tmp_path,
                       "px4_msgs.iface")
    assert not [d for d in result.diagnostics if d.code == "px4-upstream-name"]


def test_the_upstream_list_carries_its_px4_version_source_and_licence() -> None:
    data = json.loads((ROOT / "server" / "iface" / "emit" / "px4" / "upstream.json").read_text())
    assert data["px4_version"].startswith("v1.") and "BSD-3-Clause" in data["license"]
    assert "github.com/PX4/px4_msgs" in data["source"] and "PX4/PX4-Autopilot" in data["source"]
    assert data["messages"]["SensorGps"] == ["sensor_gps", "vehicle_gps_position"]
    assert len(data["messages"]) > 200
