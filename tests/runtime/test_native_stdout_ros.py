"""A command's JSON stays JSON when Fast DDS logs to standard output, on every release (``live/stdout.py``).

Fast DDS writes its log to descriptor 1 (Jazzy's 2.14 its errors too: a hand-over's JSON once began with
``RTPS_TRANSPORT_SHM Error … open_and_lock_file failed``). A discovery-server list it cannot read makes it log
an error at every participant's start (``ROS_DISCOVERY_SERVER=bogus::::1``), and the participant still works:
``verify --format json`` of a component nobody runs prints its findings as JSON, and the error goes to stderr.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from ..ros_harness.ros import ROOT, environment

PER_RELEASE = True


def test_fast_dds_logging_to_stdout_does_not_break_the_json(ros_venv: Path, tmp_path: Path) -> None:
    env = {**environment(ros_venv, log_dir=tmp_path / "ros-log"), "ROS_DISCOVERY_SERVER": "bogus::::1"}
    done = subprocess.run([sys.executable, "-m", "iface", "verify", str(ROOT / "examples" / "counter.iface"),
                           "--format", "json", "--timeout", "1"], env=env, capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 1, done.stderr
    assert "SERVER_CLIENT_DISCOVERY" in done.stderr, done.stderr  # Fast DDS did log
    findings = json.loads(done.stdout)["findings"]
    assert [f["code"] for f in findings] == ["live-node-missing"], findings
