"""ROS 2 ``.idl`` interfaces (wchar, wstring, includes within and across packages) and keyword names,
imported and regenerated with the same meaning, judged by rosbags' IDL parser and RIHS01 hashes."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

from iface.importers.oracle import differences, idl_views, rihs01

from ..conftest import run_main
from .helpers import DATA

pytest.importorskip("rosbags")
pytest.importorskip("mcap_ros2")

IDL_DATA = DATA / "ros2_idl"
PACKAGES = sorted(p for p in IDL_DATA.iterdir() if (p / "package.xml").is_file())
ROOT = Path(__file__).resolve().parents[2]


def _files(*packages: Path) -> list[Path]:
    return sorted(p for pkg in packages for p in pkg.rglob("*") if p.suffix in (".msg", ".srv", ".action", ".idl"))


def test_idl_only_and_keyword_packages_come_back_identical() -> None:
    done = run_main("roundtrip", "-v", "--from", "ros2", *(str(p) for p in PACKAGES))
    files = _files(*PACKAGES)
    assert sum(f.suffix == ".idl" for f in files) == 7
    assert done.stdout.splitlines()[-1] == f"{len(files)} of {len(files)} identical", done.stdout + done.stderr
    assert done.returncode == 0
    for f in files:
        assert f"{f}: identical" in done.stdout


def test_includes_become_includes_between_the_imported_files(tmp_path: Path) -> None:
    done = run_main("import", "--from", "ros2", *(str(p) for p in PACKAGES), "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    wide = (tmp_path / "wide_msgs.iface").read_text()
    user = (tmp_path / "user_msgs.iface").read_text()
    assert "message Holder {\n    Base base,\n    Base[2] pair,\n    Base[<=5] some,\n    wchar tag\n}" in wide
    assert "service Ask {" in wide and "wchar question" in wide and "action Spell {" in wide
    assert 'include "wide_msgs.iface"' in user and "wide_msgs.Wide wide" in user
    assert "const wchar INITIAL = 90" in user
    check = run_main("check", *(str(p) for p in sorted(tmp_path.glob("*.iface"))))
    assert check.returncode == 0, check.stdout


def test_a_type_from_a_package_not_given_is_named_with_how_to_bring_it_in(tmp_path: Path) -> None:
    done = run_main("import", "--from", "ros2", str(IDL_DATA / "user_msgs"), "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    assert "from the package 'wide_msgs', which was not imported" in done.stderr and "--deps DIR" in done.stderr
    deps = run_main("import", "--from", "ros2", str(IDL_DATA / "user_msgs"), "--deps", str(IDL_DATA),
                   "--out", str(tmp_path / "with_deps"))
    assert deps.returncode == 0, deps.stderr
    assert sorted(p.name for p in (tmp_path / "with_deps").glob("*.iface")) == ["user_msgs.iface", "wide_msgs.iface"]


def test_the_ros2_target_writes_idl_where_msg_has_no_such_type(tmp_path: Path) -> None:
    run_main("import", "-q", "--from", "ros2", str(IDL_DATA / "wide_msgs"), "--out", str(tmp_path / "i"))
    done = run_main("generate", str(tmp_path / "i" / "wide_msgs.iface"), "--target", "ros2", "-o", str(tmp_path / "g"))
    assert done.returncode == 0, done.stderr
    pkg = tmp_path / "g" / "wide_msgs"
    written = sorted(str(p.relative_to(pkg)) for p in pkg.rglob("*") if p.is_file())
    # Base has a wstring but no wchar: .msg states it; a wchar needs .idl
    assert written == ["CMakeLists.txt", "action/Spell.idl", "msg/Base.msg", "msg/Defaults.idl", "msg/Holder.idl",
                       "msg/Plain.msg", "msg/Wide.idl", "package.xml", "srv/Ask.idl"]
    cmake = (pkg / "CMakeLists.txt").read_text()
    assert all(f'"{name}"' in cmake for name in ("msg/Base.msg", "msg/Holder.idl", "msg/Wide.idl", "srv/Ask.idl"))
    assert '#include "wide_msgs/msg/Base.idl"' in (pkg / "msg" / "Holder.idl").read_text()


def test_a_changed_bound_or_type_is_a_difference() -> None:
    text = (IDL_DATA / "wide_msgs" / "msg" / "Wide.idl").read_text()
    a = idl_views(text)["Wide"]
    for old, new in (("wstring<5> short_text", "wstring<6> short_text"), ("wchar letter", "char letter"),
                     ("sequence<wstring<7>> many", "sequence<wstring<7>, 2> many"),
                     ("const wchar LETTER = 65", "const wchar LETTER = 66")):
        assert old in text
        b = idl_views(text.replace(old, new))["Wide"]
        assert differences(a, b), new
    with_defaults = (IDL_DATA / "wide_msgs" / "msg" / "Defaults.idl").read_text()
    d = idl_views(with_defaults)["Defaults"]
    for old, new in (("value=5)", "value=6)"), ('"(1, 2, 3)"', '"(1, 2, 4)"'), ("then go", "then stop"),
                     ("value=TRUE", "value=FALSE")):
        assert old in with_defaults
        assert differences(d, idl_views(with_defaults.replace(old, new))["Defaults"]), new
    changed = idl_views(text.replace("wstring<5> short_text", "wstring<6> short_text"))["Wide"]
    name = a.parts[0].name
    assert rihs01(name, {name: a.parts[0].descs}) != rihs01(name, {name: changed.parts[0].descs})


def _corpus() -> Path | None:
    for p in (os.environ.get("IFACE_CORPUS"), ROOT.parent / "shared" / "corpus"):
        if p and (Path(p) / "ros2").is_dir():
            return Path(p)
    return None


def test_every_corpus_package_round_trips_idl_included() -> None:
    corpus = _corpus()
    if corpus is None:
        pytest.skip("the shared corpus (../shared/corpus or IFACE_CORPUS) is not here")
    packages = sorted(p.parent for p in (corpus / "ros2").rglob("package.xml")
                      if any((p.parent / k).is_dir() for k in ("msg", "srv", "action", "idl")))
    files = _files(*packages)
    done = run_main("roundtrip", "--from", "ros2", *(str(p) for p in packages))
    assert any(f.suffix == ".idl" for f in files)
    assert done.stdout.splitlines()[-1] == f"{len(files)} of {len(files)} identical", done.stdout + done.stderr
    assert done.returncode == 0


_ROSIDL_READ = r"""
import json, sys
from rosidl_parser.parser import parse_idl_string
from rosidl_parser.definition import Action, Message, Service
out = {}
for path in sys.argv[1:]:
    content = parse_idl_string(open(path).read())
    structs = [m.structure for m in content.get_elements_of_type(Message)]
    for s in content.get_elements_of_type(Service):
        structs += [s.request_message.structure, s.response_message.structure]
    for a in content.get_elements_of_type(Action):
        structs += [a.goal.structure, a.result.structure, a.feedback.structure]
    for s in structs:
        out[s.namespaced_type.name] = [[m.name, type(m.type).__name__,
                                        m.get_annotation_value("default")["value"]
                                        if m.has_annotation("default") else None] for m in s.members]
print(json.dumps(out))
"""


def test_the_generated_idl_files_parse_with_rosidl_parser(tmp_path: Path) -> None:
    """ROS 2's own IDL parser (rosidl_parser, in the ROS 2 runtime venv) reads every .idl the ros2 target wrote."""
    from ..ros_harness.ros import DEFAULT_VENV

    venv = Path(os.environ.get("IFACE_ROS2_VENV", DEFAULT_VENV))
    python = venv / "bin" / "python"
    if not python.is_file() or subprocess.run([str(python), "-c", "import rosidl_parser.parser"],
                                              capture_output=True).returncode:
        pytest.skip(f"no ROS 2 runtime with rosidl_parser at {venv} (set IFACE_ROS2_VENV)")
    run_main("import", "-q", "--from", "ros2", *(str(p) for p in PACKAGES), "--out", str(tmp_path / "i"))
    for iface in sorted((tmp_path / "i").glob("*.iface")):
        done = run_main("generate", str(iface), "--target", "ros2", "-o", str(tmp_path / "g"))
        assert done.returncode == 0, done.stderr
    idl = sorted((tmp_path / "g").rglob("*.idl"))
    assert len(idl) == 6
    structs = _rosidl_read(python, idl)
    assert sorted(structs) == ["Ask_Request", "Ask_Response", "Defaults", "Holder", "Spell_Feedback", "Spell_Goal",
                               "Spell_Result", "User", "Wide"]
    assert structs["Spell_Feedback"][0] == ["progress", "BasicType", 0.5]
    assert [m[0] for m in structs["Wide"]] == ["letter", "text", "short_text", "three", "some", "many", "few",
                                               "pair", "letters", "two_short"]
    assert structs["Holder"][3][:2] == ["tag", "BasicType"] and structs["Wide"][1][:2] == ["text", "UnboundedWString"]
    # the defaults, read by rosidl_parser from the original and from what iface wrote back
    original = _rosidl_read(python, [IDL_DATA / "wide_msgs" / "msg" / "Defaults.idl"])["Defaults"]
    assert original[3] == ["text", "UnboundedString", 'say "hi"; then go']
    assert structs["Defaults"] == original


def _rosidl_read(python: Path, paths: list[Path]) -> dict[str, list[list[object]]]:
    read = subprocess.run([str(python), "-c", _ROSIDL_READ, *map(str, paths)], capture_output=True, text=True,
                          timeout=120)
    assert read.returncode == 0, read.stderr
    return json.loads(read.stdout)


def test_the_regenerated_idl_packages_build_with_rosidl(tmp_path: Path) -> None:
    """ROS 2's own generators build what the ros2 target wrote (.idl with wchar, includes across packages,
    a service and an action in IDL) in C and C++ and run a program per type: ../shared/ros2-build with Debian's
    rosidl."""
    from ..ros_harness.ros import shared_dir
    from ..ros_harness.workspaces import debian_build

    shared = shared_dir()
    if shared is None or not (shared / "ros2-build" / "build.sh").is_file():
        pytest.skip("no ../shared/ros2-build (set IFACE_ROS2_SHARED): Debian's rosidl build is not available")
    packages = [IDL_DATA / "wide_msgs", IDL_DATA / "user_msgs"]
    run_main("import", "-q", "--from", "ros2", *(str(p) for p in packages), "--out", str(tmp_path / "i"))
    for iface in sorted((tmp_path / "i").glob("*.iface")):
        done = run_main("generate", str(iface), "--target", "ros2", "-o", str(tmp_path / "gen"))
        assert done.returncode == 0, done.stderr
    assert len(list((tmp_path / "gen").rglob("*.idl"))) == 6
    done = debian_build(tmp_path / "gen")  # or its outcome from the test cache: the same files, script and rosidl
    last = done.stdout.strip().splitlines()[-1] if done.stdout.strip() else done.stderr
    if done.returncode == 2:
        pytest.skip(f"Debian's rosidl is not installed ({last}): apt-get install ../shared/ros2-build/apt-packages.txt")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert "ros2-build: OK:" in last and "(2 generated)" in last, last


def test_what_iface_cannot_hold_is_reported_at_its_line(tmp_path: Path) -> None:
    folder = tmp_path / "b_msgs" / "msg"
    folder.mkdir(parents=True)
    (folder / "S.idl").write_text('module b_msgs {\n  module msg {\n    module S_Constants {\n'
                                  "      const long double K = 1.0;\n    };\n    struct S {\n"
                                  "      @default (value=FOO)\n      int32 i;\n      @default (value=\"x\")\n"
                                  "      int32 j;\n      long double q;\n    };\n  };\n};\n")
    (folder / "Good.idl").write_text("module b_msgs { module msg { struct Good { int32 x; }; }; };\n")
    done = run_main("import", "--from", "ros2", str(tmp_path / "b_msgs"), "--out", str(tmp_path / "out"))
    assert done.returncode == 1
    path = folder / "S.idl"
    assert done.stderr.splitlines() == [
        f"{path}:4: S.K: the IDL type 'float128' has no iface equivalent",
        f"{path}:8: S.i: the @default value 'FOO' is not a value of type int32",
        f"{path}:10: S.j: the @default value 'x' is not a value of type int32",
        f"{path}:11: S.q: the IDL type 'float128' has no iface equivalent"]
    assert "message Good" in (tmp_path / "out" / "b_msgs.iface").read_text()
    rt = run_main("roundtrip", "--from", "ros2", str(tmp_path / "b_msgs"))
    assert rt.returncode == 1 and rt.stdout.splitlines()[-1] == "1 of 2 identical"
