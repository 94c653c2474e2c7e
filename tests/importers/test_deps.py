"""Importing a package whose types come from other packages: named when missing, imported with --deps."""

from __future__ import annotations

from pathlib import Path

from ..conftest import run_main

XML = ('<?xml version="1.0"?>\n<package format="3"><name>{0}</name><version>0.1.0</version><description>d'
       '</description><maintainer email="a@b.c">a</maintainer><license>Apache-2.0</license></package>\n')


def _package(root: Path, name: str, **msgs: str) -> Path:
    folder = root / name
    (folder / "msg").mkdir(parents=True)
    (folder / "package.xml").write_text(XML.format(name))
    for stem, text in msgs.items():
        (folder / "msg" / f"{stem}.msg").write_text(text)
    return folder


def _workspace(tmp_path: Path) -> tuple[Path, Path]:
    top = _package(tmp_path / "src", "foo_msgs", Foo="bar_msgs/Thing thing\nbaz_msgs/Other other\nfloat64 x\n")
    deps = tmp_path / "deps"
    _package(deps / "nested", "bar_msgs", Thing="qux_msgs/Deep deep\n")
    _package(deps, "qux_msgs", Deep="string z\n")
    return top, deps


def test_each_missing_package_is_named_with_how_to_bring_it_in(tmp_path: Path) -> None:
    top, _ = _workspace(tmp_path)
    done = run_main("import", "--from", "ros2", str(top), "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    for name in ("bar_msgs", "baz_msgs"):
        assert f"from the package '{name}', which was not imported" in done.stderr
    assert "--deps DIR" in done.stderr


def test_deps_imports_what_is_used_each_into_its_own_file_with_includes(tmp_path: Path) -> None:
    top, deps = _workspace(tmp_path)
    out = tmp_path / "out"
    done = run_main("import", "--from", "ros2", str(top), "--deps", str(deps), "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in out.glob("*.iface")) == ["bar_msgs.iface", "foo_msgs.iface", "qux_msgs.iface"]
    foo = (out / "foo_msgs.iface").read_text()
    assert 'include "bar_msgs.iface"' in foo and "external baz_msgs" in foo  # baz_msgs is nowhere: still named
    assert 'include "qux_msgs.iface"' in (out / "bar_msgs.iface").read_text()  # and the dependency's own
    assert "from the package 'baz_msgs', which was not imported" in done.stderr
    checked = run_main("check", *(str(p) for p in sorted(out.glob("*.iface"))))
    assert checked.returncode == 0, checked.stdout


def test_deps_must_be_a_folder_and_ros2_only(tmp_path: Path) -> None:
    top, _ = _workspace(tmp_path)
    bad = run_main("import", "--from", "ros2", str(top), "--deps", str(tmp_path / "nope"), "--out", str(tmp_path / "o"))
    assert bad.returncode == 2 and "--deps needs a folder" in bad.stderr
    other = run_main("import", "--from", "px4", str(top), "--deps", str(tmp_path), "--out", str(tmp_path / "o"))
    assert other.returncode == 2 and "--from ros2 only" in other.stderr
