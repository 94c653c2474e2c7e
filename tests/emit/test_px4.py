"""The px4 target: uORB messages (pyros-genmsg), module.yaml (PX4's schema), the header (g++), goldens."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import genmsg
import genmsg.msg_loader
import jsonschema
import pytest
import yaml

from iface.emit import generate, get_target
from iface.emit.base import Result
from iface.emit.px4 import CODES
from iface.semantics.compile import Workspace

from ..conftest import generated_in_two_processes
from .golden_util import check_golden

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).parent / "data" / "px4"
ROBOT_ARM = ROOT / "examples" / "robot_arm.iface"
CASES = ["flight_arm", "injection_docs"]


def run(path: Path) -> Result:
    return generate(Workspace().compile_path(str(path)), "px4")


def ok(path: Path) -> Result:
    result = run(path)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return result


def files(result: Result) -> dict[str, str]:
    return {f.path: f.text for f in result.files}


def messages(result: Result) -> dict[str, genmsg.MsgSpec]:
    """Every generated .msg parsed by pyros-genmsg, PX4's own message parser."""
    ctx = genmsg.MsgContext.create_default()
    out = {}
    for path, text in files(result).items():
        if path.startswith("msg/"):
            name = Path(path).stem
            out[name] = genmsg.msg_loader.load_msg_from_string(ctx, text, f"px4_msgs/{name}")
    return out


def topics_of(text: str, name: str) -> list[str]:
    found = [t for line in text.splitlines() if line.startswith("# TOPICS") for t in line.split()[2:]]
    return found or [re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()]


def check_header(result: Result, tmp: Path) -> None:
    """Compile the module header against stub PX4 headers, with topic headers and params from the output."""
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    out = files(result)
    inc = tmp / "inc"
    for path, text in out.items():
        if path.startswith("msg/"):
            name = Path(path).stem
            stem = re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()
            header = inc / "uORB" / "topics" / f"{stem}.h"
            header.parent.mkdir(parents=True, exist_ok=True)
            header.write_text("#pragma once\n#include <uORB/uORB.h>\n"
                              f"struct {stem}_s {{ unsigned long long timestamp; }};\n"
                              + "".join(f"extern const orb_metadata __orb_{t};\n" for t in topics_of(text, name)))
    # PX4's parameter_update topic header, as PX4 generates it (the module header subscribes it)
    update = inc / "uORB" / "topics" / "parameter_update.h"
    update.parent.mkdir(parents=True, exist_ok=True)
    update.write_text("#pragma once\n#include <uORB/uORB.h>\nstruct parameter_update_s { unsigned long long timestamp; };\n"
                      "extern const orb_metadata __orb_parameter_update;\n")
    module_yaml = next(t for p, t in out.items() if p.endswith("module.yaml"))
    params = [n for g in yaml.safe_load(module_yaml).get("parameters", []) for n in g["definitions"]]
    inc.mkdir(parents=True, exist_ok=True)
    (inc / "px4_params_generated.h").write_text(
        "#pragma once\nnamespace px4 { enum class params { " + ", ".join(params) + " }; }\n")
    header = next(p for p in out if p.endswith(".hpp"))
    (tmp / Path(header).name).write_text(out[header])
    main = tmp / "main.cpp"
    cls = Path(header).stem
    main.write_text(f'#include "{Path(header).name}"\n#include <cstdio>\n'
                    f"int main() {{ std::fputs({cls}::DESCRIPTION, stdout); return 0; }}\n"
                    if "DESCRIPTION" in out[header] else f'#include "{Path(header).name}"\nint main() {{ return 0; }}\n')
    exe = tmp / "main"
    proc = subprocess.run(["g++", "-std=c++17", "-Wall", "-Wextra", "-Werror", "-I", str(DATA / "stubs"),
                           "-I", str(inc), "-o", str(exe), str(main)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout  # type: ignore[return-value]


# ---- the target ------------------------------------------------------------------


def test_found_through_entry_point() -> None:
    target = get_target("px4")
    assert target is not None and target.name == "px4"


@pytest.mark.parametrize("case", CASES)
def test_golden(case: str) -> None:
    check_golden("px4", case, ok(DATA / f"{case}.iface").files)


def test_deterministic_across_hash_seeds() -> None:
    one, two = generated_in_two_processes("px4", [*(DATA / f"{case}.iface" for case in CASES), ROBOT_ARM])
    assert one == two and one.count("px4") >= len(CASES) + 1


# ---- oracles ------------------------------------------------------------------------


def test_messages_parse_with_genmsg() -> None:
    specs = messages(ok(DATA / "flight_arm.iface"))
    assert sorted(specs) == ["ArmSetpoint", "ArmStatus", "JointState"]
    status = specs["ArmStatus"]
    assert list(zip(status.types, status.names)) == [
        ("uint64", "timestamp"), ("px4_msgs/JointState[2]", "joints"), ("uint8", "mode"),
        ("bool", "healthy"), ("char[16]", "label")]
    assert [(c.type, c.name, c.val) for c in status.constants] == [
        ("uint8", "ORB_QUEUE_LENGTH", 4), ("uint32", "MESSAGE_VERSION", 1), ("uint8", "ARM_MODE_IDLE", 0),
        ("uint8", "ARM_MODE_HOLD", 1), ("uint8", "ARM_MODE_TRACK", 2)]
    for spec in specs.values():
        assert (spec.types[0], spec.names[0]) == ("uint64", "timestamp")


def test_topics_from_wiring_and_annotation() -> None:
    out = files(ok(DATA / "flight_arm.iface"))
    assert topics_of(out["msg/ArmSetpoint.msg"], "ArmSetpoint") == [
        "arm_setpoint", "arm_setpoint_override", "arm_setpoint_backup"]
    assert topics_of(out["msg/ArmStatus.msg"], "ArmStatus") == ["flight_arm_status"]
    assert "# TOPICS" not in out["msg/JointState.msg"]


def test_module_yaml_follows_px4_schema() -> None:
    out = files(ok(DATA / "flight_arm.iface"))
    doc = yaml.safe_load(out["src/modules/flight_arm/module.yaml"])
    jsonschema.validate(doc, json.loads((DATA / "module_schema.json").read_text()))
    defs = doc["parameters"][0]["definitions"]
    assert defs["FARM_MAX_SPEED"] == {
        "description": {"short": "Maximum joint speed.", "long": "Maximum joint speed. Applied to both joints."},
        "type": "float", "default": 1.5, "min": 0.0, "max": 3.0, "unit": "rad/s"}
    assert defs["FARM_ENABLED"]["type"] == "boolean" and defs["FARM_ENABLED"]["default"] is True
    assert defs["FARM_START_MODE"]["values"] == {0: "Idle", 1: "Hold", 2: "Track"}
    assert defs["FARM_GAIN"]["decimal"] == 3


def test_header_compiles(tmp_path: Path) -> None:
    result = ok(DATA / "flight_arm.iface")
    printed = check_header(result, tmp_path)
    assert printed == "A two-joint arm mounted under a multicopter.\n\nReads the vehicle attitude, commands the joints."
    header = files(result)["src/modules/flight_arm/FlightArm.hpp"]
    assert "uORB::Publication<arm_status_s> _flight_arm_status_pub{ORB_ID(flight_arm_status)};" in header
    assert "uORB::SubscriptionCallbackWorkItem _arm_setpoint_sub{this, ORB_ID(arm_setpoint)};" in header
    assert "uORB::Subscription _arm_setpoint_override_sub{ORB_ID(arm_setpoint_override)};" in header
    assert "(ParamFloat<px4::params::FARM_MAX_SPEED>) _param_farm_max_speed," in header


def test_robot_arm(tmp_path: Path) -> None:
    result = ok(ROBOT_ARM)
    assert messages(result)
    jsonschema.validate(yaml.safe_load(next(f.text for f in result.files if f.path.endswith("module.yaml"))),
                        json.loads((DATA / "module_schema.json").read_text()))
    check_header(result, tmp_path)


# ---- what PX4 cannot hold -----------------------------------------------------------------


def codes_by_name(result: Result) -> set[tuple[str, str]]:
    return {(d.code, m.group(1)) for d in result.diagnostics
            for m in [re.search(r"(?:field|constant|parameter) '([^']+)'", d.message)] if m}


def test_listing1_errors_name_each_field() -> None:
    result = run(DATA / "listing1.iface")
    assert result.has_errors and result.files == []
    errors = [d for d in result.diagnostics if d.severity == 1]
    named = {(d.code, d.message.split("'")[1], d.message.split("'")[3]) for d in errors
             if d.code == "px4-unsupported-type"}
    assert named == {("px4-unsupported-type", "str", "message1"), ("px4-unsupported-type", "str", "message2")}
    assert ("px4-param-type", "param1") in codes_by_name(result)
    services = sorted(d.message.split("'")[1] for d in result.diagnostics if d.code == "px4-no-services")
    assert services == ["action1", "action2", "diagnostics", "service1", "service2"]
    assert all("PX4 has no" in d.message for d in result.diagnostics if d.code == "px4-no-services")


def test_unsupported_constructs_are_errors_at_the_field() -> None:
    result = run(DATA / "unsupported.iface")
    assert result.files == []
    found = codes_by_name(result)
    assert {("px4-timestamp-type", "timestamp"), ("px4-unsupported-type", "name"),
            ("px4-variable-array", "samples"), ("px4-variable-array", "bounded"),
            ("px4-unsupported-type", "table"), ("px4-unsupported-type", "ids"),
            ("px4-unsupported-type", "choice"), ("px4-default", "count"), ("px4-unsupported-type", "blob"),
            ("px4-param-type", "label"), ("px4-param-type", "counter"),
            ("px4-param-name-too-long", "a_parameter_with_a_long_name")} <= found
    assert any(d.code == "px4-topic-invalid" and "~/private" in d.message for d in result.diagnostics)
    text = (DATA / "unsupported.iface").read_text()
    for d in result.diagnostics:
        assert d.code in CODES
        if d.code == "px4-variable-array":
            name = d.message.split("'")[1]
            line = d.location()[0]
            assert name in text.splitlines()[line - 1], "the diagnostic is located at the field"


def test_timestamp_added_with_information() -> None:
    result = ok(DATA / "flight_arm.iface")
    added = sorted(d.message.split("'")[1] for d in result.diagnostics if d.code == "px4-timestamp-added")
    assert added == ["ArmSetpoint", "JointState"]
    assert all(d.severity == 3 for d in result.diagnostics if d.code == "px4-timestamp-added")


# ---- injection --------------------------------------------------------------------------


def test_injection_docs_stay_comments(tmp_path: Path) -> None:
    result = ok(DATA / "injection_docs.iface")
    specs = messages(result)
    assert list(zip(specs["Probe"].types, specs["Probe"].names)) == [
        ("uint64", "timestamp"), ("float32", "value"), ("int32", "count")]
    assert specs["Probe"].constants == []
    doc = (DATA / "injection_docs.iface").read_text().split("*/\ncomponent")[0]
    expected = "\n".join(line.strip().removeprefix("/**").removeprefix("*").strip().rstrip("\\").rstrip()
                         for line in doc.splitlines()).strip()
    assert check_header(result, tmp_path) == expected
    yaml_doc = yaml.safe_load(files(result)["src/modules/inject/module.yaml"])
    assert yaml_doc["parameters"][0]["definitions"]["INJ_GAIN"]["description"]["short"] == \
        'Gain "quoted" # hash <b> ../x second'
    for path, text in files(result).items():
        if path.endswith(".hpp"):
            for line in text.splitlines():
                assert not line.rstrip().endswith("\\"), "a comment continued onto the next line"


def test_injection_strings_are_refused() -> None:
    result = run(DATA / "injection_strings.iface")
    assert result.files == []
    found = codes_by_name(result)
    assert {("px4-unsupported-type", "note"), ("px4-default", "note"), ("px4-unsupported-type", "GREETING"),
            ("px4-param-type", "mode")} <= found


def test_cli_generate_fails_for_listing1(tmp_path: Path) -> None:
    proc = subprocess.run([sys.executable, "-m", "iface", "generate", "--target", "px4", "-o", str(tmp_path),
                           str(DATA / "listing1.iface")], capture_output=True, text=True)
    assert proc.returncode == 1
    assert "px4-unsupported-type" in proc.stdout + proc.stderr


# ---- text: string<=N is char[N] ----------------------------------------------------------


TEXT = """component texts
message LogLine {
  u64 timestamp,
  string<=127 text,
  u8 severity
}
publishes LogLine on "/log_line"
"""


def test_a_bounded_string_is_a_char_array(tmp_path: Path) -> None:
    path = tmp_path / "texts.iface"
    path.write_text(TEXT)
    spec = messages(ok(path))["LogLine"]
    assert list(zip(spec.types, spec.names)) == [("uint64", "timestamp"), ("char[127]", "text"),
                                                 ("uint8", "severity")]


@pytest.mark.parametrize(("field", "reason"), [
    ("string note", "uORB has no unbounded strings: write string<=N, which becomes char[N]"),
    ("wstring<=10 wide", "uORB has no wide strings"),
    ("string<=8[4] tags", "uORB has no arrays of arrays"),
])
def test_text_uorb_cannot_hold_is_an_error_naming_the_field(tmp_path: Path, field: str, reason: str) -> None:
    path = tmp_path / "texts.iface"
    path.write_text(TEXT.replace("u8 severity", f"u8 severity,\n  {field}"))
    result = run(path)
    assert result.files == []
    name = field.split()[-1]
    found = [d for d in result.diagnostics if d.code == "px4-unsupported-type"]
    assert len(found) == 1 and f"field '{name}'" in found[0].message and reason in found[0].message


# ---- topics of messages PX4 already has, through the uXRCE-DDS bridge ------------------------

BRIDGE = """component att
external px4_msgs
subscribes px4_msgs.VehicleAttitude on "/fmu/out/vehicle_attitude"
subscribes px4_msgs.VehicleCommand on "/px4_1/fmu/in/vehicle_command"
publishes px4_msgs.VehicleGlobalPosition on "/fmu/out/estimator_global_position"
subscribes px4_msgs.SensorGps on "/gps"
subscribes px4_msgs.VehicleLocalPosition on "vehicle_local_position"
"""


def compile_px4(tmp_path: Path, text: str, name: str = "att.iface") -> tuple[Result, str]:
    path = tmp_path / name
    path.write_text(text)
    return run(path), text


def test_bridge_names_map_to_their_uorb_topic(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, BRIDGE)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    header = files(result)["src/modules/att/Att.hpp"]
    orb_ids = sorted(re.findall(r"ORB_ID\((\w+)\)", header))
    assert orb_ids == ["estimator_global_position", "parameter_update", "sensor_gps", "vehicle_attitude",
                       "vehicle_command", "vehicle_local_position"]
    assert "fmu" not in header
    assert "uORB::Publication<vehicle_global_position_s> _estimator_global_position_pub" in header


def test_other_names_of_px4_msgs_types_warn_that_the_topic_is_assumed(tmp_path: Path) -> None:
    result, text = compile_px4(tmp_path, BRIDGE)
    assumed = [d for d in result.diagnostics if d.code == "px4-topic-assumed"]
    # "/gps" is assumed to be sensor_gps; "vehicle_local_position" already says the assumed name
    assert [text[d.span.start:d.span.end] for d in assumed] == ['"/gps"']
    assert "'sensor_gps'" in assumed[0].message and "/fmu/out/<topic>" in assumed[0].message
    assert CODES["px4-topic-assumed"][0] == 2


def test_a_bridge_name_of_the_components_own_message(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, "component arm\nmessage ArmStatus { u64 timestamp, u8 mode }\n"
                            'publishes ArmStatus on "/fmu/out/arm_status"\n', "arm.iface")
    out = files(ok_result(result))
    assert topics_of(out["msg/ArmStatus.msg"], "ArmStatus") == ["arm_status"]
    assert "ORB_ID(arm_status)" in out["src/modules/arm/Arm.hpp"]


def test_a_bridge_name_with_a_bad_topic_is_invalid(tmp_path: Path) -> None:
    result, text = compile_px4(tmp_path, 'component att\nexternal px4_msgs\n'
                               'subscribes px4_msgs.VehicleAttitude on "/fmu/out/VehicleAttitude"\n')
    (d,) = [d for d in result.diagnostics if d.code == "px4-topic-invalid"]
    assert text[d.span.start:d.span.end] == '"/fmu/out/VehicleAttitude"'


def test_bridge_header_compiles(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, BRIDGE + "message Marker { u64 timestamp }\n"
                            'publishes Marker on "/fmu/in/marker"\n')
    # PX4's own topic headers, as PX4 generates them for the messages the module uses (stubs)
    px4_topics = {"vehicle_attitude": ["vehicle_attitude"], "vehicle_command": ["vehicle_command"],
                  "vehicle_global_position": ["estimator_global_position"], "sensor_gps": ["sensor_gps"],
                  "vehicle_local_position": ["vehicle_local_position"]}
    topics = tmp_path / "inc" / "uORB" / "topics"
    topics.mkdir(parents=True)
    for stem, names in px4_topics.items():
        (topics / f"{stem}.h").write_text("#pragma once\n#include <uORB/uORB.h>\n"
                                          f"struct {stem}_s {{ unsigned long long timestamp; }};\n"
                                          + "".join(f"extern const orb_metadata __orb_{t};\n" for t in names))
    check_header(ok_result(result), tmp_path)


def ok_result(result: Result) -> Result:
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return result


# ---- message libraries ------------------------------------------------------------------------


def test_a_message_library_gets_no_module(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, "message PositionPoint { u64 timestamp, float32 x }\n"
                            "message VehicleThing { u64 timestamp, PositionPoint p }\n", "px4_msgs.iface")
    assert sorted(files(ok_result(result))) == ["msg/PositionPoint.msg", "msg/VehicleThing.msg"]
    assert [d.code for d in result.diagnostics] == ["px4-message-library"]


def test_a_parameter_alone_makes_a_module(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, "component tuner\nconfiguration c { float gain = 1 }\n", "tuner.iface")
    assert sorted(files(ok_result(result))) == [f"src/modules/tuner/{name}" for name in (
        "CMakeLists.txt", "Kconfig", "Tuner.cpp", "Tuner.hpp", "Tuner_user.cpp", "module.yaml")]


def test_imported_px4_messages_generate_back_without_a_module(tmp_path: Path) -> None:
    from tests.conftest import run_main

    src = ROOT / "tests" / "importers" / "data" / "px4" / "msg"
    assert run_main("import", "--from", "px4", str(src), "--out", str(tmp_path / "iface"), "-q").returncode == 0
    (imported,) = (tmp_path / "iface").glob("*.iface")
    out = tmp_path / "out"
    proc = run_main("generate", str(imported), "-t", "px4", "-o", str(out), "-q")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    written = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert written and all(p.startswith("msg/") for p in written)


# ---- the module that builds in PX4's tree ----------------------------------------------------


def test_the_module_follows_px4s_module_template() -> None:
    """CMakeLists.txt, Kconfig and the frame .cpp as PX4's template_module and work_item example write them."""
    out = files(ok(DATA / "flight_arm.iface"))
    folder = "src/modules/flight_arm"
    cmake = out[f"{folder}/CMakeLists.txt"]
    for line in ("px4_add_module(", "MODULE modules__flight_arm", "MAIN flight_arm", "FlightArm.cpp",
                 "FlightArm_user.cpp", "MODULE_CONFIG", "module.yaml", "DEPENDS", "px4_work_queue"):
        assert line in cmake, line
    kconfig = out[f"{folder}/Kconfig"]
    assert "menuconfig MODULES_FLIGHT_ARM\n\tbool \"flight_arm\"\n\tdefault n\n\t---help---\n" in kconfig
    cpp = out[f"{folder}/FlightArm.cpp"]
    assert "ScheduledWorkItem(MODULE_NAME, px4::wq_configurations::lp_default)" in cpp
    assert "if (!_arm_setpoint_sub.registerCallback()) {" in cpp  # the px4.callback subscription schedules Run()
    assert "ScheduleOnInterval" not in cpp
    assert "while (_arm_setpoint_sub.update(&arm_setpoint)) {\n\t\ton_arm_setpoint(arm_setpoint);" in cpp
    assert "updateParams(); // the members of DEFINE_PARAMETERS\n\t\ton_parameters_updated();" in cpp
    assert 'extern "C" __EXPORT int flight_arm_main(int argc, char *argv[])' in cpp
    header = out[f"{folder}/FlightArm.hpp"]
    for hook in ("void on_start();", "void on_parameters_updated();", "void on_cycle();",
                 "void on_arm_setpoint(const arm_setpoint_s &msg);"):
        assert hook in header, hook
    user = next(f for f in ok(DATA / "flight_arm.iface").files if f.path == f"{folder}/FlightArm_user.cpp")
    assert user.once and "void FlightArm::on_arm_setpoint(const arm_setpoint_s &msg)" in user.text


def test_the_user_file_is_written_once(tmp_path: Path) -> None:
    from iface.emit.write import write_files

    result = ok(DATA / "flight_arm.iface")
    write_files(result.files, tmp_path)
    user = tmp_path / "src/modules/flight_arm/FlightArm_user.cpp"
    user.write_text(user.read_text() + "// mine\n")
    again = write_files(result.files, tmp_path, force=True)
    assert again.kept == ["src/modules/flight_arm/FlightArm_user.cpp"]
    assert user.read_text().endswith("// mine\n")


def test_without_a_callback_subscription_run_is_scheduled_on_an_interval(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, 'component pinger (px4.work_queue = "hp_default", px4.interval_us = 2000)\n'
                            "message Ping { u64 timestamp }\npublishes Ping on \"/ping\"\n")
    cpp = files(ok_result(result))["src/modules/pinger/Pinger.cpp"]
    assert "px4::wq_configurations::hp_default" in cpp and "ScheduleOnInterval(2000);" in cpp


def test_a_work_queue_px4_does_not_have_is_an_error(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, 'component pinger (px4.work_queue = "fast_lane")\n'
                               "message Ping { u64 timestamp }\npublishes Ping on \"/ping\"\n")
    (d,) = [d for d in result.diagnostics if d.code == "px4-annotation"]
    assert "fast_lane" in d.message and "lp_default" in d.message and not result.files


def test_a_long_description_is_cut_for_short_and_kept_whole_in_long(tmp_path: Path) -> None:
    doc = ("The largest speed any joint of the arm may reach while it follows a trajectory planned by the "
           "motion planner, in either direction")
    result, _ = compile_px4(tmp_path, f"component tuner\nconfiguration c {{\n    /** {doc}. Tune it with care. */\n"
                            "    float gain = 1\n}\n", "tuner.iface")
    doc_yaml = yaml.safe_load(files(ok_result(result))["src/modules/tuner/module.yaml"])
    (entry,) = doc_yaml["parameters"][0]["definitions"].values()
    short, long = entry["description"]["short"], entry["description"]["long"]
    assert len(short) <= 70 and short.endswith("...") and doc.startswith(short[:-3])
    assert long == f"{doc}. Tune it with care."
    jsonschema.validate(doc_yaml, json.loads((DATA / "module_schema.json").read_text()))


# ---- PX4's rules for message definitions (Tools/msg, uORB) ----------------------------------------


def _located(result: Result, code: str) -> list[int]:
    return sorted(d.location()[0] for d in result.diagnostics if d.code == code)


def test_orb_queue_length_is_a_uint8_power_of_two(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, "component q\n"
                            "message A { u64 timestamp, const u8 ORB_QUEUE_LENGTH = 4 }\n"
                            "message B { u64 timestamp, const u8 ORB_QUEUE_LENGTH = 5 }\n"
                            "message C { u64 timestamp, const u8 ORB_QUEUE_LENGTH = 200 }\n"
                            'publishes A on "/a"\npublishes B on "/b"\npublishes C on "/c"\n')
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    assert _located(result, "px4-queue-length-rounded") == [3, 4]
    rounded = {d.location()[0]: d.message for d in result.diagnostics if d.code == "px4-queue-length-rounded"}
    assert "holds 8" in rounded[3] and "holds 128" in rounded[4]
    specs = messages(result)
    assert [(c.type, c.name, c.val) for c in specs["A"].constants] == [("uint8", "ORB_QUEUE_LENGTH", 4)]
    other, _ = compile_px4(tmp_path, "component q\nmessage A { u64 timestamp, const u32 ORB_QUEUE_LENGTH = 2 }\n"
                           "message B { u64 timestamp, const u16 ORB_QUEUE_LENGTH = 300 }\n"
                           'publishes A on "/a"\npublishes B on "/b"\n')
    assert not other.has_errors, [d.format() for d in other.diagnostics]
    assert _located(other, "px4-queue-length") == [2, 3]
    assert _located(other, "px4-queue-length-rounded") == [3]
    assert "holds 64" in next(d.message for d in other.diagnostics if d.code == "px4-queue-length-rounded")
    specs = messages(other)
    assert [(c.type, c.name, c.val) for c in specs["A"].constants] == [("uint32", "ORB_QUEUE_LENGTH", 2)]


def test_a_float_constant_with_a_fraction_is_kept_with_a_warning(tmp_path: Path) -> None:
    result, _ = compile_px4(tmp_path, "component f\nmessage A {\n    u64 timestamp,\n    const float32 HALF = 0.5,\n"
                            "    const float32 TWO = 2.0\n}\npublishes A on \"/a\"\n")
    assert _located(result, "px4-constant-fraction") == [4] and not result.has_errors
    assert [(c.name, c.val) for c in messages(result)["A"].constants] == [("HALF", 0.5), ("TWO", 2.0)]
    assert "int(value)" in next(d.message for d in result.diagnostics if d.code == "px4-constant-fraction")


def test_topic_names_fit_uorbs_node_path(tmp_path: Path) -> None:
    fits, too_long = "t" * 57, "t" * 58
    ok_result, _ = compile_px4(tmp_path, f'component t\nmessage A {{ u64 timestamp }}\npublishes A on "/{fits}"\n')
    assert not ok_result.has_errors, [d.format() for d in ok_result.diagnostics]
    assert topics_of(files(ok_result)["msg/A.msg"], "A") == [fits]
    result, _ = compile_px4(tmp_path, f'component t\nmessage A {{ u64 timestamp }}\npublishes A on "/{too_long}"\n')
    assert _located(result, "px4-topic-too-long") == [3] and not result.has_errors
    assert topics_of(files(result)["msg/A.msg"], "A") == [too_long]
    named, _ = compile_px4(tmp_path, "component t\n/** used by nothing: its topic is its own name */\n"
                           f"message {'Abcdefgh' * 8} {{ u64 timestamp }}\nmessage B {{ u64 timestamp }}\n"
                           'publishes B on "/b"\n')
    assert _located(named, "px4-topic-too-long") == [3]


def test_generated_messages_follow_pxs_generator_rules() -> None:
    """timestamp first and uint64, lower-case field names, # TOPICS as PX4's get_topics reads it, int constants."""
    for case in CASES:
        out = files(ok(DATA / f"{case}.iface"))
        for path, text in out.items():
            if not path.startswith("msg/"):
                continue
            spec = genmsg.msg_loader.load_msg_from_string(genmsg.MsgContext.create_default(), text,
                                                          f"px4/{Path(path).stem}")
            assert (spec.types[0], spec.names[0]) == ("uint64", "timestamp"), path
            assert all(n == n.lower() and not n.startswith("_padding") for n in spec.names), path
            assert all(float(c.val) == int(float(c.val)) for c in spec.constants if c.type != "bool"), path
            for line in text.splitlines():
                if line.startswith("# TOPICS"):
                    assert line.startswith("# TOPICS ") and "  " not in line and line == line.rstrip(), path
                    assert all(re.fullmatch(r"[a-z][a-z0-9_]*", t) and len(t) <= 57 for t in line.split()[2:])
