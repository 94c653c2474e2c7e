"""``system status``'s three forms from a manager's answer, without ROS: each instance's container in text and json,
and in html each container drawn around the instances it holds."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from iface.commands.system import _status
from iface.nodes.system import system_spec

from ..ros_harness.ros import ROOT

SYSTEM = """system plant version "1.0.0"
include "counter.iface"
include "room_sensor.iface"
instance sensor : room_sensor
instance one : counter (container = "box")
instance two : counter (container = "box", node = "counter_two")
"""


def _data() -> dict[str, Any]:
    def inst(name: str, node: str, state: str, pid: int, container: str | None) -> dict[str, Any]:
        component = "room_sensor" if name == "sensor" else "counter"
        return {"name": name, "node": node, "component": component, "state": state, "pid": pid, "restarts": 1 if container else 0,
                "interface_hash": "sha256:" + "ab" * 32, "last_snapshot": None, "container": container}

    return {"system": "plant", "instances": [inst("sensor", "/sensor", "active", 101, None),
                                             inst("one", "/one", "active", 202, "box"),
                                             inst("two", "/counter_two", "starting", 202, "box")],
            "findings": [{"instance": "one", "message": "container box (pid 150) ended (signal 9): restarted"}]}


@pytest.fixture
def spec(tmp_path: Path) -> Any:
    for name in ("counter.iface", "room_sensor.iface"):
        (tmp_path / name).write_text((ROOT / "examples" / name).read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / "plant.iface").write_text(SYSTEM, encoding="utf-8")
    return system_spec(tmp_path / "plant.iface")


def test_json_has_each_instances_container(spec: Any, capsys: pytest.CaptureFixture[str]) -> None:
    assert _status(spec, _data(), "json") == 1  # one instance is not active
    out = json.loads(capsys.readouterr().out)
    assert [(i["name"], i["container"]) for i in out["instances"]] == [("sensor", None), ("one", "box"),
                                                                       ("two", "box")]
    assert set(out) == {"instances", "findings"}


def test_text_names_the_container_of_each_instance_and_its_members(spec: Any,
                                                                   capsys: pytest.CaptureFixture[str]) -> None:
    _status(spec, _data(), "text")
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "plant: 2 of 3 instances active"
    assert lines[1].startswith("  sensor ") and "container" not in lines[1]
    assert lines[2].startswith("  one ") and lines[2].endswith("  in container box")
    assert "container box: one, two; pid 202" in lines
    assert lines[-1] == "one: container box (pid 150) ended (signal 9): restarted"


def test_html_draws_each_container_around_its_instances(spec: Any, capsys: pytest.CaptureFixture[str]) -> None:
    _status(spec, _data(), "html")
    page = capsys.readouterr().out
    box = re.search(r'<div class="process container" id="container-box">(.*?</div>)</div>(?:\n|</section>)', page,
                    re.DOTALL)
    assert box is not None, page
    inside = box.group(1)
    assert 'id="instance-one"' in inside and 'id="instance-two"' in inside and "pid 202" in inside
    assert 'id="instance-sensor"' not in inside and 'id="instance-sensor"' in page
    assert "one [active] in box" in page and "sensor [active]" in page  # the graph's labels
    assert "<td>box</td>" in page and "<td>counter</td>" in page and "<script" not in page
