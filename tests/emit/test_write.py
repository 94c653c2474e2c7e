"""Writing generated files: the whole set is checked before anything is written; short temporary names."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from iface.emit import generate
from iface.emit.base import GeneratedFile
from iface.emit.write import atomic_write, path_problem, write_files
from tests.conftest import run_main

from .helpers import compile_text


def tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_a_name_too_long_for_the_file_system_writes_no_file_of_the_set(tmp_path: Path) -> None:
    files = [GeneratedFile("pkg/CMakeLists.txt", "a\n"), GeneratedFile(f"pkg/msg/{'A' * 300}.msg", "b\n"),
             GeneratedFile("pkg/package.xml", "c\n")]
    report = write_files(files, tmp_path / "out")
    assert report.written == []
    assert len(report.errors) == 1 and "304 bytes" in report.errors[0] and "255" in report.errors[0]
    assert not (tmp_path / "out").exists()


def test_names_are_measured_in_utf8_bytes(tmp_path: Path) -> None:
    # 128 two-byte characters: 128 characters but 256 bytes
    report = write_files([GeneratedFile("ok.txt", "x"), GeneratedFile("é" * 128, "y")], tmp_path)
    assert report.written == [] and "256 bytes" in report.errors[0]
    assert tree(tmp_path) == {}


def test_a_name_that_fits_is_written_whatever_the_temporary_name(tmp_path: Path) -> None:
    name = "A" * 249 + ".msg"  # 253 bytes: ".<name>.XXXXXXXX.tmp" would not fit, ".iface-XXXXXXXX.tmp" does
    report = write_files([GeneratedFile(f"pkg/{name}", "text\n")], tmp_path)
    assert report.errors == [] and report.written == [f"pkg/{name}"]
    assert (tmp_path / "pkg" / name).read_text() == "text\n"
    assert sorted(p.name for p in (tmp_path / "pkg").iterdir()) == [name]  # no temporary left behind


def test_atomic_write_uses_a_short_temporary_name_in_the_same_folder(tmp_path: Path,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    seen: list[tuple[str, str]] = []
    real = os.replace

    def spy(src: str, dst: str) -> None:
        seen.append((src, dst))
        real(src, dst)

    monkeypatch.setattr(os, "replace", spy)
    target = tmp_path / ("B" * 250)
    atomic_write(target, "x")
    (src, dst), = seen
    assert Path(src).parent == tmp_path and Path(dst) == target
    assert Path(src).name.startswith(".iface-") and Path(src).name.endswith(".tmp") and len(Path(src).name) < 40


def test_an_existing_file_where_a_folder_must_go_writes_nothing(tmp_path: Path) -> None:
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "msg").write_text("in the way")
    files = [GeneratedFile("pkg/CMakeLists.txt", "a\n"), GeneratedFile("pkg/msg/M.msg", "b\n")]
    report = write_files(files, tmp_path)
    assert report.written == [] and "is not a folder" in report.errors[0]
    assert tree(tmp_path) == {"pkg/msg": b"in the way"}


def test_a_folder_where_the_file_must_go_writes_nothing(tmp_path: Path) -> None:
    (tmp_path / "pkg" / "package.xml").mkdir(parents=True)
    report = write_files([GeneratedFile("pkg/a.txt", "a"), GeneratedFile("pkg/package.xml", "b")], tmp_path)
    assert report.written == [] and "package.xml" in report.errors[0]
    assert not (tmp_path / "pkg" / "a.txt").exists()


def test_one_generated_file_that_another_needs_as_a_folder_writes_nothing(tmp_path: Path) -> None:
    report = write_files([GeneratedFile("a", "x"), GeneratedFile("a/b", "y")], tmp_path)
    assert report.written == [] and "a is generated as a file" in report.errors[0]
    assert tree(tmp_path) == {}


def test_every_file_under_a_blocked_folder_is_named_and_the_others_are_not(tmp_path: Path) -> None:
    """Each folder is looked at once (plan): its verdict holds for each of its files, and only for them."""
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "msg").write_text("in the way")
    files = [GeneratedFile("pkg/msg/A.msg", "a"), GeneratedFile("pkg/CMakeLists.txt", "b"),
             GeneratedFile("pkg/msg/B.msg", "c"), GeneratedFile("pkg/msg/sub/C.msg", "d")]
    report = write_files(files, tmp_path)
    assert report.written == []
    assert [e.split(":")[0] for e in report.errors] == ["pkg/msg/A.msg", "pkg/msg/B.msg", "pkg/msg/sub/C.msg"]
    assert all("is not a folder" in e for e in report.errors)
    assert tree(tmp_path) == {"pkg/msg": b"in the way"}


def test_a_folder_linked_outside_refuses_each_of_its_files_and_writes_nothing(tmp_path: Path) -> None:
    out, outside = tmp_path / "out", tmp_path / "outside"
    (out / "pkg").mkdir(parents=True)
    outside.mkdir()
    (out / "pkg" / "msg").symlink_to(outside)
    files = [GeneratedFile("pkg/msg/A.msg", "a"), GeneratedFile("pkg/package.xml", "b"),
             GeneratedFile("pkg/msg/B.msg", "c")]
    report = write_files(files, out)
    assert report.written == [] and [e.split(":")[0] for e in report.errors] == ["pkg/msg/A.msg", "pkg/msg/B.msg"]
    assert all("leaves the output folder" in e for e in report.errors)
    assert tree(outside) == {} and not (out / "pkg" / "package.xml").exists()


@pytest.mark.parametrize("rel", ["", ".", "../x", "/abs/x", "a/../../x", "a\\b", "a\0b"])
def test_a_path_that_names_no_file_inside_the_output_folder_is_refused(tmp_path: Path, rel: str) -> None:
    report = write_files([GeneratedFile("ok.txt", "x"), GeneratedFile(rel, "y")], tmp_path / "out")
    assert report.written == [] and len(report.errors) == 1, report.errors
    assert "leaves the output folder" in report.errors[0]
    assert not (tmp_path / "out").exists() and not (tmp_path / "x").exists()


def test_an_output_folder_in_a_loop_of_links_refuses_every_file(tmp_path: Path) -> None:
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    report = write_files([GeneratedFile("x.txt", "x"), GeneratedFile("d/y.txt", "y")], tmp_path / "a" / "out")
    assert report.written == [] and len(report.errors) == 2
    assert all("leaves the output folder" in e for e in report.errors)


def test_a_path_longer_than_path_max_is_refused(tmp_path: Path) -> None:
    deep = "/".join(["d" * 200] * 25)  # 5024 bytes, every name short enough
    assert path_problem(tmp_path / deep / "f.txt") is not None
    report = write_files([GeneratedFile("ok.txt", "x"), GeneratedFile(f"{deep}/f.txt", "y")], tmp_path)
    assert report.written == [] and "bytes long" in report.errors[0]
    assert tree(tmp_path) == {}


def test_an_io_error_midway_stops_and_leaves_written_files_complete(tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    import iface.emit.write as write

    calls = {"n": 0}
    real = write.atomic_write

    def failing(path: Path, text: str) -> None:
        calls["n"] += 1
        if calls["n"] == 2:
            raise OSError(28, "No space left on device")
        real(path, text)

    monkeypatch.setattr(write, "atomic_write", failing)
    files = [GeneratedFile("a.txt", "a"), GeneratedFile("b.txt", "b"), GeneratedFile("c.txt", "c")]
    report = write_files(files, tmp_path)
    assert report.written == ["a.txt"]
    assert "No space left on device" in report.errors[0] and "stopped after 1 file" in report.errors[0]
    assert tree(tmp_path) == {"a.txt": b"a"}


def test_cli_writes_nothing_when_a_path_is_blocked(tmp_path: Path) -> None:
    src = tmp_path / "blocked.iface"
    src.write_text("component blocked\nmessage M { i32 x }\npublishes M on \"/m\"\n")
    out = tmp_path / "out"
    (out / "blocked").mkdir(parents=True)
    (out / "blocked" / "msg").write_text("a file where the msg folder goes\n")
    proc = run_main("generate", str(src), "-t", "ros2", "-o", str(out))
    assert proc.returncode == 2, proc.stderr
    assert "is not a folder" in proc.stderr and "nothing was written" in proc.stderr
    assert tree(out) == {"blocked/msg": b"a file where the msg folder goes\n"}


def test_an_over_long_generated_name_is_an_error_at_the_definition(tmp_path: Path) -> None:
    name = "A" * 300
    text = f"component c\n/** doc */\nmessage {name} {{ u64 timestamp, i32 x }}\npublishes {name} on \"/fmu/out/t\"\n"
    comp = compile_text(text, "c.iface", tmp_path)
    result = generate(comp, "px4")
    (d,) = [d for d in result.diagnostics if d.code == "output-name-too-long"]
    assert result.has_errors and result.files == []
    assert "304 bytes" in d.message
    assert comp.interface.source.text[:d.span.start].count("\n") == 2
    assert comp.interface.source.text[d.span.start:d.span.end] == name


@pytest.mark.parametrize("target", ["json", "markdown"])
def test_an_over_long_name_from_the_file_name_is_an_error(target: str, tmp_path: Path) -> None:
    comp = compile_text("message M { i32 x }\n", f"{'c' * 260}.iface", tmp_path)
    result = generate(comp, target)
    assert [d.code for d in result.diagnostics] == ["output-name-too-long"]
    assert result.files == []


def test_cli_over_long_message_name_is_a_located_error_and_writes_nothing(tmp_path: Path) -> None:
    name = "A" * 300
    src = tmp_path / "longname.iface"
    src.write_text(f"component c\nmessage {name} {{ i32 x }}\npublishes {name} on \"/t\"\n")
    out = tmp_path / "out"
    for target in ("ros2", "px4", "idl", "ardupilot"):
        proc = run_main("generate", str(src), "-t", target, "-o", str(out))
        assert proc.returncode == 1, (target, proc.stdout, proc.stderr)
        assert "longname.iface:2:9: error[" in proc.stdout, (target, proc.stdout)
        assert not out.exists()
