"""iface_msgs and the shared packages without ROS: the protocol's types, written once, updated or kept by version."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from iface.emit.write import stamp, unstamp
from iface.nodes import protocol, shared
from tests.emit.golden_util import check_golden
from tests.emit.oracles import rosidl_parse

from ..ros_harness.ros import ROOT

EXAMPLES = ROOT / "examples"
_VERSION = re.compile(r"<version>([^<]+)</version>")


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "iface", *args], capture_output=True, text=True, timeout=120,
                          check=False)


def generate(out: Path, example: str, target: str = "rclpy") -> subprocess.CompletedProcess[str]:
    done = cli("generate", str(EXAMPLES / example), "--target", target, "--out", str(out))
    assert done.returncode == 0, done.stderr
    return done


def contents(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def set_version(package_xml: Path, version: str) -> None:
    """Give a generated package.xml another version, stamped as iface would have written it."""
    body, _ = unstamp(package_xml.read_text(encoding="utf-8"))
    package_xml.write_text(stamp(_VERSION.sub(f"<version>{version}</version>", body)), encoding="utf-8")


def test_the_protocol_has_describe_and_versions() -> None:
    assert protocol.PROTOCOL_VERSION == "1" and protocol.PACKAGE == "iface_msgs"
    by_name = {s.type_name: s for s in protocol.SERVICES}
    assert set(by_name) >= {"SaveState", "RestoreState", "ComponentControl", "Describe"}
    describe = by_name["Describe"]
    assert describe.served_as == "~/describe" and describe.request == ()
    assert [(f.type, f.name) for f in describe.response] == [
        ("string", n) for n in ("node_name", "component", "version", "interface_hash", "runtime", "runtime_version",
                                "protocol_version", "interface_json")]
    control = [(f.type, f.name) for f in by_name["ComponentControl"].response]
    assert ("string", "protocol_version") in control and ("uint32", "pid") in control


def test_iface_msgs_holds_every_protocol_type_and_passes_rosidl() -> None:
    package = shared.msgs_package()
    files = {f.path: f.text for f in package.files}
    expected = {f"iface_msgs/srv/{s.type_name}.srv" for s in protocol.SERVICES}
    expected |= {f"iface_msgs/msg/{m.type_name}.msg" for m in protocol.MESSAGES}
    assert expected | {"iface_msgs/package.xml", "iface_msgs/CMakeLists.txt"} == set(files)
    assert f"<version>{protocol.PACKAGE_VERSION}</version>" in files["iface_msgs/package.xml"]
    for s in protocol.SERVICES:
        request, response = rosidl_parse(files[f"iface_msgs/srv/{s.type_name}.srv"], "iface_msgs", "srv",
                                         s.type_name)
        assert [f.name for f in response.fields] == [f.name for f in s.response]
        assert [f.name for f in request.fields] == [f.name for f in s.request]


def test_two_components_share_one_copy_and_a_newer_one_is_kept(tmp_path: Path) -> None:
    out = tmp_path / "src"
    first = generate(out, "robot_arm.iface")
    v = protocol.PACKAGE_VERSION
    assert f"iface_msgs {v}: new in" in first.stderr
    written = contents(out / "iface_msgs")
    second = generate(out, "counter.iface", "rclcpp")
    assert "is this version: reused" in second.stderr and "wrote " + str(out / "iface_msgs") not in second.stderr
    assert contents(out / "iface_msgs") == written

    set_version(out / "iface_msgs" / "package.xml", "0.9.0")
    older = generate(out, "counter.iface")
    assert f"(0.9.0) is older than this iface's ({v}): updated" in older.stderr
    assert f"<version>{v}</version>" in (out / "iface_msgs" / "package.xml").read_text(encoding="utf-8")

    set_version(out / "iface_msgs" / "package.xml", "9.1.0")
    (out / "iface_msgs" / "srv" / "Describe.srv").unlink()
    newer = generate(out, "counter.iface")
    assert f"(9.1.0) is newer than this iface's ({v}): kept" in newer.stderr
    assert "<version>9.1.0</version>" in (out / "iface_msgs" / "package.xml").read_text(encoding="utf-8")
    assert not (out / "iface_msgs" / "srv" / "Describe.srv").exists()  # left as found: not even a missing file
    quiet = cli("generate", str(EXAMPLES / "counter.iface"), "--target", "rclpy", "--out", str(out), "-q")
    assert quiet.returncode == 0 and quiet.stderr == ""


def test_iface_msgs_is_its_golden() -> None:
    """iface_msgs is generated from iface.nodes.protocol for every node target alike: one golden (golden/ros2)."""
    check_golden("ros2", "iface_msgs", list(shared.msgs_package().files))
