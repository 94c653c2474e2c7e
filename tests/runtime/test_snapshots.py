"""Snapshots on disk: atomic writes, the last N kept, the previous one readable when a writer is killed mid-write."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from iface.operate.snapshots import SnapshotStore, iso_time

from ..ros_harness.ros import ROOT

WRITER = """
import sys
from pathlib import Path
from iface.operate.snapshots import SnapshotStore
store = SnapshotStore(Path(sys.argv[1]), keep=3)
big = '{"values": {"blob": "' + 'x' * 40_000_000 + '"}}'
while True:
    store.write(big)
"""


def _doc(n: int) -> str:
    return json.dumps({"format": "iface-state/1", "values": {"n": n}}, sort_keys=True)


def test_keeps_the_last_n_newest_first(tmp_path: Path) -> None:
    store = SnapshotStore(tmp_path / "thermostat", keep=3)
    assert store.latest() is None
    for n in range(1, 6):
        snap = store.write(_doc(n))
        assert snap.sequence == n
    assert [json.loads(s.document)["values"]["n"] for s in store.all()] == [3, 4, 5]
    latest = store.latest()
    assert latest is not None and json.loads(latest.document)["values"]["n"] == 5
    assert sorted(p.name for p in (tmp_path / "thermostat").iterdir()) == [
        "0000000003.json", "0000000004.json", "0000000005.json"]


def test_an_unreadable_newest_file_is_skipped(tmp_path: Path) -> None:
    store = SnapshotStore(tmp_path / "s")
    store.write(_doc(1))
    (tmp_path / "s" / "0000000002.json").write_text('{"values": ', encoding="utf-8")
    latest = store.latest()
    assert latest is not None and latest.sequence == 1


def test_iso_time() -> None:
    assert iso_time(0.5) == "1970-01-01T00:00:00.500Z"


def test_a_writer_killed_mid_write_leaves_the_previous_snapshot_readable(tmp_path: Path) -> None:
    folder = tmp_path / "sensor"
    store = SnapshotStore(folder, keep=3)
    store.write(_doc(7))
    env = {**os.environ, "PYTHONPATH": str(ROOT / "server")}
    for _attempt in range(5):
        proc = subprocess.Popen([sys.executable, "-c", WRITER, str(folder)], env=env, start_new_session=True)
        try:
            deadline = time.monotonic() + 60
            temp = None
            while temp is None and time.monotonic() < deadline and proc.poll() is None:
                temp = next((p for p in folder.iterdir() if p.name.startswith(".tmp-")), None)
                if temp is None:
                    time.sleep(0.001)
            os.kill(proc.pid, signal.SIGKILL)
        finally:
            if proc.poll() is None:
                proc.kill()
            proc.wait(timeout=30)
        assert temp is not None, "the writer never started a snapshot"
        if temp.exists():
            break  # killed while the temporary file was being written: the case under test
    else:
        pytest.fail("the writer was never caught mid-write in 5 attempts")
    latest = store.latest()
    assert latest is not None
    values = json.loads(latest.document)["values"]
    assert values == {"n": 7} or len(values["blob"]) == 40_000_000
    assert all(json.loads(s.document) for s in store.all())
    store.write(_doc(8))
    assert not [p for p in folder.iterdir() if p.name.startswith(".tmp-")], "a stray temporary file was kept"
    latest = store.latest()
    assert latest is not None and json.loads(latest.document)["values"] == {"n": 8}
