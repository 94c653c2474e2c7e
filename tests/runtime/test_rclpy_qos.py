"""Every QoS policy of the file reaches the entities the generated node creates, seen from outside.

tests/runtime/data/qos_probe.iface sets every policy, each to a value that is not ROS 2's default, on a
publisher, a subscription, a provided service and a provided action. Its node is started from its entry
point and another process reads what each endpoint announces on the wire (reliability, durability,
deadline, lifespan, liveliness and its lease). DDS discovery does not carry history and depth (Fast DDS
reports them as unknown/0), so those are read from the entities a configured node created in-process.
Loopback only, a random ROS_DOMAIN_ID, every wait bounded, the node stopped by its own handle.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
from pathlib import Path
from typing import Any

import pytest

from ..ros_harness.ros import DATA, HARNESS, build, environment, generate, run_bounded

#: Run once per ROS 2 release (tests/runtime/conftest.py).
PER_RELEASE = True

DRIVER = HARNESS / "drive_qos.py"
S = 1_000_000_000
INFINITE = 9223372036854775807  # the largest rmw duration: what an unset deadline, lifespan or lease reads as

#: What each endpoint announces: the file's values, ROS 2's defaults where the file sets none.
WIRE = {
    "pub:/qos/out": {"reliability": "best_effort", "durability": "transient_local", "deadline": 3 * S // 2,
                     "lifespan": 3 * S // 4, "liveliness": "manual_by_topic", "liveliness_lease_duration": 4 * S},
    "sub:/qos/in": {"reliability": "reliable", "durability": "transient_local", "deadline": 5 * S,
                    "lifespan": INFINITE, "liveliness": "manual_by_topic", "liveliness_lease_duration": 6 * S},
    # a service is a request reader and a reply writer; services default to reliable
    "sub:rq/qos/pingRequest": {"reliability": "reliable", "durability": "transient_local", "deadline": 7 * S,
                               "lifespan": 2 * S, "liveliness": "automatic", "liveliness_lease_duration": INFINITE},
    "pub:rr/qos/pingReply": {"reliability": "reliable", "durability": "transient_local", "deadline": 7 * S,
                             "lifespan": 2 * S, "liveliness": "automatic", "liveliness_lease_duration": INFINITE},
    # an action: its feedback topic and its goal service
    "pub:/qos/go/_action/feedback": {"reliability": "best_effort", "durability": "volatile", "deadline": 8 * S,
                                     "lifespan": INFINITE, "liveliness": "manual_by_topic",
                                     "liveliness_lease_duration": 9 * S},
    "sub:rq/qos/go/_action/send_goalRequest": {"reliability": "best_effort", "durability": "volatile",
                                               "deadline": 8 * S, "lifespan": INFINITE,
                                               "liveliness": "manual_by_topic", "liveliness_lease_duration": 9 * S},
}
#: History and depth of the entities the configured node holds.
ENTITIES = {
    "pub:/qos/out": {"history": "keep_all"},
    "sub:/qos/in": {"history": "keep_last", "depth": 3},
    "srv:/qos/ping": {"history": "keep_last", "depth": 4},
}


@pytest.fixture(scope="module")
def probe(ros_venv: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """Generate and build qos_probe, start it, read its endpoints' QoS; then its entities in-process."""
    root = tmp_path_factory.mktemp("qos_probe")
    made = generate(DATA / "qos_probe.iface", root / "gen")
    assert made.returncode == 0, made.stderr
    (root / "ws").mkdir()
    ok, tail, _ = build(ros_venv, root / "gen", root / "ws")
    assert ok, f"qos_probe did not build:\n{tail}"
    env = environment(ros_venv, root / "ws", root / "ros-log")
    python = str(ros_venv / "bin" / "python")
    with open(root / "node.log", "w") as log:
        node = subprocess.Popen([python, "-m", "qos_probe", "--activate"], env=env, stdout=log,
                                stderr=subprocess.STDOUT, start_new_session=True)
    try:
        code = run_bounded([python, str(DRIVER), "wire", "qos_probe", *WIRE], env, 120, root / "wire.log")
        wire = _last_json(root / "wire.log", code)
    finally:
        os.killpg(node.pid, signal.SIGINT)
        try:
            node.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(node.pid, signal.SIGKILL)
            node.wait(timeout=20)
    code = run_bounded([python, str(DRIVER), "entities", "qos_probe", "QosProbe"], env, 120, root / "entities.log")
    return {"wire": wire, "entities": _last_json(root / "entities.log", code), "logs": str(root)}


def _last_json(log: Path, code: int | None) -> dict[str, Any]:
    text = log.read_text(errors="replace")
    assert code == 0, f"the probe exited {code}:\n{text[-3000:]}"
    return json.loads(text.strip().splitlines()[-1])


@pytest.mark.parametrize("endpoint", sorted(WIRE))
def test_the_endpoint_announces_the_declared_qos(probe: dict[str, Any], endpoint: str) -> None:
    assert endpoint in probe["wire"], f"{endpoint} was not discovered (logs in {probe['logs']})"
    seen = {k: v for k, v in probe["wire"][endpoint].items() if k in WIRE[endpoint]}
    assert seen == WIRE[endpoint]


@pytest.mark.parametrize("entity", sorted(ENTITIES))
def test_the_entity_keeps_the_declared_history_and_depth(probe: dict[str, Any], entity: str) -> None:
    assert entity in probe["entities"], f"{entity} not created: {sorted(probe['entities'])}"
    seen = {k: v for k, v in probe["entities"][entity].items() if k in ENTITIES[entity]}
    assert seen == ENTITIES[entity]
