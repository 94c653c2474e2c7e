"""The manager's participant announces itself every 0.2 s (operate/announce.py), only where nothing else is asked for.

Its profile is read back by an XML parser. The manager scenario (tests/ros_harness/drive_manager.py, step "up") sees
the manager say so and its instances started without the profile; what it buys (a restarted instance finds the
manager within 0.2 s instead of up to 3 s) is measured by bench/manager_bench.py (docs/system.md, "Restart time").
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from iface.operate import announce

NS = {"dds": "http://www.eprosima.com"}


def test_the_profile_is_a_default_participant_profile_announcing_every_0_2_s(tmp_path: Path) -> None:
    made = announce.own_profile({}, tmp_path, tmp_path)
    assert set(made) == set(announce.PROFILE_VARIABLES)
    path = Path(made["FASTDDS_DEFAULT_PROFILES_FILE"])
    assert path.parent == tmp_path and made["FASTRTPS_DEFAULT_PROFILES_FILE"] == str(path)
    root = ET.parse(path).getroot()
    participant = root.find("dds:profiles/dds:participant", NS)
    assert participant is not None and participant.get("is_default_profile") == "true"
    period = participant.find("dds:rtps/dds:builtin/dds:discovery_config/dds:leaseAnnouncement", NS)
    assert period is not None
    assert int(period.findtext("dds:sec", namespaces=NS) or "x") == 0
    assert int(period.findtext("dds:nanosec", namespaces=NS) or "x") == 200_000_000
    assert not list(tmp_path.glob("*.partial"))


def test_the_profile_is_written_once_and_the_same_each_time(tmp_path: Path) -> None:
    first = Path(announce.own_profile({}, tmp_path, tmp_path)["FASTDDS_DEFAULT_PROFILES_FILE"])
    stamp = first.stat().st_mtime_ns
    again = Path(announce.own_profile({"RMW_IMPLEMENTATION": "rmw_fastrtps_cpp"}, tmp_path, tmp_path)
                 ["FASTDDS_DEFAULT_PROFILES_FILE"])
    assert again == first and first.stat().st_mtime_ns == stamp
    assert announce.profile_xml(1.5).count("<sec>1</sec><nanosec>500000000</nanosec>") == 1


@pytest.mark.parametrize(("env", "reason"), [
    ({"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp"}, "the RMW is rmw_cyclonedds_cpp"),
    ({"FASTDDS_DEFAULT_PROFILES_FILE": "/etc/mine.xml"}, "FASTDDS_DEFAULT_PROFILES_FILE names a profile file"),
    ({"FASTRTPS_DEFAULT_PROFILES_FILE": "/etc/mine.xml"}, "FASTRTPS_DEFAULT_PROFILES_FILE names a profile file"),
    ({"ROS_DISCOVERY_SERVER": "127.0.0.1:11811"}, "a discovery server is used (ROS_DISCOVERY_SERVER)"),
])
def test_what_the_user_asked_for_is_kept(tmp_path: Path, env: dict[str, str], reason: str) -> None:
    assert announce.why_not(env, tmp_path) == reason
    assert announce.own_profile(env, tmp_path / "state", tmp_path) == {}
    assert not (tmp_path / "state").exists()


def test_a_profile_file_in_the_working_folder_is_kept(tmp_path: Path) -> None:
    (tmp_path / "DEFAULT_FASTRTPS_PROFILES.xml").write_text("<dds/>", encoding="utf-8")
    assert announce.why_not({}, tmp_path) == "DEFAULT_FASTRTPS_PROFILES.xml is in the working folder"
    assert announce.own_profile({}, tmp_path, tmp_path) == {}

