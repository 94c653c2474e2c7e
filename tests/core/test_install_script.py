"""scripts/install-ros.sh in a clone without ../shared: the clear message, no other machine's path."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_a_clone_without_shared_gets_the_clear_message(tmp_path: Path) -> None:
    clone = tmp_path / "elsewhere" / "iface"
    (clone / "scripts").mkdir(parents=True)
    shutil.copy(ROOT / "scripts" / "install-ros.sh", clone / "scripts")
    # stand-ins that stop the script before it installs anything, should it find a ../shared somewhere
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name in ("dpkg", "apt-get"):
        (bin_dir / name).write_text("#!/bin/sh\nexit 1\n")
        (bin_dir / name).chmod(0o755)
    (bin_dir / "id").write_text("#!/bin/sh\necho 1000\n")
    (bin_dir / "id").chmod(0o755)
    env = {k: v for k, v in os.environ.items() if not k.startswith("IFACE_ROS2")}
    env.update(PATH=f"{bin_dir}:{env.get('PATH', '/usr/bin:/bin')}", HOME=str(tmp_path),
               IFACE_ROS2_VENV=str(tmp_path / "venv"))
    r = subprocess.run(["bash", str(clone / "scripts" / "install-ros.sh")], env=env, capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stderr
    assert f"install-ros: no ../shared beside this clone ({tmp_path / 'elsewhere' / 'shared'}/ros2-runtime" in r.stderr
    assert not (tmp_path / "venv").exists()


def test_the_script_names_no_machine_path() -> None:
    text = (ROOT / "scripts" / "install-ros.sh").read_text()
    assert "/work/" not in text
