"""The ardupilot target: AP_DDS IDL (rosbags), the AP_Param table (g++), index stability, goldens."""

from __future__ import annotations

import re
import shutil
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from rosbags.typesys import get_types_from_idl

from iface.emit import generate, get_target
from iface.emit.ardupilot import CODES
from iface.emit.base import Result
from iface.semantics.compile import Workspace

from ..conftest import generated_in_two_processes
from .golden_util import check_golden
from .idl_oracle import FASTDDSGEN, NO_FASTDDSGEN, fastddsgen

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).parent / "data" / "ardupilot"
ROBOT_ARM = ROOT / "examples" / "robot_arm.iface"
SHARED = DATA / "shared"
IDLC = shutil.which("idlc")
IDL_CASES = ["listing1", "rover_v1", "injection_docs", "dds"]
NO_IDLC = "idlc (Cyclone DDS's IDL compiler, Debian package cyclonedds-tools) is not installed: scripts/test.sh " \
          "installs it where it runs as root"
CASES = ["listing1", "rover_v1", "injection_docs", "dds", "metadata"]
ENTRY = re.compile(r'AP_GROUPINFO(?:_FLAGS)?\("([A-Z0-9_]+)", (\d+), (\w+), (\w+), ([^,)]+)(?:, (\w+))?\),')


def run(path: Path) -> Result:
    return generate(Workspace().compile_path(str(path)), "ardupilot")


def ok(path: Path) -> Result:
    result = run(path)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    return result


def files(result: Result) -> dict[str, str]:
    return {f.path: f.text for f in result.files}


def idl_types(result: Result) -> dict[str, tuple[list, list]]:
    """Every generated .idl parsed by rosbags (which reads preprocessed IDL: includes are checked apart)."""
    out: dict[str, tuple[list, list]] = {}
    generated = files(result)
    for path, text in generated.items():
        if path.endswith(".idl"):
            for inc in re.findall(r'^#include "([^"]+)"$', text, re.M):
                package = inc.split("/")[0]
                assert f"libraries/AP_DDS/Idl/{inc}" in generated or package != path.split("/")[3], inc
            assert_guarded(path, text)
            types = get_types_from_idl(re.sub(r"^\s*#(include|ifndef|define|endif)\b.*$", "", text, flags=re.M))
            assert types, f"{path}: rosbags found no type"
            out.update(types)
    return out


def assert_guarded(path: str, text: str) -> None:
    """The file's declarations sit in ``#ifndef <pkg>_<kind>_<Name>_defined`` guards, as ArduPilot writes them."""
    _, _, _, pkg, kind, file = path.split("/")
    lines = [line.strip() for line in text.splitlines()]
    opened = [line.split()[1] for line in lines if line.startswith("#ifndef")]
    defined = [line.split()[1] for line in lines if line.startswith("#define")]
    assert opened == defined and len(opened) == sum(line == "#endif" for line in lines), path
    assert opened[0] == f"{pkg}_{kind}_{file.removesuffix('.idl')}_defined", path
    typedefs = re.findall(r"^    typedef \S+ (\w+)\[\d+\];$", text, re.M)
    assert opened[1:] == [f"{pkg}_{kind}_{name}_defined" for name in typedefs], path


def entries(result: Result) -> dict[str, int]:
    """AP_Param name → index, from the generated var_info table."""
    cpp = next(t for p, t in files(result).items() if p.endswith(".cpp"))
    return {m.group(1): int(m.group(2)) for m in ENTRY.finditer(cpp)}


def compile_params(result: Result, tmp: Path) -> None:
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    out = files(result)
    for path, text in out.items():
        if path.endswith(("_Params.h", ".cpp")):
            (tmp / Path(path).name).write_text(text)
    cpp = next(p for p in out if p.endswith(".cpp"))
    proc = subprocess.run(["g++", "-std=gnu++17", "-fsyntax-only", "-Wall", "-Wextra", "-Werror",
                           "-Wno-pedantic", "-I", str(DATA / "stubs"), "-I", str(tmp), str(tmp / Path(cpp).name)],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_found_through_entry_point() -> None:
    target = get_target("ardupilot")
    assert target is not None and target.name == "ardupilot"


@pytest.mark.parametrize("case", CASES)
def test_golden(case: str) -> None:
    check_golden("ardupilot", case, ok(DATA / f"{case}.iface").files)


def test_deterministic_across_hash_seeds() -> None:
    one, two = generated_in_two_processes("ardupilot", [*(DATA / f"{case}.iface" for case in CASES), ROBOT_ARM])
    assert one == two and one.count("\n") == len(CASES) + 1


# ---- IDL ------------------------------------------------------------------------------


def test_listing1_idl_parses_with_rosbags(tmp_path: Path) -> None:
    result = ok(DATA / "listing1.iface")
    types = idl_types(result)
    assert {"listing1/msg/Message1", "listing1/msg/Message2", "listing1/srv/Service1_Request",
            "listing1/srv/Service1_Response", "listing1/srv/Diagnostics_Request"} <= set(types)
    consts, fields = types["listing1/srv/Service1_Request"]
    assert [name for name, _ in fields] == ["str", "i"]
    assert not any("/action/" in p for p in files(result)), "AP_DDS has no actions"
    actions = [d for d in result.diagnostics if d.code == "ap-no-actions"]
    assert sorted(d.message.split("'")[1] for d in actions) == ["Action1", "Action2"]
    compile_params(result, tmp_path)


def test_idl_lives_in_the_ap_dds_tree() -> None:
    paths = files(ok(DATA / "rover_v1.iface"))
    assert "libraries/AP_DDS/Idl/rover_v1/msg/Drive.idl" in paths
    assert "libraries/AP_Rover/AP_Rover_Params.h" in paths


def test_robot_arm(tmp_path: Path) -> None:
    result = ok(ROBOT_ARM)
    assert idl_types(result)
    compile_params(result, tmp_path)


# ---- a real IDL compiler ------------------------------------------------------------------


def generate_cli(target: str, out: Path, *sources: Path) -> None:
    """``iface-lsp generate -t TARGET -o OUT SOURCE`` for each source, as a user runs it."""
    for source in sources:
        proc = subprocess.run([sys.executable, "-m", "iface", "generate", "-t", target, "-o", str(out), str(source)],
                              capture_output=True, text=True, timeout=120)
        assert proc.returncode == 0, proc.stdout + proc.stderr


def idlc(root: Path, files: list[str], tmp: Path) -> subprocess.CompletedProcess[str]:
    """idlc over one top-level IDL file that includes ``files`` (paths under ``root``), writing C into ``tmp``."""
    top = tmp / "together.idl"
    top.write_text("".join(f'#include "{f}"\n' for f in files))
    out = tmp / "c"
    out.mkdir()
    return subprocess.run([str(IDLC), "-I", str(root), "-o", str(out), str(top)], capture_output=True, text=True,
                          timeout=120)


@pytest.mark.skipif(IDLC is None, reason=NO_IDLC)
def test_two_components_including_one_dependency_compile_together(tmp_path: Path) -> None:
    out = tmp_path / "out"
    generate_cli("ardupilot", out, SHARED / "common.iface", SHARED / "comp_a.iface", SHARED / "comp_b.iface")
    root = out / "libraries" / "AP_DDS" / "Idl"
    parts = sorted(p.relative_to(root).as_posix() for p in root.rglob("*.idl") if not p.parts[-3] == "common_msgs")
    assert parts == ["comp_a/msg/Report.idl", "comp_b/msg/Target.idl"]
    proc = idlc(root, parts, tmp_path)
    assert proc.returncode == 0, proc.stderr
    header = (tmp_path / "c" / "together.h").read_text()
    assert '#include "comp_a/msg/Report.h"' in header and '#include "comp_b/msg/Target.h"' in header
    # idlc writes C for the top-level file only; each file on its own declares its struct
    for part, struct in (("common_msgs/msg/Stamp.idl", "common_msgs_msg_Stamp"),
                         ("common_msgs/msg/Position.idl", "common_msgs_msg_Position"),
                         ("comp_a/msg/Report.idl", "comp_a_msg_Report")):
        alone = tmp_path / struct
        alone.mkdir()
        proc = subprocess.run([str(IDLC), "-I", str(root), "-o", str(alone), str(root / part)], capture_output=True,
                              text=True, timeout=120)
        assert proc.returncode == 0, proc.stderr
        assert f"typedef struct {struct}\n" in (alone / Path(part).with_suffix(".h").name).read_text()


@pytest.mark.skipif(IDLC is None, reason=NO_IDLC)
def test_without_the_guards_the_same_files_do_not_compile_together(tmp_path: Path) -> None:
    """The control: the idl target writes rosidl's IDL, which has no guards, and idlc refuses the second Stamp."""
    out = tmp_path / "out"
    generate_cli("idl", out, SHARED / "common.iface", SHARED / "comp_a.iface", SHARED / "comp_b.iface")
    proc = idlc(out, ["comp_a/msg/Report.idl", "comp_b/msg/Target.idl"], tmp_path)
    assert proc.returncode != 0 and "collides" in proc.stderr, proc.stderr


@pytest.mark.skipif(IDLC is None, reason=NO_IDLC)
@pytest.mark.parametrize("case", IDL_CASES)
def test_every_case_compiles_with_idlc(tmp_path: Path, case: str) -> None:
    root, parts = write_idl(case, tmp_path)
    proc = idlc(root, parts, tmp_path)
    assert proc.returncode == 0, proc.stderr


def write_idl(case: str, tmp: Path) -> tuple[Path, list[str]]:
    """The case's IDL files under ``tmp/out`` (the tree's libraries/AP_DDS/Idl), and their paths there."""
    root = tmp / "out"
    for f in ok(DATA / f"{case}.iface").files:
        if f.path.endswith(".idl"):
            path = root / f.path.removeprefix("libraries/AP_DDS/Idl/")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(f.text)
    parts = sorted(p.relative_to(root).as_posix() for p in root.rglob("*.idl"))
    assert parts
    return root, parts


#: Debian's Fast-DDS-Gen 2.3.0 does not lex the \" escape in a string (IDL 4.2 7.2.6.3 allows it, rosidl writes
#: it, and ArduPilot's own Idl/sensor_msgs/msg/Imu.idl has it), which injection_docs' doc comments hold.
FASTDDSGEN_CASES = [c for c in IDL_CASES if c != "injection_docs"]


@pytest.mark.skipif(FASTDDSGEN is None, reason=NO_FASTDDSGEN)
@pytest.mark.parametrize("case", FASTDDSGEN_CASES)
def test_every_case_builds_with_fastddsgen_as_ardupilot_builds_it(tmp_path: Path, case: str) -> None:
    root, parts = write_idl(case, tmp_path)
    proc = fastddsgen(root, [root / p for p in parts], tmp_path / "gen")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    for part in parts:
        assert (tmp_path / "gen" / Path(part).with_suffix(".h").name).is_file(), part


@pytest.mark.skipif(FASTDDSGEN is None, reason=NO_FASTDDSGEN)
def test_two_components_including_one_dependency_build_together_with_fastddsgen(tmp_path: Path) -> None:
    out = tmp_path / "out"
    generate_cli("ardupilot", out, SHARED / "common.iface", SHARED / "comp_a.iface", SHARED / "comp_b.iface")
    root = out / "libraries" / "AP_DDS" / "Idl"
    top = tmp_path / "together.idl"
    top.write_text('#include "comp_a/msg/Report.idl"\n#include "comp_b/msg/Target.idl"\n')
    proc = fastddsgen(root, [top], tmp_path / "gen")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    header = (tmp_path / "gen" / "together.h").read_text()
    assert '#include "comp_a/msg/Report.h"' in header and '#include "comp_b/msg/Target.h"' in header


# ---- AP_DDS topic and service tables, XRCE-DDS profiles ---------------------------------------

#: What dds.iface wires, as AP_DDS must see it: (index, writer, topic, type, durability, reliability, history, depth).
TOPICS = [
    ("PROBE_STATUS_PUB", True, "rt/probe/status", "dds::msg::dds_::Status_", "VOLATILE", "BEST_EFFORT", "KEEP_LAST", 5),
    ("PROBE_GOAL_PUB", True, "rt/probe/goal", "dds::msg::dds_::Goal_", "TRANSIENT_LOCAL", "RELIABLE", "KEEP_LAST",
     1),
    ("CMD_GOAL_SUB", False, "rt/cmd_goal", "dds::msg::dds_::Goal_", "VOLATILE", "RELIABLE", "KEEP_ALL", 10),
    ("PROBE_CMD_VEL_SUB", False, "rt/probe/cmd_vel", "geometry_msgs::msg::dds_::Twist_", "VOLATILE", "RELIABLE",
     "KEEP_LAST", 10),
]
#: (index, replier, ROS name, type) of each service entry; request/reply topics and types follow from them.
SERVICES = [
    ("PROBE_ARM", True, "probe/arm", "dds::srv::dds_::Arm_", "TRANSIENT_LOCAL", 5),
    ("DDS_PROBE_CALIBRATION_START", True, "dds_probe/calibration/start", "dds::srv::dds_::CalibrationStart_",
     "VOLATILE", 10),
    ("DDS_PROBE_CALIBRATION_STOP", True, "dds_probe/calibration/stop", "dds::srv::dds_::CalibrationStop_",
     "VOLATILE", 10),
    ("OTHER_ARM", False, "other/arm", "dds::srv::dds_::Arm_", "VOLATILE", 10),
    ("PROBE_HEALTH", True, "probe/health", "dds::srv::dds_::Health_", "VOLATILE", 10),
]


def dds_files(result: Result) -> tuple[str, str, str]:
    out = files(result)
    folder = "libraries/AP_DdsProbe"
    return (out[f"{folder}/AP_DDS_Topic_Table.h"], out[f"{folder}/AP_DDS_Service_Table.h"],
            out[f"{folder}/dds_xrce_profile.xml"])


def test_dds_tables_compile_and_hold_the_wiring(tmp_path: Path) -> None:
    """g++ builds both tables against AP_DDS_Client.h's structs and checks every entry at compile time."""
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    topics, services, _ = dds_files(ok(DATA / "dds.iface"))
    (tmp_path / "AP_DDS_Topic_Table.h").write_text(topics)
    (tmp_path / "AP_DDS_Service_Table.h").write_text(services)
    for header in re.findall(r'^#include "(\w+/msg/\w+\.h)"$', topics, re.M):
        (tmp_path / header).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / header).write_text("#pragma once\n")  # the C types microxrceddsgen makes from the IDL
    checks = ["constexpr bool same(const char* a, const char* b) "
              "{ return *a == *b && (*a == 0 || same(a + 1, b + 1)); }"]
    for i, (index, writer, name, type_name, durability, reliability, history, depth) in enumerate(TOPICS):
        t = f"AP_DDS_Client::topics[{i}]"
        rw = "DataWriter" if writer else "DataReader"
        checks += [f"static_assert({t}.topic_id == {i} && {t}.dw_id.id == {i} && "
                   f"{t}.dr_id.type == UXR_DATAREADER_ID);",
                   f"static_assert(to_underlying(TopicIndex::{index}) == {i});",
                   f"static_assert({t}.topic_rw == AP_DDS_Client::Topic_rw::{rw});",
                   f'static_assert(same({t}.topic_name, "{name}") && same({t}.type_name, "{type_name}"));',
                   f"static_assert({t}.qos.durability == UXR_DURABILITY_{durability} && "
                   f"{t}.qos.reliability == UXR_RELIABILITY_{reliability} && "
                   f"{t}.qos.history == UXR_HISTORY_{history} && {t}.qos.depth == {depth});"]
    for i, (index, replier, name, type_name, durability, depth) in enumerate(SERVICES):
        s = f"AP_DDS_Client::services[{i}]"
        rr = "Replier" if replier else "Requester"
        checks += [f"static_assert(to_underlying(ServiceIndex::{index}) == {i} && {s}.req_id == {i});",
                   f"static_assert({s}.service_rr == AP_DDS_Client::Service_rr::{rr});",
                   f'static_assert(same({s}.service_name, "rs/{name}Service") && '
                   f'same({s}.request_topic_name, "rq/{name}Request") && '
                   f'same({s}.reply_topic_name, "rr/{name}Reply"));',
                   f'static_assert(same({s}.request_type, "{type_name}Request_") && '
                   f'same({s}.reply_type, "{type_name}Response_"));',
                   f"static_assert({s}.qos.durability == UXR_DURABILITY_{durability} && {s}.qos.depth == {depth});"]
    checks += [f"static_assert(sizeof(AP_DDS_Client::topics) / sizeof(AP_DDS_Client::topics[0]) == {len(TOPICS)});",
               f"static_assert(sizeof(AP_DDS_Client::services) / sizeof(AP_DDS_Client::services[0]) == "
               f"{len(SERVICES)});"]
    unit = tmp_path / "tables.cpp"
    unit.write_text('#include "AP_DDS_Client.h"\n#include "AP_DDS_Topic_Table.h"\n#include "AP_DDS_Service_Table.h"\n'
                    + "\n".join(checks) + "\n")
    proc = subprocess.run(["g++", "-std=c++20", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", "-I",
                           str(DATA / "stubs"), "-I", str(tmp_path), str(unit)], capture_output=True, text=True,
                           timeout=120)
    assert proc.returncode == 0, proc.stderr


def test_each_dds_entry_can_be_left_out_of_the_build(tmp_path: Path) -> None:
    """As AP_DDS_config.h lets ArduPilot's own entries be: the rest keep dense indices."""
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    topics, services, _ = dds_files(ok(DATA / "dds.iface"))
    (tmp_path / "AP_DDS_Topic_Table.h").write_text(topics)
    (tmp_path / "AP_DDS_Service_Table.h").write_text(services)
    for header in re.findall(r'^#include "(\w+/msg/\w+\.h)"$', topics, re.M):
        (tmp_path / header).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / header).write_text("#pragma once\n")
    unit = tmp_path / "tables.cpp"
    unit.write_text('#include "AP_DDS_Client.h"\n#include "AP_DDS_Topic_Table.h"\n#include "AP_DDS_Service_Table.h"\n'
                    "constexpr bool same(const char* a, const char* b) "
                    "{ return *a == *b && (*a == 0 || same(a + 1, b + 1)); }\n"
                    f"static_assert(sizeof(AP_DDS_Client::topics) / sizeof(AP_DDS_Client::topics[0]) == "
                    f"{len(TOPICS) - 1});\n"
                    'static_assert(same(AP_DDS_Client::topics[0].topic_name, "rt/probe/goal"));\n'
                    "static_assert(AP_DDS_Client::topics[0].topic_id == 0);\n"
                    f"static_assert(sizeof(AP_DDS_Client::services) / sizeof(AP_DDS_Client::services[0]) == "
                    f"{len(SERVICES) - 1});\n"
                    'static_assert(same(AP_DDS_Client::services[3].service_name, "rs/probe/healthService"));\n')
    proc = subprocess.run(["g++", "-std=c++20", "-fsyntax-only", "-Wall", "-Wextra", "-Werror",
                           "-DAP_DDS_PROBE_STATUS_PUB_ENABLED=0", "-DAP_DDS_OTHER_ARM_CLIENT_ENABLED=0", "-I",
                           str(DATA / "stubs"), "-I", str(tmp_path), str(unit)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr


def test_dds_profiles_parse_and_match_the_tables() -> None:
    _, _, xml = dds_files(ok(DATA / "dds.iface"))
    root = ET.fromstring(xml)
    assert root.tag == "profiles"
    labels = [e.get("profile_name") for e in root]
    assert len(labels) == len(set(labels))
    topics = root.findall("topic")
    endpoints = [e for e in root if e.tag in ("data_writer", "data_reader")]
    assert len(topics) == len(endpoints) == len(TOPICS)
    for topic, endpoint, (_, writer, name, type_name, durability, reliability, history, depth) in zip(
            topics, endpoints, TOPICS):
        assert endpoint.tag == ("data_writer" if writer else "data_reader")
        assert endpoint.get("profile_name") == topic.get("profile_name", "").removesuffix("__t") + (
            "__dw" if writer else "__dr")
        for where in (topic, endpoint.find("topic")):
            assert where is not None
            assert (where.findtext("name"), where.findtext("dataType")) == (name, type_name)
            assert (where.findtext("historyQos/kind"), where.findtext("historyQos/depth")) == (history, str(depth))
        assert endpoint.findtext("qos/reliability/kind") == reliability
        assert endpoint.findtext("qos/durability/kind") == durability
        assert endpoint.findtext("topic/kind") == "NO_KEY"
    services = [e for e in root if e.tag in ("replier", "requester")]
    assert [(e.tag, e.get("service_name"), e.get("request_type"), e.get("reply_type"), e.findtext("request_topic_name"),
             e.findtext("reply_topic_name")) for e in services] == [
        ("replier" if replier else "requester", f"rs/{name}Service", f"{type_name}Request_", f"{type_name}Response_",
         f"rq/{name}Request", f"rr/{name}Reply") for _, replier, name, type_name, _, _ in SERVICES]


@pytest.mark.parametrize("case", CASES)
def test_every_case_tables_compile_and_profiles_parse(tmp_path: Path, case: str) -> None:
    """Whatever a case wires: its tables build against AP_DDS_Client.h's structs, its XML is well-formed."""
    if shutil.which("g++") is None:
        pytest.skip("g++ is not installed")
    out = files(ok(DATA / f"{case}.iface"))
    tables = {Path(p).name: t for p, t in out.items() if Path(p).name.startswith("AP_DDS_")}
    profiles = [t for p, t in out.items() if p.endswith("/dds_xrce_profile.xml")]
    assert bool(tables) == bool(profiles)
    if not tables:
        return
    root = ET.fromstring(profiles[0])
    assert len(root.findall("topic")) == tables.get("AP_DDS_Topic_Table.h", "").count("        .topic_id = ")
    assert len([e for e in root if e.tag in ("replier", "requester")]) == tables.get(
        "AP_DDS_Service_Table.h", "").count("        .req_id = ")
    for name, text in tables.items():
        (tmp_path / name).write_text(text)
        for header in re.findall(r'^#include "(\w+/msg/\w+\.h)"$', text, re.M):
            (tmp_path / header).parent.mkdir(parents=True, exist_ok=True)
            (tmp_path / header).write_text("#pragma once\n")
    unit = tmp_path / "tables.cpp"
    unit.write_text('#include "AP_DDS_Client.h"\n' + "".join(f'#include "{n}"\n' for n in sorted(tables)))
    proc = subprocess.run(["g++", "-std=c++20", "-fsyntax-only", "-Wall", "-Wextra", "-Werror", "-I",
                           str(DATA / "stubs"), "-I", str(tmp_path), str(unit)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr


def test_a_qos_policy_ap_dds_cannot_carry_is_a_warning_at_the_annotation() -> None:
    result = ok(DATA / "dds.iface")
    (d,) = [d for d in result.diagnostics if d.code == "ap-dds-qos-unsupported"]
    line, col = d.location()[:2]
    text = (DATA / "dds.iface").read_text().splitlines()[line - 1]
    assert text[col - 1:].startswith('qos.deadline = "100ms"') and "qos.deadline" in d.message


def test_no_wiring_no_dds_files() -> None:
    assert not any("AP_DDS_" in p or p.endswith(".xml") for p in files(ok(SHARED / "common.iface")))


# ---- AP_Param documentation, as ArduPilot's param_parse.py reads it ---------------------------

#: ArduPilot's known_param_fields and required_param_fields (Tools/autotest/param_metadata/param.py, d84f825a).
KNOWN_FIELDS = {"Description", "DisplayName", "Values", "Range", "Units", "Increment", "User", "RebootRequired",
                "Bitmask", "Volatile", "ReadOnly", "Calibration"}
REQUIRED_FIELDS = {"Description", "DisplayName", "User"}
UNITS = json.loads((ROOT / "server" / "iface" / "emit" / "ardupilot" / "units.json").read_text())["units"]
PAIRS = re.compile(r"^-?\d+:[^,]+(,-?\d+:[^,]+)*$")


def documented(cpp: str) -> dict[str, dict[str, str]]:
    """Each ``// @Param: NAME`` block's fields, read the way param_parse.py reads them."""
    out: dict[str, dict[str, str]] = {}
    for block in re.split(r"^    // @Param: ", cpp, flags=re.M)[1:]:
        name, _, rest = block.partition("\n")
        fields = dict(re.findall(r"^    // @(\w+): (.*)$", rest.split("AP_GROUPINFO")[0], re.M))
        out[name] = fields
    return out


@pytest.mark.parametrize("case", CASES)
def test_every_parameter_documented_as_param_parse_wants(case: str) -> None:
    cpp = next(t for p, t in files(ok(DATA / f"{case}.iface")).items() if p.endswith("_Params.cpp"))
    docs = documented(cpp)
    assert docs and set(docs) == set(entries(ok(DATA / f"{case}.iface")))
    for name, fields in docs.items():
        assert REQUIRED_FIELDS <= set(fields) <= KNOWN_FIELDS, name
        assert fields["User"] in ("Standard", "Advanced"), name
        assert "Units" not in fields or fields["Units"] in UNITS, name
        for key in ("Values", "Bitmask"):
            assert key not in fields or PAIRS.match(fields[key]), (name, fields[key])
        if "Range" in fields:
            low, high = (float(x) for x in fields["Range"].split())
            assert low <= high, name
        if "Increment" in fields:
            assert float(fields["Increment"]) > 0, name
        assert fields.get("RebootRequired", "True") == "True", name


def test_metadata_from_annotations(tmp_path: Path) -> None:
    result = ok(DATA / "metadata.iface")
    compile_params(result, tmp_path)
    docs = documented(next(t for p, t in files(result).items() if p.endswith("_Params.cpp")))
    assert docs["RATE"] == {"DisplayName": "Loop rate", "Description": "Loop rate.", "Units": "Hz",
                            "Range": "10 400", "Increment": "10", "User": "Standard"}
    assert docs["ACCEL"]["Units"] == "m/s/s" and docs["ACCEL"]["Increment"] == "0.1"
    assert docs["ACCEL"]["User"] == "Advanced"
    assert docs["AXES"]["Bitmask"] == "0:Roll,1:Pitch,2:Yaw"
    assert docs["MODE"]["Values"] == "0:Off,1:On" and docs["FAILSAFE"]["Values"] == "0:Hold,1:Land,2:Return"
    assert docs["ENABLE"]["RebootRequired"] == "True"
    assert "Units" not in docs["DRIFT"]


def test_a_unit_arducopter_does_not_know_warns_at_the_annotation_with_a_suggestion() -> None:
    result = ok(DATA / "metadata.iface")
    (d,) = [d for d in result.diagnostics if d.code == "ap-param-units"]
    line, col = d.location()[:2]
    assert (DATA / "metadata.iface").read_text().splitlines()[line - 1][col - 1:].startswith('unit = "m/sec"')
    assert "'m/sec' is not one of ArduPilot's unit names" in d.message and "did you mean 'm/s'?" in d.message


@pytest.mark.parametrize(("unit", "suggestion"), [("m/s^2", "m/s/s"), ("degrees", "deg"), ("hz", "Hz"),
                                                 ("rad/s^2", "rad/s/s"), ("percent", "%")])
def test_unit_suggestions(tmp_path: Path, unit: str, suggestion: str) -> None:
    path = tmp_path / "u.iface"
    path.write_text(f'component u\nconfiguration c {{ 1: float x (unit = "{unit}") }}\n')
    (d,) = [d for d in run(path).diagnostics if d.code == "ap-param-units"]
    assert f"did you mean '{suggestion}'?" in d.message


def test_units_list_names_its_source() -> None:
    data = json.loads((ROOT / "server" / "iface" / "emit" / "ardupilot" / "units.json").read_text())
    assert data["commit"] == "d84f825a932d14654087c820d535f1882c7bfb1e" and "GPL-3.0" in data["licence"]
    assert data["path"] == "Tools/autotest/param_metadata/param.py" and len(data["units"]) == 55
    assert {"m/s/s", "PWM", "degC", "gravities", "%", "cdeg/s"} <= set(data["units"])


def test_bad_metadata_annotations_are_errors_at_the_annotation() -> None:
    result = run(DATA / "bad_metadata.iface")
    assert result.files == []
    found = [d for d in result.diagnostics if d.code == "ap-param-annotation"]
    assert sorted(d.message.split("'")[1] for d in found) == ["bits", "boot", "choice", "mask", "step", "who"]
    lines = (DATA / "bad_metadata.iface").read_text().splitlines()
    for d in found:
        line, col = d.location()[:2]
        assert lines[line - 1][col - 1:].startswith("ap."), d.message


def test_enable_switch_added_unless_declared(tmp_path: Path) -> None:
    rover = files(ok(DATA / "rover_v1.iface"))
    cpp = rover["libraries/AP_Rover/AP_Rover_Params.cpp"]
    assert 'AP_GROUPINFO_FLAGS("ENABLE", 0, AP_Rover_Params, _enable, 0, AP_PARAM_FLAG_ENABLE),' in cpp
    assert "    AP_Int8 _enable;  // RVR_ENABLE" in rover["libraries/AP_Rover/AP_Rover_Params.h"]
    meta = files(ok(DATA / "metadata.iface"))["libraries/AP_Meta/AP_Meta_Params.cpp"]
    assert meta.count('"ENABLE"') == 1
    assert 'AP_GROUPINFO_FLAGS("ENABLE", 0, AP_Meta_Params, _enable, 1, AP_PARAM_FLAG_ENABLE),' in meta
    none = tmp_path / "none.iface"
    none.write_text("component none\nmessage M { 1: i32 x }\npublishes M on \"/m\"\n")
    assert not any(p.endswith("_Params.cpp") for p in files(ok(none)))


def test_a_declared_enable_switch_must_be_an_int8(tmp_path: Path) -> None:
    path = tmp_path / "en.iface"
    path.write_text('component en (ap.prefix = "EN")\nconfiguration c { 1: float enable = 1.0, 2: float x }\n')
    result = run(path)
    assert result.files == []
    (d,) = [d for d in result.diagnostics if d.code == "ap-param-enable-type"]
    assert "'enable' is the group's enable switch (EN_ENABLE) but an AP_Float" in d.message
    line, col = d.location()[:2]
    assert path.read_text().splitlines()[line - 1][col - 1:].startswith("float enable")


def test_index_zero_is_the_enable_switch() -> None:
    result = run(DATA / "enable_conflict.iface")
    assert result.files == []
    (d,) = [d for d in result.diagnostics if d.code == "ap-param-index-conflict"]
    assert "'gain' has index 0, which is CLS_ENABLE's" in d.message


def test_enable_name_too_long_is_reported_at_the_prefix(tmp_path: Path) -> None:
    path = tmp_path / "long.iface"
    path.write_text('component long_one (ap.prefix = "LONGPREFIX")\nconfiguration c { 1: float x }\n')
    result = run(path)
    (d,) = [d for d in result.diagnostics if d.code == "ap-param-name-too-long"]
    assert "LONGPREFIX_ENABLE" in d.message
    line, col = d.location()[:2]
    assert path.read_text().splitlines()[line - 1][col - 1:].startswith('ap.prefix = "LONGPREFIX"')


# ---- AP_Param ------------------------------------------------------------------------------


def test_param_table(tmp_path: Path) -> None:
    result = ok(DATA / "rover_v1.iface")
    compile_params(result, tmp_path)
    cpp = next(t for p, t in files(result).items() if p.endswith(".cpp"))
    assert ('    // @Param: MAX_SPEED\n    // @DisplayName: Top speed\n'
            '    // @Description: Top speed. The rover never goes faster.\n    // @Units: m/s\n'
            '    // @Range: 0 5\n    // @User: Standard\n'
            '    AP_GROUPINFO("MAX_SPEED", 1, AP_Rover_Params, _max_speed, 2.5f),') in cpp
    assert '// @Values: 0:Disabled,1:Enabled' in cpp
    header = next(t for p, t in files(result).items() if p.endswith("_Params.h"))
    assert "    AP_Int16 _wheels;" in header and "    AP_Int8 _reverse;" in header


def test_indices_stable_when_parameters_are_inserted() -> None:
    before = entries(ok(DATA / "rover_v1.iface"))
    after = entries(ok(DATA / "rover_v2.iface"))
    assert before == {"ENABLE": 0, "MAX_SPEED": 1, "STEER_GAIN": 2, "REVERSE": 3, "WHEELS": 4}
    assert {k: after[k] for k in before} == before
    assert after["MAX_ACCEL"] == 5 and after["TRIM"] == 9


def test_implicit_indices_warn() -> None:
    result = ok(DATA / "listing1.iface")
    warned = sorted(d.message.split("'")[1] for d in result.diagnostics if d.code == "ap-param-index-implicit")
    assert warned == ["param2", "param3", "param4"]
    assert entries(result) == {"ENABLE": 0, "PARAM2": 1, "PARAM3": 2, "PARAM4": 3}
    assert any(d.code == "ap-param-unsupported-type" and "'param1'" in d.message for d in result.diagnostics)


def test_bad_params_are_errors_at_the_field() -> None:
    result = run(DATA / "bad_params.iface")
    assert result.files == []
    found = {(d.code, d.message.split("'")[1]) for d in result.diagnostics}
    assert {("ap-param-name-too-long", "a_very_long_parameter"), ("ap-param-index-conflict", "other_gain"),
            ("ap-param-index-range", "far_away"), ("ap-param-unsupported-type", "counter")} <= found
    lines = (DATA / "bad_params.iface").read_text().splitlines()
    for d in result.diagnostics:
        assert d.code in CODES
        assert d.message.split("'")[1] in lines[d.location()[0] - 1]


# ---- injection ------------------------------------------------------------------------------


def test_injection_docs_stay_comments(tmp_path: Path) -> None:
    result = ok(DATA / "injection_docs.iface")
    types = idl_types(result)
    consts, fields = types["injection_docs/msg/Probe"]
    assert consts == [] and [name for name, _ in fields] == ["value", "count"]
    compile_params(result, tmp_path)
    for path, text in files(result).items():
        for line in text.splitlines():
            assert not line.rstrip().endswith("\\"), f"{path}: a comment continued onto the next line"
    cpp = next(t for p, t in files(result).items() if p.endswith(".cpp"))
    assert '    // @Description: Gain "quoted" # hash <b> ../x second\n' in cpp
    assert entries(result) == {"ENABLE": 0, "GAIN": 1, "ON": 2}


def test_injection_strings_escaped_or_refused() -> None:
    result = run(DATA / "injection_strings.iface")
    # a string parameter is left out for its type, and gets no further diagnostic (its name would be too long)
    about_mode = [d.code for d in result.diagnostics if "'mode'" in d.message]
    assert about_mode == ["ap-param-unsupported-type"]
    assert not result.has_errors
    assert "injection_strings/msg/Texts" in idl_types(result)
    idl = next(t for p, t in files(result).items() if p.endswith("Texts.idl"))
    assert '@default (value="*/ \\" # <x> ../ | `tick` \\n end")' in idl
    assert not any(p.endswith(("_Params.h", ".cpp")) for p in files(result))


# ---- unsupported parameter types ------------------------------------------------------------


@pytest.mark.parametrize(("field", "detail"), [
    ("u32 an_unsupported_long_name", "u32 values above 2147483647 do not fit AP_Int32 (use i32)"),
    ("i64 an_unsupported_long_name", "a 64-bit integer does not fit"),
    ("string an_unsupported_long_name", ""),
])
def test_a_parameter_left_out_for_its_type_gets_no_name_diagnostic(tmp_path: Path, field: str,
                                                                   detail: str) -> None:
    path = tmp_path / "skip.iface"
    path.write_text(f"component skip\nconfiguration c (ap.prefix = \"SKIP\") {{ 1: float gain, 2: {field} }}\n")
    result = run(path)
    about = [d for d in result.diagnostics if "an_unsupported_long_name" in d.message]
    assert [d.code for d in about] == ["ap-param-unsupported-type"]
    (d,) = about
    assert "AP_Param holds signed integers of up to 32 bits (AP_Int8, AP_Int16, AP_Int32) and 32-bit " \
           "floats (AP_Float)" in d.message and detail in d.message
    assert not result.has_errors and entries(result) == {"ENABLE": 0, "GAIN": 1}
