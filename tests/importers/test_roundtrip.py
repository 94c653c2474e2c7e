"""``iface-lsp roundtrip`` end to end, and the oracle it judges with."""

from __future__ import annotations

import pytest

from iface.importers.oracle import FileView, PartView, differences, rihs01, ros_view

from ..conftest import run_main
from .helpers import BROKEN, DATA, GAPS, PX4, PX4_ACCEPTED, ROBOT_GEOMETRY, ROBOT_MSGS, ros_files

pytest.importorskip("mcap_ros2")
pytest.importorskip("genmsg")


def test_ros2_fixtures_come_back_identical():
    r = run_main("roundtrip", "--from", "ros2", str(ROBOT_MSGS), str(ROBOT_GEOMETRY))
    count = len(ros_files(ROBOT_MSGS, ROBOT_GEOMETRY))
    assert r.stdout.splitlines()[-1] == f"{count} of {count} identical", r.stdout + r.stderr
    assert r.returncode == 0


def test_a_file_that_does_not_import_is_counted_as_different():
    r = run_main("roundtrip", "--from", "ros2", str(BROKEN))
    assert r.returncode == 1
    assert "Bad.msg: not imported" in r.stdout
    assert r.stdout.splitlines()[-1] == "1 of 2 identical"


def test_string_array_elements_with_commas():
    """["a, b", 'c', d] in CommaStrings.msg: rosidl reads the commas inside quotes as text."""
    r = run_main("roundtrip", "--from", "ros2", str(GAPS))
    assert r.returncode == 0, r.stdout


def test_px4_fixtures_come_back_identical():
    r = run_main("roundtrip", "--from", "px4", str(PX4), "-v")
    assert r.stdout.splitlines()[-1] == "2 of 2 identical", r.stdout + r.stderr
    assert r.returncode == 0


def test_messages_px4_builds_import_and_regenerate(tmp_path):
    """A uint32 ORB_QUEUE_LENGTH, a float constant with a fraction, a queue uORB rounds, a topic too long for
    uORB's node path: PX4 builds each, so iface warns and writes them back as they were."""
    r = run_main("roundtrip", "--from", "px4", str(PX4_ACCEPTED))
    assert r.stdout.splitlines()[-1] == "2 of 2 identical", r.stdout + r.stderr
    assert r.returncode == 0
    assert run_main("import", "--from", "px4", str(PX4_ACCEPTED), "--out", str(tmp_path / "iface")).returncode == 0
    (model,) = (tmp_path / "iface").glob("*.iface")
    assert run_main("check", str(model)).returncode == 0
    r = run_main("generate", str(model), "--target", "px4", "--out", str(tmp_path / "out"))
    assert r.returncode == 0, r.stderr
    warned = sorted(line.split("[")[1].split("]")[0] for line in r.stderr.splitlines() if "warning[" in line)
    assert warned == ["px4-constant-fraction", "px4-queue-length", "px4-queue-length-rounded", "px4-topic-too-long"]
    written = {p.name: p.read_text().splitlines() for p in (tmp_path / "out" / "msg").glob("*.msg")}
    assert "uint32 ORB_QUEUE_LENGTH = 2" in written["ModeReply.msg"]
    burst = [line if line.startswith("# TOPICS") else line.split("#")[0].strip()
             for line in written["SampleBurst.msg"]]
    assert {"float32 GAIN = 0.5", "uint8 ORB_QUEUE_LENGTH = 5"} <= set(burst)
    assert "# TOPICS sample_burst sample_burst_of_a_sensor_with_a_name_longer_than_uorb_keeps" in burst


def test_json_round_trip(tmp_path):
    src = DATA / "iface"
    for name in ("everything", "shapes"):
        r = run_main("generate", "-t", "json", "-o", str(tmp_path), str(src / f"{name}.iface"))
        assert r.returncode == 0, r.stderr
    r = run_main("roundtrip", "--from", "json", *(str(p) for p in sorted(tmp_path.glob("*.json"))))
    assert r.stdout.splitlines()[-1] == "2 of 2 identical", r.stdout + r.stderr


def test_json_round_trip_reports_a_changed_model(tmp_path):
    r = run_main("generate", "-t", "json", "-o", str(tmp_path), str(DATA / "iface" / "shapes.iface"))
    assert r.returncode == 0, r.stderr
    path = tmp_path / "shapes.json"
    path.write_text(path.read_text().replace('"name": "shapes"', '"name": "other"'))
    r = run_main("roundtrip", "--from", "json", str(path))
    assert r.returncode == 1
    assert "/name: expected" in r.stdout


def test_rihs01_matches_rosbags():
    rosbags = pytest.importorskip("rosbags.typesys")
    store = rosbags.get_typestore(rosbags.Stores.LATEST)
    text = (ROBOT_GEOMETRY / "msg" / "Point.msg").read_text()
    view = ros_view("msg", "robot_geometry", "Point", text)
    ours = rihs01("robot_geometry/msg/Point", {view.parts[0].name: view.parts[0].descs})
    store.register(rosbags.get_types_from_msg(text, "robot_geometry/msg/Point"))
    assert ours == store.hash_rihs01("robot_geometry/msg/Point")
    assert rihs01("std_msgs/msg/Header", {}) == store.hash_rihs01("std_msgs/msg/Header")


def test_differences_name_what_changed():
    a = FileView("msg", [PartView("p/msg/M", [("x", "int32", None)], [("uint8", "K", 1)])], ["t"])
    b = FileView("msg", [PartView("p/msg/M", [("x", "int64", None)], [("uint8", "K", 2)])], ["u"])
    found = differences(a, b)
    assert len(found) == 3
    assert "field 1: expected x int32, got x int64" in found[0]
    assert differences(a, a) == []
    c = FileView("msg", [PartView("p/msg/M", [("x", "bool", True)], [])])
    d = FileView("msg", [PartView("p/msg/M", [("x", "bool", 1)], [])])
    assert differences(c, d)
