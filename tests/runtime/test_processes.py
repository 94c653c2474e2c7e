"""Instance processes without ROS: own session, records, adoption only of the very process recorded."""

from __future__ import annotations

import dataclasses
import os
import sys
from pathlib import Path

import pytest

from iface.operate.processes import Records, StartError, find_executable, running, start


def test_a_started_process_is_recorded_and_recognised_and_a_changed_record_is_not(tmp_path: Path) -> None:
    argv = [sys.executable, "-c", "import time; time.sleep(120)", "--ros-args", "-r", "__node:=sensor"]
    proc = start("sensor", "sensor", argv, dict(os.environ), tmp_path / "logs" / "sensor.log", package_dir="",
                 iface_file="s.iface", interface_hash="sha256:x", generation=1)
    try:
        assert os.getsid(proc.pid) == proc.pid, "not in a session of its own"
        assert proc.record.cmdline == tuple(argv)
        records = Records(tmp_path)
        records.save(proc.record)
        again = records.load("sensor")
        assert again == proc.record
        assert running(again)
        assert not running(dataclasses.replace(again, start_ticks=again.start_ticks + 1)), "a recycled pid"
        assert not running(dataclasses.replace(again, cmdline=(*again.cmdline, "x"))), "another command"
    finally:
        proc.stop(5.0)
    assert not proc.alive() and not running(proc.record)
    records.remove("sensor")
    assert records.load("sensor") is None


def test_an_unreadable_record_is_none(tmp_path: Path) -> None:
    (tmp_path / "processes").mkdir()
    (tmp_path / "processes" / "x.json").write_text("{", encoding="utf-8")
    assert Records(tmp_path).load("x") is None


def test_executable_found_on_the_ament_prefix_path(tmp_path: Path) -> None:
    exe = tmp_path / "prefix" / "lib" / "thermostat" / "thermostat"
    exe.parent.mkdir(parents=True)
    exe.write_text("#!/bin/sh\n")
    exe.chmod(0o755)
    env = {"AMENT_PREFIX_PATH": f"{tmp_path / 'none'}{os.pathsep}{tmp_path / 'prefix'}"}
    assert find_executable("thermostat", "thermostat", env) == str(exe)
    with pytest.raises(StartError, match="no executable other of package thermostat"):
        find_executable("thermostat", "other", env)
