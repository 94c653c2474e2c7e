"""roundtrip counts every input file: an .idl file is judged like the others, one that does not import is never success."""

from __future__ import annotations

from pathlib import Path

from ..conftest import run_main

PACKAGE_XML = """<?xml version="1.0"?>
<package format="3"><name>demo_msgs</name><version>0.1.0</version><description>d</description>
<maintainer email="a@b.c">a</maintainer><license>Apache-2.0</license></package>
"""
IDL = """module demo_msgs {
  module msg {
    struct Extra {
      int32 value;
    };
  };
};
"""


def _package(tmp_path: Path, idl: str) -> Path:
    pkg = tmp_path / "demo_msgs"
    (pkg / "msg").mkdir(parents=True)
    (pkg / "package.xml").write_text(PACKAGE_XML)
    (pkg / "msg" / "Point.msg").write_text("float64 x\nfloat64 y\n")
    (pkg / "msg" / "Extra.idl").write_text(idl)
    return pkg


def test_an_idl_file_is_counted_and_judged(tmp_path: Path) -> None:
    done = run_main("roundtrip", "-v", "--from", "ros2", str(_package(tmp_path, IDL)))
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Extra.idl: identical" in done.stdout
    assert done.stdout.splitlines()[-1] == "2 of 2 identical"


def test_an_idl_file_that_does_not_import_fails_the_round_trip(tmp_path: Path) -> None:
    done = run_main("roundtrip", "--from", "ros2", str(_package(tmp_path, "module demo_msgs { this is not idl")))
    assert done.returncode == 1, done.stdout + done.stderr
    assert "Extra.idl: not imported" in done.stdout
    assert done.stdout.splitlines()[-1] == "1 of 2 identical"
