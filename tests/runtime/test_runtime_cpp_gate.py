"""iface_runtime_cpp's work gate compiled and run without ROS: its own unit test (test/test_gate.cpp, which ctest
also runs in test_rclcpp_e2e.py) with src/gate.cpp alone, so that every machine with a C++ compiler runs it."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

RUNTIME = Path(__file__).resolve().parents[2] / "server" / "iface" / "nodes" / "runtimes" / "iface_runtime_cpp"


def test_a_pause_refuses_new_work_and_a_snapshot_holds_it(tmp_path: Path) -> None:
    compiler = shutil.which("c++") or shutil.which("g++")
    if compiler is None:
        pytest.skip("no C++ compiler (c++ or g++) on PATH")
    exe = tmp_path / "test_gate"
    built = subprocess.run([compiler, "-std=c++17", "-Wall", "-Wextra", "-Werror", "-pthread", "-I",
                            str(RUNTIME / "include"), str(RUNTIME / "test" / "test_gate.cpp"),
                            str(RUNTIME / "src" / "gate.cpp"), "-o", str(exe)],
                           capture_output=True, text=True, timeout=120, check=False)
    assert built.returncode == 0, built.stderr
    ran = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60, check=False)
    assert ran.returncode == 0 and ran.stdout.strip() == "gate: ok", ran.stdout + ran.stderr
