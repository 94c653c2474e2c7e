"""package.xml metadata survives import → generate."""

from __future__ import annotations

from pathlib import Path

from catkin_pkg.package import parse_package_string

from tests.conftest import run_main

PACKAGE_XML = """<?xml version="1.0"?>
<package format="3">
  <name>dock_msgs</name>
  <version>0.4.2</version>
  <description>Docking
     messages</description>
  <maintainer email="team@robots.example">Dock Team</maintainer>
  <license>BSD-3-Clause</license>
</package>
"""


def test_package_metadata_round_trips(tmp_path: Path) -> None:
    pkg = tmp_path / "dock_msgs"
    (pkg / "msg").mkdir(parents=True)
    (pkg / "package.xml").write_text(PACKAGE_XML)
    (pkg / "msg" / "Dock.msg").write_text("# A dock.\nint32 id\n")
    r = run_main("import", "--from", "ros2", str(pkg), "--out", str(tmp_path / "ifc"))
    assert r.returncode == 0, r.stdout + r.stderr
    text = (tmp_path / "ifc" / "dock_msgs.iface").read_text()
    assert 'component dock_msgs version "0.4.2"' in text
    r = run_main("generate", str(tmp_path / "ifc" / "dock_msgs.iface"), "--target", "ros2", "--out", str(tmp_path / "gen"))
    assert r.returncode == 0, r.stdout + r.stderr
    meta = parse_package_string((tmp_path / "gen" / "dock_msgs" / "package.xml").read_text())
    assert (meta.version, meta.description, meta.licenses[0]) == ("0.4.2", "Docking messages", "BSD-3-Clause")
    assert (meta.maintainers[0].name, meta.maintainers[0].email) == ("Dock Team", "team@robots.example")
